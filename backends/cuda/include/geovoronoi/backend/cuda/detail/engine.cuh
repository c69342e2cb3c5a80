#pragma once
// The tiled relaxation engine shared by every CUDA operation.
//
// The grid is cut into tiles (8x8x8 in 3D, 16x16 in 2D). One 512-thread block takes one active tile
// at a time: it loads the tile and a one-voxel halo (state words and field) into shared memory,
// relaxes the tile's voxels to local convergence by pulling from their neighbours (Jacobi steps
// separated by barriers, so shared memory is race-free), writes improved voxels back with a 64-bit
// atomicMin and pushes candidates into the halo voxels, that is into the neighbouring tiles, also
// with atomicMin. A tile whose voxel a push improved is appended, once, to the next worklist.
//
// The worklist lives on the device: two lists of tile ids that alternate, a per-tile "queued" flag
// and two counters. The host enqueues iterations (relax + reset) without waiting and reads the
// active count once every check_every iterations; no per-iteration round trip.
//
// What a "state word" means is a rule: packed (distance, label) for float solves, the distance bits
// for double solves and for insert queries. Smaller is always better, all ones is "not reached".

#include <geovoronoi/backend/cuda/detail/error.cuh>
#include <geovoronoi/backend/cuda/detail/tile_ops.hpp>
#include <geovoronoi/backend/cuda/detail/tiling.hpp>
#include <geovoronoi/detail/search/relax.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/metric.hpp>

#include <cuda_runtime.h>

#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace geovoronoi::cuda::detail {

/// The device worklist: two alternating tile lists, their counters, one queued flag per tile.
struct worklist_view {
  std::uint32_t* list[2];
  std::uint32_t* count;  // [2]
  std::uint32_t* queued;
  int* error;            // set when a metric returns a negative or NaN weight
  /// List @p which (0 or 1); a select rather than an index keeps the view in registers.
  __device__ __forceinline__ std::uint32_t* tiles(int which) const { return which ? list[1] : list[0]; }
};

__device__ __forceinline__ void enqueue(const worklist_view& wl, int which, std::uint32_t tile) {
  if (atomicExch(&wl.queued[tile], 1u) == 0u) {
    const std::uint32_t at = atomicAdd(&wl.count[which], 1u);
    wl.tiles(which)[at] = tile;
  }
}


template <class = void>
GEOVORONOI_KERNEL void seed_kernel(tiling t, unsigned long long* words, const seed_word* seeds, int count, worklist_view wl) {
  for (int i = blockIdx.x * blockDim.x + threadIdx.x; i < count; i += gridDim.x * blockDim.x) {
    const seed_word s = seeds[i];
    atomicMin(&words[s.voxel], static_cast<unsigned long long>(s.word));
    enqueue(wl, 0, std::uint32_t(t.tile_of(s.voxel)));
  }
}

/// Clears the label half of every reached key before the float label pass.
template <class = void>
GEOVORONOI_KERNEL void clear_labels_kernel(unsigned long long* words, index_t n) {
  for (index_t v = index_t(blockIdx.x) * blockDim.x + threadIdx.x; v < n; v += index_t(gridDim.x) * blockDim.x)
    words[v] = clear_label(words[v]);
}

/// After an iteration: the list just filled becomes current (its tiles may be queued again), the
/// list just consumed is emptied for the next iteration to fill.
template <class = void>
GEOVORONOI_KERNEL void reset_kernel(worklist_view wl, int filled) {
  const std::uint32_t n = wl.count[filled];
  for (std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x; i < n; i += gridDim.x * blockDim.x)
    wl.queued[wl.tiles(filled)[i]] = 0u;
  if (blockIdx.x == 0 && threadIdx.x == 0) wl.count[1 - filled] = 0u;
}

template <class P, class Rule>
GEOVORONOI_KERNEL void __launch_bounds__(tile_shape<P::dim>::voxels)
relax_kernel(P p, Rule rule, tiling t, unsigned long long* words, worklist_view wl, int cur) {
  using T = typename P::value_type;
  using S = tile_shape<P::dim>;
  constexpr int Dim = P::dim;
  __shared__ unsigned long long sw[S::halo_voxels];
  __shared__ T sf[S::halo_voxels];

  const int me_x = int(threadIdx.x) % S::tx;
  const int me_y = (int(threadIdx.x) / S::tx) % S::ty;
  const int me_z = int(threadIdx.x) / (S::tx * S::ty);
  const int me = halo_slot<Dim>(me_x, me_y, me_z);
  const std::uint32_t active = wl.count[cur];

  for (std::uint32_t item = blockIdx.x; item < active; item += gridDim.x) {
    const std::uint32_t tile = wl.tiles(cur)[item];
    const tile_origin o = origin_of(t, tile);
    for (int s = int(threadIdx.x); s < S::halo_voxels; s += int(blockDim.x))
      load_slot(p, t, o, s, sw, sf, [words](index_t v) { return __ldcg(&words[v]); });
    __syncthreads();

    const index_t gx = o.x + me_x, gy = o.y + me_y, gz = o.z + me_z;
    const bool mine = t.in_grid(gx, gy, gz) && in_domain<P>(sf[me]);
    const index_t v = mine ? t.voxel(gx, gy, gz) : 0;
    const unsigned long long loaded = sw[me];
    bool bad = false;
    for (;;) {
      // Jacobi step: every thread reads, then every thread writes its own voxel
      const unsigned long long best = mine ? pull(p, rule, sw, sf, me_x, me_y, me_z, v, bad) : sw[me];
      __syncthreads();
      const bool changed = best < sw[me];
      if (changed) sw[me] = best;
      if (!__syncthreads_or(changed)) break;
    }
    if (mine && sw[me] < loaded) atomicMin(&words[v], sw[me]);

    // push into the halo, i.e. into the neighbouring tiles' border voxels
    for (int s = int(threadIdx.x); s < S::halo_voxels; s += int(blockDim.x)) {
      int lx, ly, lz;
      halo_coords<Dim>(s, lx, ly, lz);
      if (!is_halo<Dim>(lx, ly, lz)) continue;
      const index_t hx = o.x + lx, hy = o.y + ly, hz = o.z + lz;
      if (!t.in_grid(hx, hy, hz) || !in_domain<P>(sf[s])) continue;
      const index_t h = t.voxel(hx, hy, hz);
      const unsigned long long c = push_candidate(p, rule, sw, sf, lx, ly, lz, h, bad);
      if (c != unreached) {
        const unsigned long long before = atomicMin(&words[h], c);
        if (c < before) enqueue(wl, 1 - cur, std::uint32_t(t.tile_of(hx, hy, hz)));
      }
    }
    if (bad) *wl.error = 1;
    __syncthreads();  // the next tile reuses the shared arrays
  }
}

/// Device state of one engine run; owns everything it allocates.
struct engine_buffers {
  device_buffer<std::uint32_t> lists[2];
  device_buffer<std::uint32_t> count;
  device_buffer<std::uint32_t> queued;
  device_buffer<int> error;
  worklist_view view() const noexcept {
    return {{lists[0].data(), lists[1].data()}, count.data(), queued.data(), error.data()};
  }
};

/// How often (in iterations) the host looks at the active-tile count.
inline constexpr int check_every = 8;

inline int sm_count() {
  int dev = 0, sms = 0;
  GEOVORONOI_CUDA_CHECK(cudaGetDevice(&dev));
  GEOVORONOI_CUDA_CHECK(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, dev));
  return sms;
}

/**
 * Relaxes @p words (one per voxel, already on the device, all ones where unreached) from @p seeds
 * to the least fixed point of @p rule. @p dp is the problem with its field pointer on the device.
 * Returns the number of iterations.
 */
template <class P, class Rule>
long long run_engine(const P& dp, const Rule& rule, const tiling& t, unsigned long long* words,
                     const std::vector<seed_word>& seeds, cudaStream_t stream) {
  const index_t tiles = t.tiles();
  engine_buffers b;
  b.lists[0] = device_buffer<std::uint32_t>(std::size_t(tiles));
  b.lists[1] = device_buffer<std::uint32_t>(std::size_t(tiles));
  b.count = device_buffer<std::uint32_t>(2);
  b.queued = device_buffer<std::uint32_t>(std::size_t(tiles));
  b.error = device_buffer<int>(1);
  b.count.fill_bytes(0, stream);
  b.queued.fill_bytes(0, stream);
  b.error.fill_bytes(0, stream);
  const worklist_view wl = b.view();

  device_buffer<seed_word> dseeds(seeds.size());
  dseeds.upload(seeds.data(), seeds.size(), stream);
  if (!seeds.empty()) {
    const int sb = int((seeds.size() + 255) / 256);
    seed_kernel<><<<sb < 1024 ? sb : 1024, 256, 0, stream>>>(t, words, dseeds.data(), int(seeds.size()), wl);
    GEOVORONOI_CUDA_CHECK_LAUNCH("seed_kernel");
  }
  reset_kernel<><<<64, 256, 0, stream>>>(wl, 0);
  GEOVORONOI_CUDA_CHECK_LAUNCH("reset_kernel");

  constexpr int threads = tile_shape<P::dim>::voxels;
  int per_sm = 0;
  GEOVORONOI_CUDA_CHECK(
      cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, relax_kernel<P, Rule>, threads, 0));
  const int blocks = blocks_for(tiles, sm_count(), per_sm);
  const int reset_blocks = blocks_for(tiles, 64, 1);

  // Every iteration strictly lowers some word, so the loop ends; the cap only guards against bugs.
  const long long cap = 64LL * (long long)tiles * tile_shape<P::dim>::voxels + 1024;
  long long it = 0;
  for (;; ++it) {
    relax_kernel<P, Rule><<<blocks, threads, 0, stream>>>(dp, rule, t, words, wl, current_list(it));
    GEOVORONOI_CUDA_CHECK_LAUNCH("relax_kernel");
    reset_kernel<><<<reset_blocks, 256, 0, stream>>>(wl, next_list(it));
    GEOVORONOI_CUDA_CHECK_LAUNCH("reset_kernel");
    if ((it + 1) % check_every == 0) {
      std::uint32_t left = 0;
      GEOVORONOI_CUDA_CHECK(cudaMemcpyAsync(&left, b.count.data() + next_list(it), sizeof left,
                                            cudaMemcpyDeviceToHost, stream));
      sync(stream, "relaxation");
      if (left == 0) break;
      if (it > cap) throw error("geovoronoi::cuda: the relaxation did not converge (internal error)");
    }
  }
  int bad = 0;
  b.error.download(&bad, 1, stream);
  sync(stream, "relaxation error flag");
  if (bad) geovoronoi::detail::search::bad_weight();
  return it + 1;
}

}  // namespace geovoronoi::cuda::detail
