#pragma once
// Dense and bounded solves on the near-far engine.

#include <geovoronoi/backend/thrust/detail/engine.hpp>
#include <geovoronoi/backend/thrust/detail/repair.hpp>
#include <geovoronoi/detail/search/engine.hpp>
#include <geovoronoi/detail/overflow.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/image.hpp>
#include <geovoronoi/result.hpp>

#include <thrust/count.h>
#include <thrust/fill.h>

#ifdef __CUDACC__
#include <thrust/copy.h>
#include <thrust/iterator/counting_iterator.h>
#endif

#include <algorithm>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

namespace geovoronoi::thrust::detail {

template <class T>
struct below_radius {
  T radius;
  GEOVORONOI_HOST_DEVICE bool operator()(index_t, T nd) const { return nd < radius; }
};

/// Writes the sources' keys and queues them far.
template <class T>
struct seed_fn {
  const index_t* voxel;
  const key_cell<T>* key;
  key_cell<T>* keys;
  flag_t* flags;
  GEOVORONOI_HOST_DEVICE void operator()(index_t i) const {
    keys[voxel[i]] = key[i];
    flags[voxel[i]] = queued_far;
  }
};

/// Splits keys into distance and label arrays (+inf / -1 where unreached).
template <class T>
struct unpack_fn {
  const key_cell<T>* keys;
  T* distance;
  label_t* label;
  T inf;
  GEOVORONOI_HOST_DEVICE void operator()(index_t v) const {
    using kt = search::key_traits<T>;
    const auto k = key_cell<T>::load(keys + v);
    if (k == kt::unreached_key()) {
      distance[v] = inf;
      label[v] = no_label;
    } else {
      distance[v] = kt::distance(k);
      label[v] = kt::label(k);
    }
  }
};

/// Host systems: over chunks of voxels, counts each chunk's suspect voxels and, unless
/// unpack.distance is null, unpacks the keys and counts the reached voxels too. Counts go to
/// counts[2j] (reached) and counts[2j+1] (suspects) when unpacking, else to counts[j].
template <class T>
struct scan_chunk_fn {
  unpack_fn<T> unpack;
  const flag_t* flags;
  index_t n;
  index_t chunk;
  index_t* counts;
  void operator()(index_t j) const {
    const index_t begin = j * chunk, end = std::min(n, begin + chunk);
    const bool unpacking = unpack.distance != nullptr;
    index_t reached = 0, suspects = 0;
    for (index_t v = begin; v < end; ++v) {
      if (unpacking) {
        unpack(v);
        reached += unpack.label[v] != no_label;
      }
      suspects += (flags[v] & suspect_bit) != 0;
    }
    if (unpacking) {
      counts[2 * j] = reached;
      counts[2 * j + 1] = suspects;
    } else {
      counts[j] = suspects;
    }
  }
};

struct is_suspect {
  GEOVORONOI_HOST_DEVICE bool operator()(flag_t f) const noexcept { return (f & suspect_bit) != 0; }
};

/// Host systems: the suspect voxels of the chunks whose count is non-zero (normally few).
inline std::vector<index_t> gather_suspects(const flag_t* flags, index_t n, index_t chunk, const index_t* counts,
                                            index_t stride) {
  std::vector<index_t> out;
  const index_t chunks = (n + chunk - 1) / chunk;
  for (index_t j = 0; j < chunks; ++j) {
    if (counts[j * stride] == 0) continue;
    const index_t begin = j * chunk, end = std::min(n, begin + chunk);
    for (index_t v = begin; v < end; ++v)
      if (flags[v] & suspect_bit) out.push_back(v);
  }
  return out;
}

/// The voxels the engine marked suspect, on the host, in increasing index.
template <class Exec>
std::vector<index_t> collect_suspects(const Exec& exec, const flag_t* flags, index_t n) {
  if constexpr (is_cuda_policy_v<Exec>) {
#ifdef __CUDACC__
    const auto dev = ::thrust::device_pointer_cast(flags);
    const index_t c = static_cast<index_t>(::thrust::count_if(exec, dev, dev + n, is_suspect{}));
    std::vector<index_t> out(static_cast<std::size_t>(c));
    if (c == 0) return out;
    vec<Exec, index_t> list(static_cast<std::size_t>(c));
    ::thrust::copy_if(exec, ::thrust::counting_iterator<index_t>(0), ::thrust::counting_iterator<index_t>(n), dev,
                      list.begin(), is_suspect{});
    ::thrust::copy(list.begin(), list.end(), out.begin());
    return out;
#else
    return {};
#endif
  } else {
    const index_t chunk = 16384;
    const index_t chunks = (n + chunk - 1) / chunk;
    std::vector<index_t> counts(static_cast<std::size_t>(chunks));
    // counting only: nothing is unpacked, so the key type does not matter
    const scan_chunk_fn<float> count{{nullptr, nullptr, nullptr, 0.0f}, flags, n, chunk, counts.data()};
    parallel_for(exec, chunks, count, n);
    return gather_suspects(flags, n, chunk, counts.data(), 1);
  }
}

/// Working state of one engine run over the whole grid.
template <class Exec, class T>
struct dense_state {
  vec<Exec, key_cell<T>> keys;
  vec<Exec, flag_t> flags;
  vec<Exec, index_t> far;
  index_t far_size = 0;
};

/// Initialise keys and flags for @p sources (those not accepted, here d >= radius, are left out).
template <class Exec, class T, class Keep>
void seed(const Exec& exec, dense_state<Exec, T>& st, index_t n, const std::vector<source<T>>& sources, Keep keep) {
  using kt = search::key_traits<T>;
  st.keys.resize(static_cast<std::size_t>(n));
  st.flags.resize(static_cast<std::size_t>(n));
  if (go_parallel<Exec>(n)) {
    ::thrust::fill(exec, raw(st.keys), raw(st.keys) + n, key_cell<T>::make(kt::unreached));
    ::thrust::fill(exec, raw(st.flags), raw(st.flags) + n, idle);
  } else {
    std::fill(raw(st.keys), raw(st.keys) + n, key_cell<T>::make(kt::unreached));
    std::fill(raw(st.flags), raw(st.flags) + n, idle);
  }
  std::vector<index_t> vox;
  std::vector<key_cell<T>> key;
  for (const auto& s : sources)
    if (keep(s)) {
      vox.push_back(s.voxel);
      key.push_back(key_cell<T>::make(kt::make(s.distance, s.label)));
    }
  st.far_size = static_cast<index_t>(vox.size());
  st.far.resize(vox.size());
  if (vox.empty()) return;
  vec<Exec, key_cell<T>> kv(key.begin(), key.end());
  vec<Exec, index_t> vv(vox.begin(), vox.end());
  st.far = vv;
  parallel_for(exec, st.far_size, seed_fn<T>{raw(vv), raw(kv), raw(st.keys), raw(st.flags)}, st.far_size);
}

/// Seeds @p st with the sources below @p radius and runs the engine bounded by the radius: the common
/// start of the dense and the bounded solves.
template <class Exec, class P>
engine_counts run_below(const Exec& exec, const P& p, const std::vector<source<typename P::value_type>>& sources,
                        typename P::value_type radius, index_t target,
                        dense_state<Exec, typename P::value_type>& st,
                        const geovoronoi::detail::solve_control& ctl) {
  using T = typename P::value_type;
  // the progress denominator: the domain's voxels where the field is host memory, else the grid's
  double total = double(search::node_count(p));
  if constexpr (!is_cuda_policy_v<Exec>)
    if (ctl.reporting()) total = double(search::count_inside(p));
  ctl.report(0.0);
  seed(exec, st, search::node_count(p), sources, [radius](const source<T>& s) { return s.distance < radius; });
  return run(exec, p, raw(st.keys), raw(st.flags), st.far, st.far_size, below_radius<T>{radius}, target, ctl, total);
}

/// A raised overflow flag of an unbounded solve: the scan of geovoronoi/detail/overflow.hpp on the
/// host result, which throws if the overflow is real. On the CUDA system the field may live in device
/// memory, so there the error names no voxel.
template <class Exec, class P, class Scan>
void check_overflow(const engine_counts& c, typename P::value_type radius, Scan&& scan) {
  using T = typename P::value_type;
  if (!c.overflowed || radius <= std::numeric_limits<T>::max()) return;
  if constexpr (is_cuda_policy_v<Exec>) {
    throw overflow_error(std::string("geovoronoi: a distance overflows ") +
                         (std::is_same_v<T, float> ? "float" : "double") +
                         " (a path sum or an edge weight is +inf), so voxels that a path reaches would come out "
                         "unreachable; compute in double precision, or rescale the field or the spacing");
  } else {
    scan();
  }
}

/// Dense solve over the nodes of @p p (a grid's voxels or an explicit graph's nodes) into the host
/// arrays @p distance and @p label (one entry per node, every entry written), labels repaired (see
/// repair.hpp).
/// The same with the engine running on @p pe, the problem as the system reads it (on the CUDA system,
/// an explicit graph whose arrays were copied to the device); the label repair and the overflow scan
/// read @p p (host memory). solve_into(exec, p, ...) is solve_on(exec, p, p, ...).
template <class Exec, class PE, class P>
void solve_on(const Exec& exec, const PE& pe, const P& p, const std::vector<source<typename P::value_type>>& sources,
              typename P::value_type radius, index_t target, engine_counts& counts,
              const geovoronoi::detail::solve_control& ctl, typename P::value_type* distance, label_t* label) {
  using T = typename P::value_type;
  const index_t n = search::node_count(p);
  dense_state<Exec, T> st;
  counts = run_below(exec, pe, sources, radius, target, st, ctl);
  const T inf = std::numeric_limits<T>::infinity();
  std::vector<index_t> suspects;
  if constexpr (is_cuda_policy_v<Exec>) {
#ifdef __CUDACC__
    vec<Exec, T> dist(static_cast<std::size_t>(n));
    vec<Exec, label_t> lab(static_cast<std::size_t>(n));
    parallel_for(exec, n, unpack_fn<T>{raw(st.keys), raw(dist), raw(lab), inf}, n);
    ::thrust::copy(dist.begin(), dist.end(), distance);
    ::thrust::copy(lab.begin(), lab.end(), label);
    suspects = collect_suspects(exec, raw(st.flags), n);
    for (index_t v = 0; v < n; ++v) counts.reached += label[v] != no_label;
#endif
  } else {
    const index_t chunk = 16384;
    const index_t chunks = (n + chunk - 1) / chunk;
    std::vector<index_t> c(static_cast<std::size_t>(2 * chunks));
    const unpack_fn<T> unpack{raw(st.keys), distance, label, inf};
    parallel_for(exec, chunks, scan_chunk_fn<T>{unpack, raw(st.flags), n, chunk, c.data()}, n);
    for (index_t j = 0; j < chunks; ++j) counts.reached += static_cast<std::uint64_t>(c[2 * j]);
    suspects = gather_suspects(raw(st.flags), n, chunk, c.data() + 1, 2);
  }
  counts.suspects = suspects.size();
  dense_labels<T> store{distance, label, n};
  counts.relabelled = repair_labels(p, store, sources, std::move(suspects));
  check_overflow<Exec, P>(counts, radius, [&] { geovoronoi::detail::throw_if_overflowed_dense(p, distance); });
  ctl.report(1.0);
}

template <class Exec, class P>
void solve_into(const Exec& exec, const P& p, const std::vector<source<typename P::value_type>>& sources,
                typename P::value_type radius, index_t target, engine_counts& counts,
                const geovoronoi::detail::solve_control& ctl, typename P::value_type* distance, label_t* label) {
  solve_on(exec, p, p, sources, radius, target, counts, ctl, distance, label);
}

/// Dense solve: distance and label images, labels repaired (see repair.hpp).
template <class Exec, class P>
diagram<typename P::value_type, P::dim> solve(const Exec& exec, const P& p,
                                              const std::vector<source<typename P::value_type>>& sources,
                                              typename P::value_type radius, index_t target, engine_counts& counts,
                                              const geovoronoi::detail::solve_control& ctl = {}) {
  using T = typename P::value_type;
  diagram<T, P::dim> d;
  d.distance = image<T, P::dim>(p.geometry, T(0));
  d.label = image<label_t, P::dim>(p.geometry, no_label);
  solve_into(exec, p, sources, radius, target, counts, ctl, d.distance.data(), d.label.data());
  return d;
}

/// The same over the nodes of an explicit graph (a branching grid's copies). On the CUDA system the
/// engine walks device copies of the graph's arrays (P::with_walk_arrays); the rest runs on the host.
template <class Exec, class P>
node_diagram<typename P::value_type> solve_nodes(const Exec& exec, const P& p,
                                                 const std::vector<source<typename P::value_type>>& sources,
                                                 typename P::value_type radius, index_t target, engine_counts& counts,
                                                 const geovoronoi::detail::solve_control& ctl = {}) {
  using T = typename P::value_type;
  node_diagram<T> d;
  const auto n = static_cast<std::size_t>(search::node_count(p));
  d.distance.assign(n, T(0));
  d.label.assign(n, no_label);
  if constexpr (is_cuda_policy_v<Exec>) {
#ifdef __CUDACC__
    // the graph's arrays are host memory: the engine reads device copies (P::with_walk_arrays)
    std::vector<std::shared_ptr<void>> keep;
    const P pd = p.with_walk_arrays([&](const auto* data, std::size_t count) {
      using U = std::remove_cv_t<std::remove_pointer_t<decltype(data)>>;
      auto v = std::make_shared<vec<Exec, U>>(data, data + count);
      keep.push_back(v);
      return static_cast<const U*>(raw(*v));
    });
    solve_on(exec, pd, p, sources, radius, target, counts, ctl, d.distance.data(), d.label.data());
#endif
  } else {
    solve_into(exec, p, sources, radius, target, counts, ctl, d.distance.data(), d.label.data());
  }
  return d;
}

/// Per-chunk count / write of the reached voxels, in voxel order.
template <class T>
struct reached_fn {
  const key_cell<T>* keys;
  index_t n;
  index_t chunk;
  index_t* count;
  index_t* out;  // nullptr: count pass
  GEOVORONOI_HOST_DEVICE void operator()(index_t j) const {
    using kt = search::key_traits<T>;
    const index_t begin = j * chunk, end = begin + chunk < n ? begin + chunk : n;
    if (begin >= n) {
      if (!out) count[j] = 0;
      return;
    }
    index_t c = 0;
    for (index_t v = begin; v < end; ++v)
      if (key_cell<T>::load(keys + v) != kt::unreached_key()) {
        if (out) out[count[j] + c] = v;
        ++c;
      }
    if (!out) count[j] = c;
  }
};

template <class T>
struct sparse_fn {
  const key_cell<T>* keys;
  const index_t* voxel;
  T* distance;
  label_t* label;
  GEOVORONOI_HOST_DEVICE void operator()(index_t i) const {
    using kt = search::key_traits<T>;
    const auto k = key_cell<T>::load(keys + voxel[i]);
    distance[i] = kt::distance(k);
    label[i] = kt::label(k);
  }
};

/// Voxels whose key is set, sorted, with their distances and labels.
template <class Exec, class T>
sparse_solution<T> extract(const Exec& exec, const key_cell<T>* keys, index_t n) {
  const index_t chunk = is_cuda_policy_v<Exec> ? 256 : 4096;
  const index_t chunks = (n + chunk - 1) / chunk;
  vec<Exec, index_t> count(static_cast<std::size_t>(chunks + 1));
  parallel_for(exec, chunks + 1, reached_fn<T>{keys, n, chunk, raw(count), nullptr}, n);
  const index_t total = exclusive_scan(exec, raw(count), chunks + 1);
  sparse_solution<T> r;
  r.voxel.resize(static_cast<std::size_t>(total));
  r.distance.resize(static_cast<std::size_t>(total));
  r.label.resize(static_cast<std::size_t>(total));
  if (total == 0) return r;
  if constexpr (is_cuda_policy_v<Exec>) {
#ifdef __CUDACC__
    vec<Exec, index_t> vox(static_cast<std::size_t>(total));
    vec<Exec, T> dist(static_cast<std::size_t>(total));
    vec<Exec, label_t> lab(static_cast<std::size_t>(total));
    parallel_for(exec, chunks, reached_fn<T>{keys, n, chunk, raw(count), raw(vox)}, n);
    parallel_for(exec, total, sparse_fn<T>{keys, raw(vox), raw(dist), raw(lab)}, total);
    ::thrust::copy(vox.begin(), vox.end(), r.voxel.begin());
    ::thrust::copy(dist.begin(), dist.end(), r.distance.begin());
    ::thrust::copy(lab.begin(), lab.end(), r.label.begin());
#endif
  } else {  // host memory: straight into the result
    parallel_for(exec, chunks, reached_fn<T>{keys, n, chunk, raw(count), r.voxel.data()}, n);
    parallel_for(exec, total, sparse_fn<T>{keys, r.voxel.data(), r.distance.data(), r.label.data()}, total);
  }
  return r;
}

template <class Exec, class P>
sparse_solution<typename P::value_type> bounded(const Exec& exec, const P& p,
                                                const std::vector<source<typename P::value_type>>& sources,
                                                typename P::value_type radius, index_t target, engine_counts& counts,
                                                const geovoronoi::detail::solve_control& ctl = {}) {
  using T = typename P::value_type;
  const index_t n = p.geometry.size();
  dense_state<Exec, T> st;
  counts = run_below(exec, p, sources, radius, target, st, ctl);
  auto r = extract(exec, raw(st.keys), n);
  counts.reached = r.size();
  auto suspects = collect_suspects(exec, raw(st.flags), n);
  counts.suspects = suspects.size();
  sparse_labels<T> store{r.voxel.data(), r.distance.data(), r.label.data(), static_cast<index_t>(r.size())};
  counts.relabelled = repair_labels(p, store, sources, std::move(suspects));
  check_overflow<Exec, P>(counts, radius, [&] {
    geovoronoi::detail::throw_if_overflowed_sparse(p, r.voxel.data(), r.distance.data(), r.size());
  });
  ctl.report(1.0);
  return r;
}

}  // namespace geovoronoi::thrust::detail
