#pragma once
// The CUDA backend's dense solve on the device (the bounded solve runs it too, with the radius as
// bound): the problem's field uploaded, the tiled engine (engine.cuh) run from the sources, and for
// float a second pass that recomputes labels from the final distances (repair.cuh); then the reached
// voxels read back in increasing voxel order.

#include <geovoronoi/backend/cuda/detail/engine.cuh>
#include <geovoronoi/backend/cuda/detail/error.cuh>
#include <geovoronoi/backend/cuda/detail/repair.cuh>
#include <geovoronoi/backend/cuda/detail/tiling.hpp>
#include <geovoronoi/result.hpp>

#include <cuda_runtime.h>

#include <cstdint>
#include <type_traits>
#include <vector>

namespace geovoronoi::cuda {

namespace detail {

template <class P>
using T_of = typename P::value_type;

template <class P>
tiling tiling_of(const P& p) {
  const auto& g = p.geometry;
  return make_tiling<P::dim>(g.extent(0), g.extent(1), P::dim == 3 ? g.extent(P::dim - 1) : 1);
}

/// The problem's field (and cut table, if it has one) on the device, and a copy of the problem that
/// points at them.
template <class P>
struct device_problem {
  device_buffer<T_of<P>> field;
  device_buffer<index_t> cut_keys;
  device_buffer<cut_mask_t> cut_masks;
  P view;
  device_problem(const P& p, cudaStream_t s) : field(std::size_t(p.geometry.size())), view(p) {
    field.upload(p.field, field.size(), s);
    view.field = field.data();
    if constexpr (P::has_cuts) {
      const std::size_t cap = std::size_t(p.cuts.capacity);
      if (cap > 0) {
        cut_keys = device_buffer<index_t>(cap);
        cut_masks = device_buffer<cut_mask_t>(cap);
        cut_keys.upload(p.cuts.keys, cap, s);
        cut_masks.upload(p.cuts.masks, cap, s);
        view.cuts.keys = cut_keys.data();
        view.cuts.masks = cut_masks.data();
      }
    }
  }
};

/// Dense solve into state words (float: packed keys; double: distance bits, plus labels).
template <class P>
struct dense_state {
  device_buffer<unsigned long long> words;
  device_buffer<unsigned int> labels;  // double only
  bool overflowed = false;             // a candidate's sum was +inf (see geovoronoi/detail/overflow.hpp)
};

/// The dense solve on the device; @p iterations (optional) receives the engine iterations run.
template <class P>
dense_state<P> solve_dense(const device_problem<P>& dp, const tiling& t,
                           const std::vector<source<T_of<P>>>& sources, T_of<P> radius, cudaStream_t s,
                           long long* iterations = nullptr) {
  using T = T_of<P>;
  static_assert(std::is_trivially_copyable_v<P>, "geovoronoi::cuda: the problem must be trivially copyable");
  dense_state<P> st;
  st.words = device_buffer<unsigned long long>(std::size_t(t.voxels()));
  st.words.fill_bytes(0xFF, s);
  std::vector<seed_word> seeds;
  for (const auto& x : sources)
    if (x.distance < radius) {
      if constexpr (std::is_same_v<T, float>)
        seeds.push_back({x.voxel, pack(x.distance, x.label)});
      else
        seeds.push_back({x.voxel, distance_word(x.distance)});
    }
  device_buffer<int> overflow(1);
  overflow.fill_bytes(0, s);
  if constexpr (std::is_same_v<T, float>) {
    // pass 1: (distance, label) keys; pass 2: labels again from the final distances (rule_label)
    long long it = run_engine(dp.view, rule_voronoi{radius, overflow.data()}, t, st.words.data(), seeds, s);
    const index_t n = t.voxels();
    const int blocks = int((n + 255) / 256 < 65535 ? (n + 255) / 256 : 65535);
    clear_labels_kernel<><<<blocks, 256, 0, s>>>(st.words.data(), n);
    GEOVORONOI_CUDA_CHECK_LAUNCH("clear_labels_kernel");
    it += run_engine(dp.view, rule_label{}, t, st.words.data(), seeds, s);
    if (iterations) *iterations = it;
  } else {
    const long long it = run_engine(dp.view, rule_distance<T>{radius, overflow.data()}, t, st.words.data(), seeds, s);
    if (iterations) *iterations = it;
    st.labels = device_buffer<unsigned int>(std::size_t(t.voxels()));
    st.labels.fill_bytes(0xFF, s);
    std::vector<label_seed> ls;
    for (const auto& x : sources)
      if (x.distance < radius) ls.push_back({x.voxel, distance_word(x.distance), std::uint32_t(x.label)});
    run_label_pass(dp.view, t, st.words.data(), st.labels.data(), ls, s);
  }
  int flag = 0;
  overflow.download(&flag, 1, s);
  sync(s, "overflow flag");
  st.overflowed = flag != 0;
  return st;
}

/// Calls f(v, distance, label) for every reached voxel, in increasing voxel order.
template <class P, class F>
void for_each_reached(const dense_state<P>& st, index_t n, cudaStream_t s, F&& f) {
  using T = T_of<P>;
  std::vector<unsigned long long> words(static_cast<std::size_t>(n));
  st.words.download(words.data(), words.size(), s);
  std::vector<unsigned int> labels;
  if constexpr (!std::is_same_v<T, float>) {
    labels.resize(static_cast<std::size_t>(n));
    st.labels.download(labels.data(), labels.size(), s);
  }
  sync(s, "download of the solution");
  for (index_t v = 0; v < n; ++v) {
    const auto w = words[static_cast<std::size_t>(v)];
    if (w == unreached) continue;
    if constexpr (std::is_same_v<T, float>)
      f(v, key_distance(w), key_label(w));
    else
      f(v, word_distance<T>(w), label_t(labels[static_cast<std::size_t>(v)]));
  }
}

/// The dense solve below @p radius, then f(v, distance, label) for every reached voxel in increasing
/// voxel order: what the dense and the bounded hooks share.
/// Returns whether the engine saw an infinite sum (the caller scans the result on the host).
template <class P, class F>
bool solve_each_reached(const P& p, const std::vector<source<T_of<P>>>& sources, T_of<P> radius, cudaStream_t s,
                        F&& f) {
  const auto t = tiling_of(p);
  const device_problem<P> dp(p, s);
  const auto st = solve_dense(dp, t, sources, radius, s);
  for_each_reached(st, t.voxels(), s, f);
  return st.overflowed;
}

}  // namespace detail

}  // namespace geovoronoi::cuda
