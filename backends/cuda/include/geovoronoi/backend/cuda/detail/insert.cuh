#pragma once
// Batched insert queries. One block per query searches a box of voxels around it (16^3 in 3D, 64^2
// in 2D) held in shared memory, with the same acceptance rule as every backend: a candidate distance
// from the query is kept only where it is strictly below the diagram's. If no accepted voxel lies on
// a box face that has grid beyond it, no accepted path can leave the box and the box result is the
// exact cell; otherwise the query is flagged and recomputed by the tiled engine on the whole grid
// (the global-memory fallback). Cells come out in box order, which is increasing voxel index.

#include <geovoronoi/backend/cuda/detail/engine.cuh>

namespace geovoronoi::cuda::detail {

inline constexpr int query_threads = 256;

/// Per-batch outputs: query i owns slots [i * box, (i + 1) * box).
template <class T>
struct query_out {
  index_t* voxel;
  T* distance;
  std::uint32_t* count;
  std::uint32_t* overflow;
};

template <class P>
GEOVORONOI_KERNEL void __launch_bounds__(query_threads)
insert_box_kernel(P p, tiling t, const typename P::value_type* old, const index_t* queries, query_out<typename P::value_type> out) {
  using T = typename P::value_type;
  using B = query_box_shape<P::dim>;
  constexpr int per_thread = B::voxels / query_threads;
  static_assert(B::voxels % query_threads == 0, "query box must split evenly over the block");
  __shared__ unsigned long long sw[B::voxels];
  __shared__ std::uint32_t scan[query_threads];

  const index_t q = queries[blockIdx.x];
  const query_box box = box_around<P::dim>(t, q);
  const int used = box.used();
  const int first = int(threadIdx.x) * per_thread;  // each thread owns a contiguous run of box slots

  for (int j = 0; j < per_thread; ++j) {
    const int s = first + j;
    sw[s] = unreached;
    if (s < used && box.voxel(t, s) == q && T(0) < old[q]) sw[s] = distance_word(T(0));
  }
  __syncthreads();

  for (;;) {
    // Jacobi step over the box: read everything, barrier, write own slots
    unsigned long long next[per_thread];
#pragma unroll
    for (int j = 0; j < per_thread; ++j) {
      const int s = first + j;
      next[j] = s < used ? box_pull(p, t, box, sw, old, s, sw[s]) : unreached;
    }
    __syncthreads();
    bool changed = false;
#pragma unroll
    for (int j = 0; j < per_thread; ++j)
      if (first + j < used && next[j] < sw[first + j]) {
        sw[first + j] = next[j];
        changed = true;
      }
    if (!__syncthreads_or(changed)) break;
  }

  // overflow test and per-thread counts
  std::uint32_t mine = 0;
  bool open = false;
  for (int j = 0; j < per_thread; ++j) {
    const int s = first + j;
    if (s >= used || sw[s] == unreached) continue;
    ++mine;
    open = open || box.open(t, s);
  }
  const int overflow = __syncthreads_or(open);
  scan[threadIdx.x] = mine;
  __syncthreads();
  // inclusive Hillis-Steele scan over the block's counts
  for (int step = 1; step < query_threads; step <<= 1) {
    const std::uint32_t add = int(threadIdx.x) >= step ? scan[threadIdx.x - step] : 0u;
    __syncthreads();
    scan[threadIdx.x] += add;
    __syncthreads();
  }
  if (threadIdx.x == query_threads - 1) {
    out.count[blockIdx.x] = overflow ? 0u : scan[threadIdx.x];
    out.overflow[blockIdx.x] = overflow ? 1u : 0u;
  }
  if (overflow) return;
  std::size_t at = std::size_t(blockIdx.x) * B::voxels + (scan[threadIdx.x] - mine);
  for (int j = 0; j < per_thread; ++j) {
    const int s = first + j;
    if (s >= used || sw[s] == unreached) continue;
    out.voxel[at] = box.voxel(t, s);
    out.distance[at] = word_distance<T>(sw[s]);
    ++at;
  }
}

}  // namespace geovoronoi::cuda::detail
