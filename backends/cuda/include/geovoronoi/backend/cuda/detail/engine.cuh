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
#include <geovoronoi/backend/cuda/detail/tiling.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/metric.hpp>

#include <cuda_runtime.h>

#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace geovoronoi::cuda {

/**
 * @brief Customisation point: the metric object kernels evaluate for a problem's metric type.
 *
 * The default is the metric itself, which must then have a host-device call operator (the core's
 * metrics do). Specialise it to map a host-only metric to an equivalent device-capable one.
 */
template <class Metric>
struct device_metric {
  using type = Metric;
  static GEOVORONOI_HOST_DEVICE const Metric& convert(const Metric& m) noexcept { return m; }
};

namespace detail {

template <class P>
using dmetric_t = typename device_metric<typename P::metric_type>::type;

/// Round-to-nearest addition that the compiler may not fuse or reorder.
__device__ __forceinline__ float add_rn(float a, float b) { return __fadd_rn(a, b); }
__device__ __forceinline__ double add_rn(double a, double b) { return __dadd_rn(a, b); }

/// Edge weight from a voxel with field @p from to one with field @p to through neighbour k.
template <class P>
__device__ __forceinline__ typename P::value_type edge_weight(const P& p, int k, typename P::value_type from,
                                                              typename P::value_type to) {
  const auto& m = device_metric<typename P::metric_type>::convert(p.metric);
  return m(p.edges.length[k], from, to);
}

template <class P>
__device__ __forceinline__ bool in_domain(typename P::value_type f) {
  return geovoronoi::detail::inside<dmetric_t<P>>(f);
}

// ---- rules ---------------------------------------------------------------------------------------

/// float Voronoi: packed (distance, label) keys; accepts distances below the radius.
struct rule_voronoi {
  float radius;
  __device__ uint64_t candidate(uint64_t from, float w, index_t) const {
    const float nd = add_rn(key_distance(from), w);
    return nd < radius ? pack(nd, key_label(from)) : unreached;
  }
};

/// Distances only (double solves; labels follow in a separate pass).
template <class T>
struct rule_distance {
  T radius;
  __device__ uint64_t candidate(uint64_t from, T w, index_t) const {
    const T nd = add_rn(word_distance<T>(from), w);
    return nd < radius ? distance_word(nd) : unreached;
  }
};

/// Insert query: distances from the query, accepted only where strictly below the diagram's.
template <class T>
struct rule_insert {
  const T* old;
  __device__ uint64_t candidate(uint64_t from, T w, index_t v) const {
    const T nd = add_rn(word_distance<T>(from), w);
    return nd < old[v] ? distance_word(nd) : unreached;
  }
};

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

/// A source of the engine: voxel and initial state word.
struct seed_word {
  index_t voxel;
  uint64_t word;
};

template <class = void>
GEOVORONOI_KERNEL void seed_kernel(tiling t, unsigned long long* words, const seed_word* seeds, int count, worklist_view wl) {
  for (int i = blockIdx.x * blockDim.x + threadIdx.x; i < count; i += gridDim.x * blockDim.x) {
    const seed_word s = seeds[i];
    atomicMin(&words[s.voxel], static_cast<unsigned long long>(s.word));
    enqueue(wl, 0, std::uint32_t(t.tile_of(s.voxel)));
  }
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
  constexpr int N = P::neighbours;
  __shared__ unsigned long long sw[S::halo_voxels];
  __shared__ T sf[S::halo_voxels];

  const int me_x = int(threadIdx.x) % S::tx;
  const int me_y = (int(threadIdx.x) / S::tx) % S::ty;
  const int me_z = int(threadIdx.x) / (S::tx * S::ty);
  const int me = halo_slot<Dim>(me_x, me_y, me_z);
  const std::uint32_t active = wl.count[cur];

  for (std::uint32_t item = blockIdx.x; item < active; item += gridDim.x) {
    const std::uint32_t tile = wl.tiles(cur)[item];
    index_t ta, tb, tc;
    t.tile_coords(tile, ta, tb, tc);
    const index_t x0 = ta * S::tx, y0 = tb * S::ty, z0 = tc * S::tz;

    for (int s = int(threadIdx.x); s < S::halo_voxels; s += int(blockDim.x)) {
      int lx, ly, lz;
      halo_coords<Dim>(s, lx, ly, lz);
      const index_t gx = x0 + lx, gy = y0 + ly, gz = z0 + lz;
      if (t.in_grid(gx, gy, gz)) {
        const index_t v = t.voxel(gx, gy, gz);
        const T f = p.field[v];
        sf[s] = f;
        sw[s] = in_domain<P>(f) ? __ldcg(&words[v]) : unreached;
      } else {
        sf[s] = T(0);
        sw[s] = unreached;
      }
    }
    __syncthreads();

    const index_t gx = x0 + me_x, gy = y0 + me_y, gz = z0 + me_z;
    const bool mine = t.in_grid(gx, gy, gz) && in_domain<P>(sf[me]);
    const index_t v = mine ? t.voxel(gx, gy, gz) : 0;
    const unsigned long long loaded = sw[me];
    for (;;) {
      unsigned long long best = sw[me];
      if (mine) {
        const T fv = sf[me];
#pragma unroll
        for (int k = 0; k < N; ++k) {
          const int s = halo_slot<Dim>(me_x + p.edges.offset[k][0], me_y + p.edges.offset[k][1],
                                       me_z + p.edges.offset[k][2]);
          const unsigned long long su = sw[s];
          if (su == unreached) continue;
          const T w = edge_weight(p, k, sf[s], fv);
          if (!(w >= T(0))) {
            *wl.error = 1;
            continue;
          }
          const unsigned long long c = rule.candidate(su, w, v);
          if (c < best) best = c;
        }
      }
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
      const index_t hx = x0 + lx, hy = y0 + ly, hz = z0 + lz;
      if (!t.in_grid(hx, hy, hz)) continue;
      const T fh = sf[s];
      if (!in_domain<P>(fh)) continue;
      const index_t h = t.voxel(hx, hy, hz);
      unsigned long long best = sw[s];
#pragma unroll
      for (int k = 0; k < N; ++k) {
        const int ux = lx + p.edges.offset[k][0], uy = ly + p.edges.offset[k][1], uz = lz + p.edges.offset[k][2];
        if (is_halo<Dim>(ux, uy, uz)) continue;
        const int su_slot = halo_slot<Dim>(ux, uy, uz);
        const unsigned long long su = sw[su_slot];
        if (su == unreached) continue;
        const T w = edge_weight(p, k, sf[su_slot], fh);
        if (!(w >= T(0))) {
          *wl.error = 1;
          continue;
        }
        const unsigned long long c = rule.candidate(su, w, h);
        if (c < best) best = c;
      }
      if (best < sw[s]) {
        const unsigned long long before = atomicMin(&words[h], best);
        if (best < before) enqueue(wl, 1 - cur, std::uint32_t(t.tile_of(hx, hy, hz)));
      }
    }
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

[[noreturn]] inline void throw_bad_weight() {
  throw metric_error("geovoronoi::cuda: the metric returned a negative or NaN edge weight; weights must be >= 0");
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
  if (bad) throw_bad_weight();
  return it + 1;
}

}  // namespace detail
}  // namespace geovoronoi::cuda
