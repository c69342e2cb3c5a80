#pragma once
// Labels of double solves. A (double, label) key is 96 bits, too wide for one atomicMin, so double
// solves run the engine on distance bits alone and then recover the labels: label(v) is the least
// label among v's own source (if its initial distance is d(v)) and the neighbours u that realise
// d(v), i.e. fl(d(u) + w(u, v)) == d(v). Starting from "none" and lowering labels with atomicMin until
// nothing changes reaches exactly the lexicographic (distance, label) minimum that the float keys
// and the sequential backend give (every reached voxel has a realising chain back to a source).

#include <geovoronoi/backend/cuda/detail/engine.cuh>

namespace geovoronoi::cuda::detail {

inline constexpr std::uint32_t no_label_word = ~std::uint32_t(0);

struct label_seed {
  index_t voxel;
  uint64_t word;  // the source's initial distance bits
  std::uint32_t label;
};

template <class = void>
GEOVORONOI_KERNEL void label_seed_kernel(const unsigned long long* words, unsigned int* labels,
                                         const label_seed* seeds, int count) {
  for (int i = blockIdx.x * blockDim.x + threadIdx.x; i < count; i += gridDim.x * blockDim.x) {
    const label_seed s = seeds[i];
    if (words[s.voxel] == s.word) atomicMin(&labels[s.voxel], s.label);
  }
}

template <class P>
GEOVORONOI_KERNEL void label_sweep_kernel(P p, tiling t, const unsigned long long* words, unsigned int* labels,
                                          int* changed) {
  using T = typename P::value_type;
  constexpr int N = P::neighbours;
  const index_t n = t.voxels();
  for (index_t v = index_t(blockIdx.x) * blockDim.x + threadIdx.x; v < n; v += index_t(gridDim.x) * blockDim.x) {
    const unsigned long long dv = words[v];
    if (dv == unreached) continue;
    const index_t x = v % t.nx, r = v / t.nx, y = r % t.ny, z = r / t.ny;
    const T fv = p.field[v];
    unsigned int best = __ldcg(&labels[v]);
    const unsigned int before = best;
#pragma unroll
    for (int k = 0; k < N; ++k) {
      const index_t ux = x + p.edges.offset[k][0], uy = y + p.edges.offset[k][1], uz = z + p.edges.offset[k][2];
      if (!t.in_grid(ux, uy, uz)) continue;
      const index_t u = v + p.edges.delta[k];
      const unsigned long long du = words[u];
      if (du == unreached) continue;
      const T w = edge_weight(p, k, p.field[u], fv);
      if (distance_word(add_rn(word_distance<T>(du), w)) != dv) continue;
      const unsigned int lu = __ldcg(&labels[u]);
      if (lu < best) best = lu;
    }
    if (best < before) {
      atomicMin(&labels[v], best);
      *changed = 1;
    }
  }
}

/// Fills @p labels (all ones on entry) for the converged distance words.
template <class P>
void run_label_pass(const P& dp, const tiling& t, const unsigned long long* words, unsigned int* labels,
                    const std::vector<label_seed>& seeds, cudaStream_t stream) {
  device_buffer<label_seed> dseeds(seeds.size());
  dseeds.upload(seeds.data(), seeds.size(), stream);
  device_buffer<int> changed(1);
  if (!seeds.empty()) {
    const int sb = int((seeds.size() + 255) / 256);
    label_seed_kernel<><<<sb < 1024 ? sb : 1024, 256, 0, stream>>>(words, labels, dseeds.data(), int(seeds.size()));
    GEOVORONOI_CUDA_CHECK_LAUNCH("label_seed_kernel");
  }
  const index_t n = t.voxels();
  const int blocks = int((n + 255) / 256 < 65535 ? (n + 255) / 256 : 65535);
  for (;;) {
    changed.fill_bytes(0, stream);
    for (int i = 0; i < check_every; ++i) {
      label_sweep_kernel<P><<<blocks, 256, 0, stream>>>(dp, t, words, labels, changed.data());
      GEOVORONOI_CUDA_CHECK_LAUNCH("label_sweep_kernel");
    }
    int any = 0;
    changed.download(&any, 1, stream);
    sync(stream, "label pass");
    if (!any) break;
  }
}

}  // namespace geovoronoi::cuda::detail
