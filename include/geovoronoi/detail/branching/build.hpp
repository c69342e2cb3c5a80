#pragma once
// Construction of a branching grid (branching_grid.hpp): per coarse cell, the connected components of
// its fine material (copies, numbered by cell, then by their lowest fine voxel); per copy, its
// stiffness (a reduction of its fine values in fine-index order) and its links to the copies of
// neighbouring cells whose fine material touches its own across the cells' border.

#include <geovoronoi/connectivity.hpp>
#include <geovoronoi/cut.hpp>
#include <geovoronoi/detail/search/topology.hpp>
#include <geovoronoi/grid.hpp>
#include <geovoronoi/image.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace geovoronoi {

/// How a copy's stiffness is reduced from the values of its fine voxels (branching_options).
enum class stiffness_reduction {
  mean,          ///< T(sum / n): sum of the values in double, in fine-index order (the default)
  min,           ///< the smallest value (exact)
  max,           ///< the largest value (exact)
  harmonic_mean  ///< T(n / sum of 1 / value), each term and the sum in double, in fine-index order;
                 ///< a copy of one voxel keeps that voxel's value exactly
};

namespace detail::branching {

/// The arrays of a branching grid, as the builder fills them.
template <int Dim, class T>
struct parts {
  grid<Dim> fine;
  grid<Dim> coarse;
  int factor = 1;
  std::vector<index_t> cell_begin;   // cells + 1
  std::vector<index_t> copy_cell;    // copies
  std::vector<index_t> copy_voxel;   // copies: the lowest fine voxel
  std::vector<index_t> voxel_count;  // copies
  std::vector<T> stiffness;          // copies
  std::vector<index_t> link_begin;   // copies + 1
  std::vector<index_t> link_copy;
  std::vector<std::uint8_t> link_dir;
  image<index_t, Dim> fine_copy;
  // The graph as the searches walk it (search::link_walker), over slots: slot c is the first copy of
  // cell c (a cell's only copy, most often), the other copies of a cell get slots after the cells.
  // A link to the only copy of neighbour cell k is bit k of the mask, its slot the cell's index,
  // found like a grid's neighbour; the links to cells of several copies are rows of walk_extra.
  // Slots of empty cells have stiffness NaN (outside every domain rule) and no links.
  std::vector<index_t> slot_of_copy;     // copies
  std::vector<index_t> copy_of_slot;     // slots, -1 for empty cells
  std::vector<T> slot_stiffness;         // slots
  std::vector<search::copy_walk> walk;   // slots
  std::vector<std::uint32_t> walk_bits;  // slots: the mask, | search::copy_walk::row_bit when the walk needs the row
  std::vector<index_t> walk_extra_node;  // slots
  std::vector<std::uint8_t> walk_extra_dir;
};

/// The coarse grid of @p fine for @p factor: extents rounded up (the last cells padded with empty
/// material), spacing times the factor, the same direction, and an origin at the centre of cell 0's
/// factor^Dim fine voxels, origin + D ((factor - 1) / 2 * spacing) (zero entries of D skipped as in
/// grid::world, so factor 1 gives the fine origin exactly).
template <int Dim>
grid<Dim> coarse_grid(const grid<Dim>& fine, int factor) {
  coord<Dim> ext{};
  point<Dim> sp{}, org{};
  const double half = double(factor - 1) / 2.0;
  for (int a = 0; a < Dim; ++a) {
    ext[a] = (fine.extent(a) + factor - 1) / factor;
    sp[a] = fine.spacing(a) * double(factor);
  }
  for (int r = 0; r < Dim; ++r) {
    double sum = 0.0;
    for (int a = 0; a < Dim; ++a)
      if (fine.direction(r, a) != 0.0) sum += fine.direction(r, a) * (half * fine.spacing(a));
    org[r] = fine.origin()[r] + sum;
  }
  try {
    return grid<Dim>(ext, sp, org, fine.direction());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("geovoronoi::make_branching_grid: the coarse grid of factor ") +
                                std::to_string(factor) + " is not a valid grid: " + e.what());
  }
}

/// Index of offset (dx, dy, dz) in connectivity<N>'s table, -1 when it is not one of its offsets.
template <int N>
std::array<int, 27> offset_table() {
  std::array<int, 27> t{};
  t.fill(-1);
  constexpr auto offs = connectivity<N>::offsets();
  for (int k = 0; k < N; ++k) {
    int code = 0, mul = 1;
    for (int a = 0; a < connectivity<N>::dim; ++a, mul *= 3) code += (offs[k][a] + 1) * mul;
    t[std::size_t(code)] = k;
  }
  return t;
}

/// The cut fine edges of @p cut as a mask per fine voxel (bit k: the edge in direction k of
/// connectivity<N>, both orientations set), for the builder's walks; empty when @p cut is null.
template <int Dim, int N>
std::vector<std::uint32_t> fine_cut_masks(const grid<Dim>& g, const cut_set<Dim>* cut) {
  std::vector<std::uint32_t> m;
  if (!cut) return m;
  if (!(cut->geometry() == g) || cut->directions() != N)
    throw std::invalid_argument("geovoronoi::make_branching_grid: the cut belongs to another grid or connectivity "
                                "than the fine image and the grid's connectivity<" + std::to_string(N) + ">");
  m.assign(std::size_t(g.size()), 0u);
  constexpr auto offs = connectivity<N>::offsets();
  cut->for_each_edge([&](index_t u, int d) {
    const index_t v = cut->neighbour(u, d);
    int back = -1;
    for (int k = 0; k < N; ++k) {
      bool opposite = true;
      for (int a = 0; a < Dim; ++a) opposite = opposite && offs[k][a] == -offs[d][a];
      if (opposite) back = k;
    }
    m[std::size_t(u)] |= std::uint32_t(1) << d;
    if (v >= 0) m[std::size_t(v)] |= std::uint32_t(1) << back;
  });
  return m;
}

template <int Dim, class T, int N>
parts<Dim, T> build(const image_view<const T, Dim>& field, int factor, stiffness_reduction reduction,
                    const cut_set<Dim>* cut = nullptr) {
  static_assert(connectivity<N>::dim == Dim, "make_branching_grid: the connectivity does not match the grid");
  const char* who = "geovoronoi::make_branching_grid: ";
  if (factor < 1)
    throw std::invalid_argument(std::string(who) + "the factor is " + std::to_string(factor) +
                                "; it must be >= 1 (1 gives the fine grid itself)");
  if (reduction != stiffness_reduction::mean && reduction != stiffness_reduction::min &&
      reduction != stiffness_reduction::max && reduction != stiffness_reduction::harmonic_mean)
    throw std::invalid_argument(std::string(who) + "unknown stiffness reduction " + std::to_string(int(reduction)));
  const grid<Dim>& g = field.geometry();
  if (g.size() == 0) throw std::invalid_argument(std::string(who) + "the fine image is empty");
  const T* f = field.data();
  auto material = [f](index_t v) { return f[v] > T(0); };

  parts<Dim, T> out;
  out.fine = g;
  out.factor = factor;
  out.coarse = coarse_grid(g, factor);
  out.fine_copy = image<index_t, Dim>(g, index_t(-1));
  // a cut fine edge joins neither two voxels of a copy nor two linked copies
  const std::vector<std::uint32_t> cut_mask = fine_cut_masks<Dim, N>(g, cut);
  const std::uint32_t* cm = cut_mask.empty() ? nullptr : cut_mask.data();
  index_t* fc = out.fine_copy.data();
  index_t material_count = 0;
  for (index_t v = 0; v < g.size(); ++v) material_count += material(v) ? 1 : 0;
  if (material_count == 0)
    throw std::invalid_argument(std::string(who) +
                                "the fine image has no material (no voxel with a value > 0): there is nothing to coarsen");

  // fine extents and strides, 3D-shaped (z extent 1 in 2D)
  const index_t nx = g.extent(0), ny = g.extent(1), nz = Dim == 3 ? g.extent(Dim - 1) : 1;
  const index_t nxy = nx * ny;
  const index_t cx = out.coarse.extent(0), cy = out.coarse.extent(1), cz = Dim == 3 ? out.coarse.extent(Dim - 1) : 1;
  const index_t cells = out.coarse.size();
  const stencil<T, Dim, N> fine_st(g);
  const auto coarse_dir = offset_table<N>();
  auto block = [&](index_t c, index_t lo[3], index_t hi[3]) {
    const index_t ci[3] = {c % cx, (c / cx) % cy, c / (cx * cy)};
    const index_t n3[3] = {nx, ny, nz};
    for (int a = 0; a < 3; ++a) {
      lo[a] = ci[a] * factor;
      hi[a] = std::min(n3[a], lo[a] + factor);
    }
  };
  (void)cz;

  // 1. copies: flood fill of each cell's material, components numbered by their lowest fine voxel
  out.cell_begin.assign(std::size_t(cells) + 1, 0);
  std::vector<index_t> queue;
  index_t next = 0;
  for (index_t c = 0; c < cells; ++c) {
    out.cell_begin[std::size_t(c)] = next;
    index_t lo[3], hi[3];
    block(c, lo, hi);
    for (index_t z = lo[2]; z < hi[2]; ++z)
      for (index_t y = lo[1]; y < hi[1]; ++y)
        for (index_t x = lo[0]; x < hi[0]; ++x) {
          const index_t s = x + nx * y + nxy * z;
          if (!material(s) || fc[s] >= 0) continue;
          const index_t id = next++;
          out.copy_cell.push_back(c);
          out.copy_voxel.push_back(s);
          queue.assign(1, s);
          fc[s] = id;
          for (std::size_t q = 0; q < queue.size(); ++q) {
            const index_t v = queue[q];
            const index_t vz = v / nxy, vy = (v - vz * nxy) / nx, vx = v - vz * nxy - vy * nx;
            for (int k = 0; k < N; ++k) {
              const index_t ux = vx + fine_st.offset[k][0], uy = vy + fine_st.offset[k][1], uz = vz + fine_st.offset[k][2];
              if (ux < lo[0] || ux >= hi[0] || uy < lo[1] || uy >= hi[1] || uz < lo[2] || uz >= hi[2]) continue;
              const index_t u = v + fine_st.delta[k];
              if (!material(u) || fc[u] >= 0 || (cm && ((cm[v] >> k) & 1u))) continue;
              fc[u] = id;
              queue.push_back(u);
            }
          }
        }
  }
  out.cell_begin[std::size_t(cells)] = next;
  const index_t copies = next;

  // 2. stiffness: the reduction of each copy's values, visited in increasing fine index
  out.stiffness.assign(std::size_t(copies), T(0));
  out.voxel_count.assign(std::size_t(copies), 0);
  {
    std::vector<double> acc(std::size_t(copies), 0.0);
    std::vector<T> ext(std::size_t(copies), T(0));
    for (index_t c = 0; c < cells; ++c) {
      index_t lo[3], hi[3];
      block(c, lo, hi);
      for (index_t z = lo[2]; z < hi[2]; ++z)
        for (index_t y = lo[1]; y < hi[1]; ++y)
          for (index_t x = lo[0]; x < hi[0]; ++x) {
            const index_t v = x + nx * y + nxy * z;
            const index_t id = fc[v];
            if (id < 0) continue;
            const T val = f[v];
            const bool first = out.voxel_count[std::size_t(id)]++ == 0;
            switch (reduction) {
              case stiffness_reduction::mean: acc[std::size_t(id)] += double(val); break;
              case stiffness_reduction::harmonic_mean:
                acc[std::size_t(id)] += 1.0 / double(val);
                ext[std::size_t(id)] = val;
                break;
              case stiffness_reduction::min:
                if (first || val < ext[std::size_t(id)]) ext[std::size_t(id)] = val;
                break;
              case stiffness_reduction::max:
                if (first || val > ext[std::size_t(id)]) ext[std::size_t(id)] = val;
                break;
            }
          }
    }
    for (index_t id = 0; id < copies; ++id) {
      const auto i = std::size_t(id);
      const double n = double(out.voxel_count[i]);
      switch (reduction) {
        case stiffness_reduction::mean: out.stiffness[i] = static_cast<T>(acc[i] / n); break;
        case stiffness_reduction::harmonic_mean:
          out.stiffness[i] = out.voxel_count[i] == 1 ? ext[i] : static_cast<T>(n / acc[i]);
          break;
        default: out.stiffness[i] = ext[i]; break;
      }
    }
  }

  // 3. links: fine neighbours in different cells, per copy sorted by the other copy
  out.link_begin.assign(std::size_t(copies) + 1, 0);
  std::vector<std::pair<index_t, index_t>> pairs;  // (copy here, copy there)
  for (index_t c = 0; c < cells; ++c) {
    index_t lo[3], hi[3];
    block(c, lo, hi);
    pairs.clear();
    for (index_t z = lo[2]; z < hi[2]; ++z)
      for (index_t y = lo[1]; y < hi[1]; ++y)
        for (index_t x = lo[0]; x < hi[0]; ++x) {
          const index_t v = x + nx * y + nxy * z;
          const index_t id = fc[v];
          if (id < 0) continue;
          // only voxels on the block's rim have neighbours in other cells
          if (x > lo[0] && x + 1 < hi[0] && y > lo[1] && y + 1 < hi[1] && (Dim == 2 || (z > lo[2] && z + 1 < hi[2])))
            continue;
          for (int k = 0; k < N; ++k) {
            const index_t ux = x + fine_st.offset[k][0], uy = y + fine_st.offset[k][1], uz = z + fine_st.offset[k][2];
            if (ux < 0 || ux >= nx || uy < 0 || uy >= ny || uz < 0 || uz >= nz) continue;
            if (ux >= lo[0] && ux < hi[0] && uy >= lo[1] && uy < hi[1] && uz >= lo[2] && uz < hi[2]) continue;
            const index_t w = fc[v + fine_st.delta[k]];
            if (w >= 0 && !(cm && ((cm[v] >> k) & 1u))) pairs.push_back({id, w});
          }
        }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    const index_t first = out.cell_begin[std::size_t(c)], last = out.cell_begin[std::size_t(c) + 1];
    std::size_t i = 0;
    const coord<Dim> here = out.coarse.coords(c);
    for (index_t id = first; id < last; ++id) {
      out.link_begin[std::size_t(id)] = index_t(out.link_copy.size());
      for (; i < pairs.size() && pairs[i].first == id; ++i) {
        const index_t w = pairs[i].second;
        const coord<Dim> there = out.coarse.coords(out.copy_cell[std::size_t(w)]);
        int code = 0, mul = 1;
        for (int a = 0; a < Dim; ++a, mul *= 3) code += int(there[a] - here[a] + 1) * mul;
        out.link_copy.push_back(w);
        out.link_dir.push_back(std::uint8_t(coarse_dir[std::size_t(code)]));
      }
    }
  }
  out.link_begin[std::size_t(copies)] = index_t(out.link_copy.size());

  // 4. the walk's form of the links, over slots
  static_assert(N <= 31, "the walk mask holds one bit per stencil direction, and the row bit");
  out.slot_of_copy.assign(std::size_t(copies), 0);
  index_t extra_slot = cells;
  for (index_t a = 0; a < copies; ++a) {
    const index_t c = out.copy_cell[std::size_t(a)];
    out.slot_of_copy[std::size_t(a)] = a == out.cell_begin[std::size_t(c)] ? c : extra_slot++;
  }
  const index_t slots = extra_slot;
  out.copy_of_slot.assign(std::size_t(slots), -1);
  out.slot_stiffness.assign(std::size_t(slots), std::numeric_limits<T>::quiet_NaN());
  out.walk.assign(std::size_t(slots), search::copy_walk{});
  out.walk_bits.assign(std::size_t(slots), 0);
  for (index_t a = 0; a < copies; ++a) {
    const index_t sa = out.slot_of_copy[std::size_t(a)];
    out.copy_of_slot[std::size_t(sa)] = a;
    out.slot_stiffness[std::size_t(sa)] = out.stiffness[std::size_t(a)];
    auto& cw = out.walk[std::size_t(sa)];
    cw.cell = out.copy_cell[std::size_t(a)];
    cw.extra_begin = index_t(out.walk_extra_node.size());
    for (index_t i = out.link_begin[std::size_t(a)]; i < out.link_begin[std::size_t(a) + 1]; ++i) {
      const index_t w = out.link_copy[std::size_t(i)];
      const index_t wc = out.copy_cell[std::size_t(w)];
      if (out.cell_begin[std::size_t(wc) + 1] - out.cell_begin[std::size_t(wc)] == 1) {
        cw.mask |= std::uint32_t(1) << out.link_dir[std::size_t(i)];
      } else {
        out.walk_extra_node.push_back(out.slot_of_copy[std::size_t(w)]);
        out.walk_extra_dir.push_back(out.link_dir[std::size_t(i)]);
        ++cw.extra_count;
      }
    }
    out.walk_bits[std::size_t(sa)] = cw.mask | (sa >= cells || cw.extra_count > 0 ? search::copy_walk::row_bit : 0u);
  }
  return out;
}

}  // namespace detail::branching
}  // namespace geovoronoi
