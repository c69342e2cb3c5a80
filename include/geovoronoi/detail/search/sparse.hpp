#pragma once
// The shared engine's sparse searches: radius-bounded multi-source solves and insert-query.
// Both run the engine's Dijkstra loop (engine.hpp) with keys in a scratch that holds only what the
// search visits, and emit their voxels in increasing index order. The scratch is a template
// parameter (paged_keys, with the page size a parameter for the benchmarks).

#include <geovoronoi/detail/search/key.hpp>
#include <geovoronoi/detail/search/paged_scratch.hpp>
#include <geovoronoi/detail/search/radix_heap.hpp>
#include <geovoronoi/detail/search/engine.hpp>
#include <geovoronoi/detail/overflow.hpp>
#include <geovoronoi/result.hpp>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace geovoronoi::detail::search {

/**
 * Keys in pages of 2^PageBits voxels (paged_scratch); field values read from the problem (copying
 * them into the pages measured slower: most look-ups stop at the key). A page is filled when the
 * search first looks at one of its voxels, each key with the bound a candidate must beat there:
 * (radius, 0) for a bounded solve, (d(v), 0) for insert-query, whose candidates carry label 1. A
 * candidate (nd, l) is then smaller than the initial key exactly when nd is below the bound, so the
 * engine's pre-check skips a voxel the search may not enter before it evaluates the metric, the
 * voxels reached are those whose key changed, and a search's cost and memory follow what it visits.
 */
template <class T, int PageBits = 6>
struct paged_keys {
  using kt = key_traits<T>;
  using key_type = typename kt::key_type;
  static constexpr label_t query_label = 1;
  paged_scratch<key_type, PageBits> pages;
  const T* f = nullptr;
  const T* bound = nullptr;  // insert-query: the diagram's distances; bounded solve: null
  key_type radius_key{};

  void begin_bounded(const T* field, index_t n, T radius) {
    f = field;
    bound = nullptr;
    radius_key = kt::make(radius, 0);
    pages.prepare(n);
  }
  void begin_queries(const T* field, index_t n, const T* distance) {
    f = field;
    bound = distance;
    pages.prepare(n);
  }
  /// Insert-query needs no filter: the initial keys prune exactly.
  auto query_filter() const noexcept {
    return [](index_t, T) { return true; };
  }

  key_type& at(index_t v) {
    return pages.touch(v, [this](index_t first, key_type* page, index_t count) { fill(first, page, count); });
  }
  key_type get(index_t v) { return at(v); }
  void set(index_t v, key_type k) { at(v) = k; }
  T field(index_t v) const noexcept { return f[v]; }
  template <class Stencil>
  void prefetch(index_t, const Stencil&) const noexcept {}

  /// Calls out(v, key) for every voxel reached, by increasing v, and empties the scratch.
  template <class Out>
  void drain_sorted(Out&& out) {
    if (bound) {
      pages.for_each_page_sorted([&](index_t first, const key_type* page, index_t count) {
        for (index_t i = 0; i < count; ++i)
          if (kt::label(page[i]) == query_label) out(first + i, page[i]);
      });
    } else {
      pages.for_each_page_sorted([&](index_t first, const key_type* page, index_t count) {
        for (index_t i = 0; i < count; ++i)
          if (page[i] != radius_key) out(first + i, page[i]);
      });
    }
    pages.clear();
  }

 private:
  void fill(index_t first, key_type* page, index_t count) const {
    if (bound) {
      // a bound that is not > 0 (a diagram's +0, or a foreign -0, negative or NaN) admits no
      // candidate, as nd < bound would not
      const T* b = bound + first;
      for (index_t i = 0; i < count; ++i) {
        page[i] = b[i] > T(0) ? kt::make(b[i], 0) : key_type{};
      }
    } else {
      for (index_t i = 0; i < count; ++i) {
        page[i] = radius_key;
      }
    }
  }
};

/// The scratch of one thread's series of sparse searches: keys and queue, reused from one to the next.
template <class T, class Keys = paged_keys<T>>
struct sparse_scratch {
  Keys keys;
  radix_heap<T> heap;
};

/// Bounded multi-source solve: the voxels with distance < @p radius, sorted by voxel. A search that is
/// interrupted (cancelled, an overflow, an exception) leaves @p st and @p heap ready for the next one.
template <class P, class Keys, class Heap>
sparse_solution<typename P::value_type> bounded(const P& p, Keys& st, Heap& heap,
                                                const std::vector<source<typename P::value_type>>& sources,
                                                typename P::value_type radius, const solve_control& ctl = {}) {
  using T = typename P::value_type;
  using kt = key_traits<T>;
  st.begin_bounded(p.field, node_count(p), radius);
  heap.clear();
  solve_monitor mon{&ctl, ctl.reporting() ? double(count_inside(p)) : 1.0};
  std::size_t reached = 0;
  try {
    ctl.report(0.0);
    reached = run_from_sources(p, st, heap, sources, radius, mon);  // each reached voxel settles once
  } catch (...) {
    st.drain_sorted([](index_t, const typename kt::key_type&) {});
    heap.clear();
    throw;
  }
  sparse_solution<T> r;
  r.voxel.reserve(reached);
  r.distance.reserve(reached);
  r.label.reserve(reached);
  st.drain_sorted([&](index_t v, const typename kt::key_type& k) {
    r.voxel.push_back(v);
    r.distance.push_back(kt::distance(k));
    r.label.push_back(kt::label(k));
  });
  if (mon.overflowed && !(radius <= std::numeric_limits<T>::max()))
    throw_if_overflowed_sparse(p, r.voxel.data(), r.distance.data(), r.size());
  ctl.report(1.0);
  return r;
}

/// Sizes @p out for @p count queries from the cells of the first @p done (which start at entry
/// @p first): one allocation of about the right size instead of a series of doublings, each copying
/// and faulting in the output again (a batch's output can reach gigabytes).
template <class T>
void reserve_for(query_cells<T>& out, std::size_t first, std::size_t done, std::size_t count) {
  const double per_query = double(out.voxel.size() - first) / double(done);
  const auto want = first + std::size_t(per_query * double(count) * 1.125) + 1;
  if (want <= out.voxel.capacity()) return;
  out.voxel.reserve(want);
  out.distance.reserve(want);
  out.owner.reserve(want);
}

/**
 * New cells of @p queries in diagram @p d, one after the other, appended to @p out (query, offsets,
 * voxel, distance, owner). The cell of q is the voxels v with d_q(v) < d(v): the search from q is
 * pruned by the diagram's distances, so it visits the cell and its one-voxel rim only.
 */
template <class P, class Keys, class Heap>
void insert_queries(const P& p, Keys& st, Heap& heap, const diagram<typename P::value_type, P::dim>& d,
                    const index_t* queries, std::size_t count, query_cells<typename P::value_type>& out) {
  insert_queries(p, st, heap, d.distance.data(), d.label.data(), queries, count, out);
}

/// The same for a diagram given as per-node distances and labels (any topology, topology.hpp).
template <class P, class Keys, class Heap>
void insert_queries(const P& p, Keys& st, Heap& heap, const typename P::value_type* dist, const label_t* lab,
                    const index_t* queries, std::size_t count, query_cells<typename P::value_type>& out) {
  using T = typename P::value_type;
  using kt = key_traits<T>;
  st.begin_queries(p.field, node_count(p), dist);
  const std::size_t first = out.voxel.size();
  const std::size_t sample = std::max<std::size_t>(16, count / 32);
  const auto start = kt::make(T(0), Keys::query_label);
  for (std::size_t i = 0; i < count; ++i) {
    const index_t q = queries[i];
    heap.clear();
    if (T(0) < dist[q]) {  // a query on a seed (distance 0) has an empty cell
      st.set(q, start);
      heap.push(start, q);
    }
    run(p, st, heap, st.query_filter());
    st.drain_sorted([&](index_t v, const typename kt::key_type& k) {
      out.voxel.push_back(v);
      out.distance.push_back(kt::distance(k));
      out.owner.push_back(lab[v]);
    });
    out.query.push_back(q);
    out.offsets.push_back(out.voxel.size());
    if (i + 1 == sample && i + 1 < count) reserve_for(out, first, i + 1, count);
  }
}

}  // namespace geovoronoi::detail::search
