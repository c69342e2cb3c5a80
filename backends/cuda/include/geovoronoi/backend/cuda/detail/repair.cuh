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
  const index_t n = t.voxels();
  for (index_t v = index_t(blockIdx.x) * blockDim.x + threadIdx.x; v < n; v += index_t(gridDim.x) * blockDim.x) {
    const unsigned long long dv = words[v];
    if (dv == unreached) continue;
    const unsigned int before = __ldcg(&labels[v]);
    const unsigned int best =
        realising_label(p, t, words, v, dv, before, [labels](index_t u) { return __ldcg(&labels[u]); });
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
