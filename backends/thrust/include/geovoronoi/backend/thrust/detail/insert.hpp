#pragma once
// Batched insert-query. Each query's search is small (its new cell) and independent of the others,
// so on host systems the batch is split into blocks run in parallel, each block running the
// sequential engine query after query with scratch bounded by the cell (the same code, hence the
// same bits, as geovoronoi::seq). On the CUDA system each query runs the near-far engine on device
// arrays, pruned by the diagram's distances.

#include <geovoronoi/backend/thrust/detail/solve.hpp>
#include <geovoronoi/detail/search/key.hpp>
#include <geovoronoi/detail/search/radix_heap.hpp>
#include <geovoronoi/detail/search/engine.hpp>
#include <geovoronoi/detail/search/sparse.hpp>
#include <geovoronoi/result.hpp>

#include <algorithm>
#include <exception>
#include <utility>
#include <vector>

namespace geovoronoi::thrust::detail {

/// One block of queries on the host, one after the other.
template <class P>
struct query_block_fn {
  using T = typename P::value_type;
  const P* p;
  const diagram<T, P::dim>* d;
  const index_t* queries;
  index_t count;
  index_t block;
  query_cells<T>* out;
  std::exception_ptr* error;

  void operator()(index_t b) const {
    query_cells<T>& o = out[b];
    try {
      // the sequential engine's paged sparse search, one scratch per block (its page table costs one
      // pointer per 64 voxels of the grid)
      search::sparse_scratch<T> s;
      const index_t end = std::min(count, (b + 1) * block);
      search::insert_queries(*p, s.keys, s.heap, *d, queries + b * block, std::size_t(end - b * block), o);
    } catch (...) {
      error[b] = std::current_exception();
    }
  }
};

template <class T>
struct below_old {
  const T* dist;
  GEOVORONOI_HOST_DEVICE bool operator()(index_t v, T nd) const { return nd < dist[v]; }
};

template <class Exec, class P>
query_cells<typename P::value_type> insert_queries(const Exec& exec, const P& p,
                                                   const diagram<typename P::value_type, P::dim>& d,
                                                   const std::vector<index_t>& queries, index_t target,
                                                   engine_counts& counts) {
  using T = typename P::value_type;
  query_cells<T> out;
  const index_t nq = static_cast<index_t>(queries.size());
  if constexpr (!is_cuda_policy_v<Exec>) {
    (void)target;
    counts = {};
    // blocks small enough to balance uneven cells, large enough to reuse scratch
    const index_t block = std::max<index_t>(1, std::min<index_t>(64, nq / 64));
    const index_t blocks = (nq + block - 1) / block;
    std::vector<query_cells<T>> parts(static_cast<std::size_t>(blocks));
    std::vector<std::exception_ptr> errors(static_cast<std::size_t>(blocks));
    for (auto& part : parts) part.offsets = {0};
    parallel_for(exec, blocks, query_block_fn<P>{&p, &d, queries.data(), nq, block, parts.data(), errors.data()},
                 nq * 64, false);
    for (const auto& e : errors)
      if (e) std::rethrow_exception(e);
    std::size_t total = 0;
    for (const auto& part : parts) total += part.voxel.size();
    out.query.reserve(queries.size());
    out.offsets.reserve(queries.size() + 1);
    out.voxel.reserve(total);
    out.distance.reserve(total);
    out.owner.reserve(total);
    for (const auto& part : parts) out.append(part);
    return out;
  } else {
#ifdef __CUDACC__
    using kt = search::key_traits<T>;
    const index_t n = p.geometry.size();
    vec<Exec, T> old(d.distance.data(), d.distance.data() + n);
    dense_state<Exec, T> st;
    counts = {};
    for (const index_t q : queries) {
      const T dq = d.distance[q];
      seed(exec, st, n, std::vector<source<T>>{{q, T(0), 0}}, [dq](const source<T>&) { return T(0) < dq; });
      const auto c = run(exec, p, raw(st.keys), raw(st.flags), st.far, st.far_size, below_old<T>{raw(old)}, target);
      counts.expansions += c.expansions;
      counts.rounds += c.rounds;
      counts.splits += c.splits;
      const auto cell = extract(exec, raw(st.keys), n);
      query_cells<T> one;
      one.query = {q};
      one.offsets = {0, cell.size()};
      one.voxel = cell.voxel;
      one.distance = cell.distance;
      for (const index_t v : cell.voxel) one.owner.push_back(d.label[v]);
      out.append(one);
      (void)kt::unreached;
    }
    return out;
#endif
  }
}

}  // namespace geovoronoi::thrust::detail
