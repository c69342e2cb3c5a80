#pragma once
// The sequential backend's batched insert-query: the shared engine's sparse search (detail/search/),
// one query after the other in one scratch, each touching its new cell and the cell's rim only.

#include <geovoronoi/detail/search/sparse.hpp>
#include <geovoronoi/result.hpp>

#include <vector>

namespace geovoronoi::detail::seq {

/// New cells of @p queries in @p d, in query order.
template <class P, class Scratch>
query_cells<typename P::value_type> insert_queries(const P& p, Scratch& scratch,
                                                   const diagram<typename P::value_type, P::dim>& d,
                                                   const std::vector<index_t>& queries) {
  query_cells<typename P::value_type> out;
  out.query.reserve(queries.size());
  out.offsets.reserve(queries.size() + 1);
  search::insert_queries(p, scratch.keys, scratch.heap, d, queries.data(), queries.size(), out);
  return out;
}

}  // namespace geovoronoi::detail::seq
