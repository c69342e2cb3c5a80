#pragma once
// Body of voxelize.hpp: the grid builder, the checks, and the row sweep (see the rule there).

#include <geovoronoi/detail/voxelize/checks.hpp>
#include <geovoronoi/detail/voxelize/common.hpp>
#include <geovoronoi/detail/voxelize/grid.hpp>
#include <geovoronoi/detail/voxelize/winding.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace geovoronoi {

namespace detail::vox {

/// A part ready for the sweep: snapped, checked, its triangles bucketed by z slice.
struct prepared_part {
  snapped_part sp;
  std::vector<std::size_t> slice_start;      ///< CSR over z slices into slice_tris
  std::vector<std::uint32_t> slice_tris;     ///< indices into sp.tris
  std::unique_ptr<winding_tree> tree;        ///< winding rule on a soup whose edges are not paired
  bool nonzero = true;                       ///< inside when the crossing count is != 0 (else >= 1)
  double value = 1.0;
};

/// Triangles whose lattice z range can meet the closed band [k - 1/2, k + 1/2] of slice k.
inline void bucket_slices(prepared_part& p, index_t nz) {
  const auto& T = p.sp.tris;
  auto range = [&](const lattice_triangle& t, index_t& a, index_t& b) {
    a = std::max<index_t>(0, lattice_floor(t.lo[2] - half));
    b = std::min<index_t>(nz - 1, lattice_ceil(t.hi[2] + half));
    return a <= b;
  };
  p.slice_start.assign(static_cast<std::size_t>(nz) + 1, 0);
  for (const auto& t : T) {
    index_t a, b;
    if (range(t, a, b))
      for (index_t k = a; k <= b; ++k) ++p.slice_start[static_cast<std::size_t>(k) + 1];
  }
  for (std::size_t k = 0; k < static_cast<std::size_t>(nz); ++k) p.slice_start[k + 1] += p.slice_start[k];
  p.slice_tris.resize(p.slice_start.back());
  std::vector<std::size_t> fill(p.slice_start.begin(), p.slice_start.end() - 1);
  for (std::uint32_t i = 0; i < T.size(); ++i) {
    index_t a, b;
    if (range(T[i], a, b))
      for (index_t k = a; k <= b; ++k) p.slice_tris[fill[static_cast<std::size_t>(k)]++] = i;
  }
}

/// What one worker thread keeps between slices.
struct worker_state {
  std::vector<std::vector<crossing>> rows;
  std::vector<std::vector<std::vector<crossing>>> part_rows;  // fraction pass: per part
  std::vector<int> diff, cnt;
  std::vector<unsigned char> inside, any;
  std::vector<std::uint32_t> count;
  std::size_t crossings = 0;
  index_t conflict = -1;  // overlap_rule::error: smallest shared voxel seen, and its two parts
  std::size_t conflict_a = 0, conflict_b = 0;
};

/// Collects the crossings of part @p p's triangles of slice @p k with the rows at height @p z and
/// y = j * one + oy[t] into rows[t * ny + j].
inline std::size_t gather(const prepared_part& p, index_t k, std::int64_t z, const std::vector<std::int64_t>& oy,
                          index_t ny, std::vector<std::vector<crossing>>& rows) {
  rows.resize(oy.size() * static_cast<std::size_t>(ny));
  for (auto& r : rows) r.clear();
  std::size_t found = 0;
  const auto& T = p.sp.tris;
  for (std::size_t q = p.slice_start[static_cast<std::size_t>(k)]; q < p.slice_start[static_cast<std::size_t>(k) + 1]; ++q) {
    const lattice_triangle& t = T[p.slice_tris[q]];
    if (t.n[0] == 0 || z < t.lo[2] || z > t.hi[2]) continue;
    for (std::size_t s = 0; s < oy.size(); ++s) {
      const index_t j0 = std::max<index_t>(0, lattice_ceil(t.lo[1] - oy[s]));
      const index_t j1 = std::min<index_t>(ny - 1, lattice_floor(t.hi[1] - oy[s]));
      for (index_t j = j0; j <= j1; ++j) {
        crossing c;
        if (row_crossing(t, j * one + oy[s], z, c)) {
          rows[s * static_cast<std::size_t>(ny) + static_cast<std::size_t>(j)].push_back(c);
          ++found;
        }
      }
    }
  }
  return found;
}

/// The crossings of a part evaluated by its winding tree: none.
inline const std::vector<crossing>& no_crossings() {
  static const std::vector<crossing> none;
  return none;
}

/// Sets in[i] (or ORs into it) the inside-ness of samples (i * one + ox, y, z), i in [0, nx), of
/// part @p p, given its crossings on that row.
inline void row_inside(const prepared_part& p, const std::vector<crossing>& cs, index_t nx, std::int64_t ox,
                       std::int64_t y, std::int64_t z, worker_state& w, unsigned char* in) {
  if (p.tree) {
    for (index_t i = 0; i < nx; ++i)
      if (p.tree->at({i * one + ox, y, z}) >= 0.5) in[i] = 1;
    return;
  }
  if (cs.empty()) return;
  w.cnt.resize(static_cast<std::size_t>(nx));
  sweep(cs, nx, ox, w.diff, w.cnt.data());
  for (index_t i = 0; i < nx; ++i)
    if (p.nonzero ? w.cnt[i] != 0 : w.cnt[i] >= 1) in[i] = 1;
}

/// Marks in[j * nx + i] for the voxels of slice @p k whose closed cube part @p p's surface meets.
inline void mark_surface(const prepared_part& p, index_t k, index_t nx, index_t ny, unsigned char* in) {
  const std::int64_t z = k * one;
  const auto& T = p.sp.tris;
  for (std::size_t q = p.slice_start[static_cast<std::size_t>(k)]; q < p.slice_start[static_cast<std::size_t>(k) + 1]; ++q) {
    const lattice_triangle& t = T[p.slice_tris[q]];
    if (t.hi[2] < z - half || t.lo[2] > z + half) continue;
    const index_t j0 = std::max<index_t>(0, lattice_ceil(t.lo[1] - half)), j1 = std::min<index_t>(ny - 1, lattice_floor(t.hi[1] + half));
    const index_t i0 = std::max<index_t>(0, lattice_ceil(t.lo[0] - half)), i1 = std::min<index_t>(nx - 1, lattice_floor(t.hi[0] + half));
    for (index_t j = j0; j <= j1; ++j)
      for (index_t i = i0; i <= i1; ++i) {
        unsigned char& c = in[j * nx + i];
        if (!c && triangle_meets_cube(t, {i * one, j * one, z})) c = 1;
      }
  }
}

/// Sample offsets of k samples per voxel along an axis: the centres of k equal sub-intervals,
/// rounded to the lattice.
inline std::vector<std::int64_t> sample_offsets(int k) {
  std::vector<std::int64_t> o(static_cast<std::size_t>(k));
  for (int s = 0; s < k; ++s) o[std::size_t(s)] = std::llround(double(2 * s + 1 - k) * double(one) / double(2 * k));
  return o;
}

}  // namespace detail::vox

template <class T>
voxelization<T> voxelize(const std::vector<voxelize_part>& parts, const grid<3>& g, const voxelize_options& o) {
  using namespace detail::vox;
  const std::string who = "geovoronoi::voxelize";
  if (parts.empty()) throw std::invalid_argument(who + ": no parts given");
  if (o.fraction_samples < 0 || o.fraction_samples > 16)
    throw std::invalid_argument(who + ": fraction_samples is " + std::to_string(o.fraction_samples) +
                                "; it must lie in [0, 16] (0: no fraction image)");
  if (g.size() == 0) throw std::invalid_argument(who + ": the grid is empty");
  for (int a = 0; a < 3; ++a)
    if (double(g.extent(a)) > detail::lattice_range)
      throw std::invalid_argument(who + ": the grid has " + std::to_string(g.extent(a)) + " voxels along axis " +
                                  std::to_string(a) + "; voxelize supports at most 2^24");
  const index_t nx = g.extent(0), ny = g.extent(1), nz = g.extent(2);
  voxelization<T> out;
  voxelize_stats& st = out.stats;

  std::vector<prepared_part> pp(parts.size());
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const std::string name = who + ": " + part_text(parts[i].name, i);
    if (!std::isfinite(parts[i].value))
      throw std::invalid_argument(name + ": value " + detail::shortest_text(parts[i].value) + " is not finite");
    prepared_part& p = pp[i];
    p.value = parts[i].value;
    p.sp = snap_part(g, parts[i].mesh, name);
    const std::string edges = edge_problem(parts[i].mesh, p.sp);
    p.sp.paired = edges.empty();
    if (o.rule == inside_rule::closed) {
      if (!edges.empty())
        throw std::invalid_argument(name + ": " + edges +
                                    "; inside_rule::closed needs a closed, consistently oriented surface "
                                    "(inside_rule::winding accepts any triangle soup)");
      if (p.sp.volume < 0)
        throw std::invalid_argument(name + " encloses a negative volume (" + detail::shortest_text(p.sp.volume) +
                                    "): its triangles face inward (the mesh is inside out); reverse them, "
                                    "e.g. swap two vertices of every triangle");
      const std::string cross = self_intersection(p.sp);
      if (!cross.empty())
        throw std::invalid_argument(name + ": " + cross +
                                    "; inside_rule::closed needs a surface without self-intersections "
                                    "(inside_rule::winding accepts them)");
      p.nonzero = true;
    } else {
      p.nonzero = false;
      if (!p.sp.paired) p.tree = std::make_unique<winding_tree>(p.sp.tris);
    }
    bucket_slices(p, nz);
    st.triangles += p.sp.tris.size();
    st.degenerate += p.sp.degenerate;
    st.mesh_volume += p.sp.volume;
  }

  // owner of each voxel (part index + 1, 0 for none), kept in the label image until the end
  out.label = image<label_t, 3>(g, 0);
  label_t* own = out.label.data();
  const unsigned workers = worker_count(nz, o.threads);
  std::vector<worker_state> ws(workers);
  const std::vector<std::int64_t> centre{0};
  const std::size_t slice = static_cast<std::size_t>(nx * ny);

  parallel_for(nz, o.threads, [&](unsigned wi, index_t k) {
    worker_state& w = ws[wi];
    w.inside.resize(slice);
    label_t* os = own + k * nx * ny;
    for (std::size_t pi = 0; pi < pp.size(); ++pi) {
      const prepared_part& p = pp[pi];
      std::fill(w.inside.begin(), w.inside.end(), 0);
      if (!p.tree) w.crossings += gather(p, k, k * one, centre, ny, w.rows);
      for (index_t j = 0; j < ny; ++j)
        row_inside(p, p.tree ? no_crossings() : w.rows[static_cast<std::size_t>(j)], nx, 0, j * one, k * one, w,
                   w.inside.data() + j * nx);
      if (o.surface_inside) mark_surface(p, k, nx, ny, w.inside.data());
      const label_t me = static_cast<label_t>(pi + 1);
      for (std::size_t v = 0; v < slice; ++v) {
        if (!w.inside[v]) continue;
        label_t& c = os[v];
        if (c == 0) {
          c = me;
          continue;
        }
        switch (o.overlap) {
          case overlap_rule::last_wins: c = me; break;
          case overlap_rule::first_wins: break;
          case overlap_rule::max_value:
            if (p.value >= pp[std::size_t(c - 1)].value) c = me;
            break;
          case overlap_rule::min_value:
            if (p.value <= pp[std::size_t(c - 1)].value) c = me;
            break;
          case overlap_rule::error: {
            const index_t at = k * nx * ny + static_cast<index_t>(v);
            if (w.conflict < 0 || at < w.conflict) {
              w.conflict = at;
              w.conflict_a = std::size_t(c - 1);
              w.conflict_b = pi;
            }
            break;
          }
        }
      }
    }
  });
  const worker_state* first = nullptr;
  for (const auto& w : ws) {
    st.crossings += w.crossings;
    if (w.conflict >= 0 && (!first || w.conflict < first->conflict)) first = &w;
  }
  if (first) {
    const coord<3> c = g.coords(first->conflict);
    throw std::invalid_argument(who + ": " + part_text(parts[first->conflict_a].name, first->conflict_a) + " and " +
                                part_text(parts[first->conflict_b].name, first->conflict_b) + " overlap, e.g. at voxel (" +
                                std::to_string(c[0]) + ", " + std::to_string(c[1]) + ", " + std::to_string(c[2]) +
                                ") (overlap_rule::error)");
  }

  out.stiffness = image<T, 3>(g);
  std::vector<T> values(pp.size());
  std::vector<label_t> labels(pp.size());
  for (std::size_t i = 0; i < pp.size(); ++i) {
    values[i] = static_cast<T>(parts[i].value);
    labels[i] = parts[i].label != 0 ? parts[i].label : static_cast<label_t>(i + 1);
  }
  const T outside = static_cast<T>(o.outside_value);
  std::vector<std::size_t> inside_count(workers, 0);
  parallel_for(nz, o.threads, [&](unsigned wi, index_t k) {
    T* s = out.stiffness.data() + k * nx * ny;
    label_t* l = own + k * nx * ny;
    std::size_t n = 0;
    for (std::size_t v = 0; v < slice; ++v) {
      const label_t c = l[v];
      if (c == 0) {
        s[v] = outside;
      } else {
        s[v] = values[std::size_t(c - 1)];
        l[v] = labels[std::size_t(c - 1)];
        ++n;
      }
    }
    inside_count[wi] += n;
  });
  for (auto n : inside_count) st.inside_voxels += n;

  if (o.fraction_samples > 0) {
    const int kk = o.fraction_samples;
    const auto off = sample_offsets(kk);
    const float scale = 1.0f / float(kk * kk * kk);
    out.fraction = image<float, 3>(g, 0.0f);
    parallel_for(nz, o.threads, [&](unsigned wi, index_t k) {
      worker_state& w = ws[wi];
      w.count.assign(slice, 0);
      w.any.resize(static_cast<std::size_t>(nx));
      w.part_rows.resize(pp.size());
      for (int u = 0; u < kk; ++u) {
        const std::int64_t z = k * one + off[std::size_t(u)];
        for (std::size_t pi = 0; pi < pp.size(); ++pi)
          if (!pp[pi].tree) gather(pp[pi], k, z, off, ny, w.part_rows[pi]);
        for (int t = 0; t < kk; ++t)
          for (index_t j = 0; j < ny; ++j) {
            const std::int64_t y = j * one + off[std::size_t(t)];
            for (int s = 0; s < kk; ++s) {
              std::fill(w.any.begin(), w.any.end(), 0);
              for (std::size_t pi = 0; pi < pp.size(); ++pi) {
                const auto& cs = pp[pi].tree ? no_crossings() : w.part_rows[pi][std::size_t(t) * std::size_t(ny) + std::size_t(j)];
                row_inside(pp[pi], cs, nx, off[std::size_t(s)], y, z, w, w.any.data());
              }
              std::uint32_t* c = w.count.data() + j * nx;
              for (index_t i = 0; i < nx; ++i) c[i] += w.any[static_cast<std::size_t>(i)];
            }
          }
      }
      float* f = out.fraction.data() + k * nx * ny;
      for (std::size_t v = 0; v < slice; ++v) f[v] = float(w.count[v]) * scale;
    });
  }
  return out;
}

template <class T>
voxelization<T> voxelize(const std::vector<voxelize_part>& parts, const voxelize_options& options) {
  return voxelize<T>(parts, voxelize_grid(parts, options), options);
}

}  // namespace geovoronoi
