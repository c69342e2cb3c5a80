#pragma once
// Sibson and Laplace coordinates from the new cells of query voxels (insert_queries, in batches).
// Per query the scratch is bounded by its cell and the number of nodes: the cell itself (returned by
// the backend, sorted by voxel) and per-node accumulators reset through a touched list.

#include <geovoronoi/detail/dispatch.hpp>
#include <geovoronoi/detail/hooks.hpp>
#include <geovoronoi/detail/parallel.hpp>
#include <geovoronoi/detail/search/fused_lanes.hpp>
#include <geovoronoi/detail/search/fused_padded.hpp>
#include <geovoronoi/detail/search/fused_query.hpp>
#include <geovoronoi/detail/search/padded_grid.hpp>
#include <geovoronoi/detail/search/radix_heap.hpp>
#include <geovoronoi/detail/search/scratch_pool.hpp>
#include <geovoronoi/detail/shape/common.hpp>
#include <geovoronoi/detail/shape/piecewise.hpp>
#include <geovoronoi/detail/shape/single_owner.hpp>
#include <geovoronoi/detail/shape/translation_invariant.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <cstdint>
#include <limits>
#include <thread>
#include <vector>

namespace geovoronoi::detail::shape {

using search::padded_grid;
using search::scratch_pool;

/// Whether voxel w is in the cell whose sorted voxels are cell[0, size), knowing cell[j] = w - delta.
/// Entries are distinct and sorted, so at most |delta| - 1 of them lie strictly between the two.
inline bool in_sorted_cell(const index_t* cell, std::size_t size, std::size_t j, index_t delta, index_t w) {
  if (delta > 0) {
    const std::size_t hi = std::min(size, j + 1 + std::size_t(delta));
    return std::binary_search(cell + j + 1, cell + hi, w);
  }
  const std::size_t span = std::size_t(-delta);
  const std::size_t lo = j > span ? j - span : 0;
  return std::binary_search(cell + lo, cell + j, w);
}

/**
 * Raw Laplace and Sibson weights of one query from its accumulators. Writes candidates (node, raw > 0)
 * to @p out.
 *
 * Sibson: raw_k = (voxels stolen from k) * voxel volume.
 * Laplace: raw_k = s_k / h_k over the facet pairs (v in C_q, w face neighbour of v in the domain, not
 * in C_q, label(w) = k); s_k = sum over axes of (faces of that axis) * face area; h_k = min of
 * (d_q(v) + c(v, w)) + d(w) evaluated in T. If some h_k is 0 (zero-weight edges) those nodes share the
 * weight in proportion to s_k. If the cell has no facet at all, Laplace falls back to Sibson.
 */
template <class P>
void finish_weights(const P& p, const std::vector<face<P::dim>>& faces, bool laplace, bool any_facet,
                    const accumulators& acc, std::vector<candidate>& out) {
  out.clear();
  if (laplace && any_facet) {
    double area[3] = {0, 0, 0};
    for (const auto& f : faces) area[f.axis] = f.area;
    bool zero_h = false;
    for (label_t k : acc.touched) {
      const auto& n = acc.faces[k];
      if ((n[0] | n[1] | n[2]) != 0 && acc.h[k] == 0) zero_h = true;
    }
    for (label_t k : acc.touched) {
      const auto& n = acc.faces[k];
      double s = 0;
      for (int a = 0; a < P::dim; ++a) s += double(n[a]) * area[a];
      if (!(s > 0)) continue;
      if (zero_h) {
        if (acc.h[k] == 0) out.push_back({k, s});
      } else {
        out.push_back({k, s / acc.h[k]});
      }
    }
  } else {
    const double vv = p.geometry.voxel_volume();
    for (label_t k : acc.touched)
      if (acc.volume[k] > 0) out.push_back({k, double(acc.volume[k]) * vv});
  }
}

/// Fills the accumulators of one query from its new cell as a backend returns it (voxels sorted,
/// their query distances and owners); returns whether the cell has a facet pair.
template <class P, class D>
bool accumulate_cell(const P& p, const D& d, const std::vector<face<P::dim>>& faces, bool laplace,
                     const index_t* cell, const typename P::value_type* dq, const label_t* owner, std::size_t size,
                     accumulators& acc) {
  using T = typename P::value_type;
  acc.clear();
  for (std::size_t j = 0; j < size; ++j) {
    const label_t o = owner[j];
    if (o < 0) continue;
    acc.touch(o);
    ++acc.volume[o];
  }
  bool any_facet = false;
  if (!laplace) return false;
  const T* dist = d.distance.data();
  const label_t* lab = d.label.data();
  for (std::size_t j = 0; j < size; ++j) {
    auto in_cell = [&](index_t w, const face<P::dim>& f) { return in_sorted_cell(cell, size, j, f.delta, w); };
    if (search::add_facets(p, cell[j], dq[j], faces, lab, dist, in_cell, acc)) any_facet = true;
  }
  return any_facet;
}

/// Morton (Z-order) code of voxel coordinates: the bits of the axes interleaved, x lowest. Only the low
/// 21 bits of each coordinate are used; voxels that differ above them tie, and a stable sort keeps
/// their input order.
template <class C>
std::uint64_t morton_code(const C& c) {
  std::uint64_t m = 0;
  for (int b = 0; b < 21; ++b)
    for (std::size_t a = 0; a < c.size(); ++a)
      m |= ((std::uint64_t(c[a]) >> b) & 1u) << (std::size_t(b) * c.size() + a);
  return m;
}

/// Per-worker scratch of the query loops.
template <class T>
struct query_scratch {
  accumulators acc;
  std::vector<candidate> cand;
  std::vector<unsigned char> mask;
  cell_members<T> members;
  explicit query_scratch(std::size_t nodes) : acc(nodes) {}
  /// Bytes of the per-node accumulators (volume, faces, h, seen, touched).
  std::size_t accumulator_bytes() const noexcept {
    return acc.volume.capacity() * (sizeof(std::int64_t) * 4 + sizeof(double) + 1 + sizeof(label_t));
  }
};

/// Queries per task of the host-parallel loops: enough to amortise a task's scratch, few enough to
/// balance cells of very different sizes.
inline constexpr std::size_t queries_per_task = 64;

/// One worker of the fused query loop: its search scratch (search::fused_query, or
/// search::fused_query_padded on the fast path) and its accumulators.
template <class P, class Search>
struct fused_worker {
  Search search;
  query_scratch<typename P::value_type> s;
  std::size_t peak = 0;  // largest bytes() seen
  template <class... A>
  fused_worker(std::size_t nodes, A&&... a) : search(std::forward<A>(a)...), s(nodes) {}
  std::size_t bytes() const noexcept {
    return search.bytes() + s.accumulator_bytes();
  }
  /// Runs queries[b, e), one search each, writing each row; returns the voxels visited.
  template <class Face, class Write>
  std::size_t run(const std::vector<index_t>& queries, std::size_t b, std::size_t e, const index_t* voxel_of,
                  bool laplace, const std::vector<Face>& faces, Write& write) {
    std::size_t sum = 0;
    for (std::size_t i = b; i < e; ++i) {
      std::size_t visited = 0;
      const bool any_facet = search.run(voxel_of[queries[i]], laplace, faces, s.acc, visited);
      write(queries[i], s, any_facet);
      sum += visited;
    }
    peak = std::max(peak, bytes());
    return sum;
  }
};

#ifdef GEOVORONOI_FUSED_LANES
/// A worker of the lane search (fused_lanes.hpp, L lanes): consecutive queries share a search.
template <class P, int L>
struct fused_lanes_worker {
  using search_type = search::fused_lanes_padded<P, L, piecewise_tables<P>>;
  static constexpr int lanes = L;
  /// Queries per task: four searches, the first of which is the progress estimate's sample (a sample
  /// of one query would run a search of one lane, about three times the cost per query). Small tasks
  /// keep the end of the loop short: the thread that finishes first waits for at most the other's
  /// last task (docs/shape-functions.md).
  static constexpr std::size_t queries_per_task = 4 * lanes;
  search_type search;
  std::vector<query_scratch<typename P::value_type>> s;  // one per lane
  std::size_t peak = 0;
  fused_lanes_worker(std::size_t nodes, const P& p, const padded_grid<P>& g, const piecewise_tables<P>* pw, bool avx512)
      : search(p, g, pw, avx512), s(std::size_t(lanes), query_scratch<typename P::value_type>(nodes)) {}
  std::size_t bytes() const noexcept {
    return search.bytes() + lanes * s[0].accumulator_bytes();
  }
  template <class Face, class Write>
  std::size_t run(const std::vector<index_t>& queries, std::size_t b, std::size_t e, const index_t* voxel_of,
                  bool laplace, const std::vector<Face>& faces, Write& write) {
    std::size_t sum = 0;
    index_t q[lanes];
    accumulators* acc[lanes];
    bool any_facet[lanes];
    std::size_t visited[lanes];
    for (int j = 0; j < lanes; ++j) acc[j] = &s[std::size_t(j)].acc;
    for (std::size_t i = b; i < e; i += lanes) {
      const int n = int(std::min<std::size_t>(lanes, e - i));
      for (int j = 0; j < n; ++j) q[j] = voxel_of[queries[i + std::size_t(j)]];
      search.run(q, n, laplace, faces, acc, any_facet, visited);
      for (int j = 0; j < n; ++j) {
        write(queries[i + std::size_t(j)], s[std::size_t(j)], any_facet[j]);
        sum += visited[j];
      }
    }
    peak = std::max(peak, bytes());
    return sum;
  }
};
#endif

/// The one-query searches, with the exact balls of constant regions.
template <class P>
using grid_search = search::fused_query<P, piecewise_tables<P>>;
template <class P>
using padded_search = search::fused_query_padded<P, piecewise_tables<P>>;

/// Bytes one fused worker is budgeted: its key array, room for a cell list of the whole grid and a
/// queue of half the grid (cells stay far below that on real problems), the per-node accumulators.
/// On the padded fast path (fused_padded.hpp) the shared (bound, label) table is counted here too, so
/// that one worker's budget always covers everything a call needs besides the exact-ball tables.
template <class P>
std::size_t fused_worker_budget(const P& p, std::size_t nodes) {
  using T = typename P::value_type;
  const std::size_t n = std::size_t(p.geometry.size());
  if (padded_grid<P>::applies(p))
    return padded_search<P>::dense_bytes(p) + padded_grid<P>::shared_bytes(p) + n * sizeof(std::uint32_t) +
           n / 2 * padded_search<P>::heap_item_bytes() + nodes * 64 + 65536;
  return grid_search<P>::dense_bytes(p) + n * sizeof(index_t) + n / 2 * sizeof(typename search::radix_heap<T>::item) +
         nodes * 64 + 65536;
}

#ifdef GEOVORONOI_FUSED_LANES
/// Bytes one lane worker is budgeted (besides the shared tables): its dense arrays, room for a touched
/// list of the whole grid (twice: Laplace sorts it) and a queue of half of it, the accumulators of its
/// lanes and its per-owner rows (volume counts, the AVX-512 facet pass's vectors).
template <int L, class P>
std::size_t fused_lanes_worker_bytes(const P& p, std::size_t nodes) {
  using S = typename fused_lanes_worker<P, L>::search_type;
  const std::size_t n = std::size_t(p.geometry.size());
  return S::dense_bytes(p) + 2 * n * sizeof(std::uint32_t) + n / 2 * S::heap_item_bytes() +
         std::size_t(L) * (nodes * 64 + 4096) + nodes * S::per_node_bytes() + 65536;
}

/// Whether Sibson/Laplace on problem @p p with @p policy run the lane search (fused_lanes.hpp)
/// given the memory budget (queries then go in Morton order, so that a search's lanes are neighbours).
template <class Policy, class P>
bool uses_fused_lanes(const P& p, std::size_t nodes, std::size_t budget) {
  if constexpr (hooks::queries_on_host<Policy>::value && search::fused_lanes_apply<P>::value) {
    // (the lanes count cell volumes in 32 bits: grids below 2^31 voxels)
    return padded_grid<P>::applies(p) && p.geometry.size() < (index_t(1) << 31) && !translation_invariant(p) &&
           budget >= fused_lanes_worker_bytes<16>(p, nodes) + padded_grid<P>::shared_bytes(p);
  } else {
    return false;
  }
}
#else
template <class Policy, class P>
bool uses_fused_lanes(const P&, std::size_t, std::size_t) { return false; }
#endif

/// Whether queries (rows, voxels voxel_of[row]) in this order are clustered enough for the lane
/// search: at least half of the consecutive pairs are at most 2 voxels apart in every axis. A search
/// of lanes whose cells do not overlap costs about as much per lane as one search each, and a
/// lane of a sparse set (1000 points scattered over a volume) shares almost nothing with its neighbours.
template <class P>
bool clustered_queries(const P& p, const std::vector<index_t>& queries, const index_t* voxel_of) {
  if (queries.size() < 2) return false;
  std::size_t close = 0;
  auto prev = p.geometry.coords(voxel_of[queries[0]]);
  for (std::size_t i = 1; i < queries.size(); ++i) {
    const auto c = p.geometry.coords(voxel_of[queries[i]]);
    index_t far = 0;
    for (int a = 0; a < P::dim; ++a) far = std::max(far, c[a] > prev[a] ? c[a] - prev[a] : prev[a] - c[a]);
    close += far <= 2;
    prev = c;
  }
  return 2 * close >= queries.size() - 1;
}

/// The query loop of fused_natural_neighbours over a pool of workers (either search), in tasks of
/// @p group consecutive queries whose first @p sampled run first (the progress estimate's sample).
template <class Policy, class Options, class Face, class Write, class Pool>
void fused_query_loop(const Policy& policy, const Options& opt, bool laplace, const std::vector<Face>& faces,
                      const std::vector<index_t>& queries, const index_t* voxel_of, Write&& write, Pool& pool,
                      std::size_t shared, std::size_t group, std::size_t sampled) {
  const std::size_t total = queries.size();
  const std::size_t groups = (total + group - 1) / group;
  auto begin = [&](std::size_t g) { return g * group; };
  auto split = [&](std::size_t g) { return std::min(total, g * group + sampled); };  // end of g's sample
  auto end = [&](std::size_t g) { return std::min(total, (g + 1) * group); };
  std::vector<std::size_t> sample(groups, 0);  // cell sizes of each group's sampled queries, summed
  std::atomic<std::size_t> visited_total{0};
  // 1. the sample: the first queries of every group, in tasks of as many queries as a group runs (64
  // one-query searches, or 4 lane searches), so that no thread waits long for the other's last task.
  // Until it is done the total is unknown: the fraction reported is that of the queries sampled (the
  // sample's share of the visits, estimated by the sample itself), by the calling thread after a task
  // of its own once a batch of queries has been sampled since its last report.
  const std::size_t groups_per_sample_task = std::max<std::size_t>(1, group / std::max<std::size_t>(1, sampled));
  const std::thread::id caller = std::this_thread::get_id();
  double last = 0;  // the last fraction reported: reports never go back
  std::atomic<std::size_t> sampled_done{0};
  std::size_t sampled_reported = 0;
  host_parallel_for(policy, index_t((groups + groups_per_sample_task - 1) / groups_per_sample_task), [&](index_t t) {
    std::size_t ran = 0;
    {
      auto wk = pool.acquire();  // back in the pool before the callback runs
      const std::size_t b = std::size_t(t) * groups_per_sample_task, e = std::min(groups, b + groups_per_sample_task);
      std::size_t sum = 0;
      for (std::size_t g = b; g < e; ++g) {
        sum += sample[g] = wk->run(queries, begin(g), split(g), voxel_of, laplace, faces, write);
        ran += split(g) - begin(g);
      }
      visited_total += sum;
    }
    const std::size_t done = sampled_done += ran;
    if (std::this_thread::get_id() == caller && done - sampled_reported >= opt.batch_size) {
      sampled_reported = done;
      last = std::max(last, double(done) / double(total));
      report(opt.progress, last);
    }
  });
  // estimated work of the queries not yet run, group by group: the sample's mean cell size each
  auto estimate = [&](std::size_t g) {
    return double(sample[g]) / double(split(g) - begin(g)) * double(end(g) - split(g));
  };
  double remaining = 0;  // the estimates of all groups (step 2 subtracts those done)
  for (std::size_t g = 0; g < groups; ++g) remaining += estimate(g);
  std::atomic<double> estimated_done{0};  // the estimates of the groups done in step 2 so far
  auto progress_now = [&] {
    const double done = double(visited_total.load());
    const double left = std::max(0.0, remaining - estimated_done.load());
    last = std::max(last, done + left > 0 ? done / (done + left) : 1.0);
    report(opt.progress, last);
  };
  progress_now();
  // 2. the rest, in one loop over the groups (consecutive queries are neighbours: their searches share
  // the cache). The calling thread reports progress, and so checks for cancellation, after a task of its
  // own once the groups done since its last report hold a batch of queries, so no thread waits for the
  // other's last task at a report (a barrier per batch would idle every thread but the last at each one).
  // A cancellation thrown there skips the tasks not yet started (host_parallel_for).
  const std::size_t groups_per_batch = std::max<std::size_t>(1, opt.batch_size / group);
  std::atomic<std::size_t> groups_done{0};
  std::size_t reported = 0;  // groups done at the last report
  host_parallel_for(policy, index_t(groups), [&](index_t t) {
    const std::size_t g = std::size_t(t);
    {
      auto wk = pool.acquire();  // back in the pool before the callback runs
      visited_total += wk->run(queries, split(g), end(g), voxel_of, laplace, faces, write);
    }
    double e = estimated_done.load();
    while (!estimated_done.compare_exchange_weak(e, e + estimate(g))) {
    }
    const std::size_t done = ++groups_done;
    if (std::this_thread::get_id() == caller && done - reported >= groups_per_batch && done < groups) {
      reported = done;
      progress_now();
    }
  });
  remaining = 0;
  estimated_done = 0;
  progress_now();  // 1: nothing remains
  if (opt.stats) {
    std::size_t peak = 0;
    pool.for_each([&](const auto& wk) { peak += wk.peak; });
    opt.stats->workers = pool.created();
    opt.stats->peak_scratch_bytes = peak + shared;
    opt.stats->voxels_visited = visited_total.load();
    opt.stats->queries = total;
  }
}

/**
 * Sibson/Laplace on a host backend: 32 or 16 queries per search (fused_lanes.hpp) where it applies and
 * the budget holds one such worker, else one fused search per query (fused_padded.hpp where it applies,
 * else fused_query.hpp); run in tasks of consecutive queries on the backend's host threads, with as
 * many worker scratches alive as memory_budget holds. Progress is reported as voxels visited over an
 * estimate of the total: the first search of every task runs first (a systematic sample), and each
 * task's remaining queries are estimated at its sample's mean cell size.
 */
template <class Policy, class P, class D, class Options, class Write>
void fused_natural_neighbours(const Policy& policy, const P& p, const D& d, const Options& opt, bool laplace,
                              std::size_t nodes, const std::vector<index_t>& queries, const index_t* voxel_of,
                              bool lanes, Write&& write) {
  using T = typename P::value_type;
  (void)lanes;  // without SSE there is only the one-query search
  const auto faces = faces_of(p);
  const std::size_t per_worker = fused_worker_budget(p, nodes);
  if (opt.memory_budget < per_worker)
    throw std::invalid_argument("geovoronoi::shape_functions: memory_budget is " + std::to_string(opt.memory_budget) +
                                " bytes, but one query worker on this grid needs " + std::to_string(per_worker));
  const T* dist = d.distance.data();
  const label_t* lab = d.label.data();
  // exact balls on constant regions (piecewise.hpp): a few small table solves, 3 bytes per voxel
  std::unique_ptr<piecewise_tables<P>> pw;
  if (opt.reuse_constant_regions) {
    pw = std::make_unique<piecewise_tables<P>>(policy, p);
    if (pw->empty() || pw->bytes() + per_worker > opt.memory_budget) pw.reset();
  }
  if (padded_grid<P>::applies(p)) {
    // the fast path: the shared table is part of per_worker (fused_worker_budget), counted once here
    const padded_grid<P> g(p, dist, lab);
#ifdef GEOVORONOI_FUSED_LANES
    if constexpr (search::fused_lanes_apply<P>::value) {
      // several queries per search (fused_lanes.hpp) where the budget holds one such worker: 32 where it
      // holds as many workers of 32 lanes as the threads would use of 16 (a worker of 32 lanes holds
      // 128 bytes of keys per voxel, of 16 lanes 64; 32 lanes cost less per query, but one worker where
      // two threads could each run one costs about twice the time), else 16
      const std::size_t fixed = (pw ? pw->bytes() : 0) + g.bytes();
      const std::size_t each16 = fused_lanes_worker_bytes<16>(p, nodes), each32 = fused_lanes_worker_bytes<32>(p, nodes);
      if (lanes && opt.memory_budget >= fixed + each16) {
        const std::size_t room = opt.memory_budget - fixed;
        const std::size_t threads = host_threads(policy);
        const int forced = opt.tuning.lanes;
        const bool wide = forced ? forced == 32 && room >= each32 : room / each32 >= std::min(room / each16, threads);
        auto run = [&](auto width) {
          constexpr int L = decltype(width)::value;
          const std::size_t each = L == 32 ? each32 : each16;
          scratch_pool<fused_lanes_worker<P, L>> pool(room / each, [&] {
            return std::make_unique<fused_lanes_worker<P, L>>(nodes, p, g, pw.get(), opt.tuning.avx512);
          });
          fused_query_loop(policy, opt, laplace, faces, queries, voxel_of, write, pool, fixed,
                           fused_lanes_worker<P, L>::queries_per_task, L);
        };
        if (wide)
          run(std::integral_constant<int, 32>());
        else
          run(std::integral_constant<int, 16>());
        return;
      }
    }
#endif
    const std::size_t shared = (pw ? pw->bytes() : 0) + g.bytes();
    const std::size_t room = opt.memory_budget - (pw ? pw->bytes() : 0);
    const std::size_t each = per_worker - padded_grid<P>::shared_bytes(p);
    scratch_pool<fused_worker<P, padded_search<P>>> pool((room - std::min(room, g.bytes())) / each, [&] {
      return std::make_unique<fused_worker<P, padded_search<P>>>(nodes, p, g, pw.get());
    });
    fused_query_loop(policy, opt, laplace, faces, queries, voxel_of, write, pool, shared, queries_per_task, 1);
  } else {
    const std::size_t shared = pw ? pw->bytes() : 0;
    scratch_pool<fused_worker<P, grid_search<P>>> pool((opt.memory_budget - shared) / per_worker, [&] {
      return std::make_unique<fused_worker<P, grid_search<P>>>(nodes, p, dist, lab, pw.get());
    });
    fused_query_loop(policy, opt, laplace, faces, queries, voxel_of, write, pool, shared, queries_per_task, 1);
  }
}

/// Bytes of a batch of materialised cells.
template <class T>
std::size_t cells_bytes(const query_cells<T>& c) {
  return c.voxel.capacity() * sizeof(index_t) + c.distance.capacity() * sizeof(T) +
         c.owner.capacity() * sizeof(label_t) + (c.query.capacity() + c.offsets.capacity()) * sizeof(index_t);
}

template <class Policy, class P, class D, class Options>
void natural_neighbour_rows(const Policy& policy, const P& p, const D& d, const Options& opt, bool laplace,
                            const index_t* voxel_of, std::size_t rows, int k, std::size_t nodes, label_t* node,
                            typename P::value_type* weight);

/**
 * Sibson: writes the row (1 for the query's node) of every query in @p queries whose new cell provably
 * holds no voxel of another node, and removes it from @p queries; returns how many. A short search per
 * query (single_owner_filter::may_share) decides most; the undecided ones run natural_neighbour_rows
 * on the filter's restricted bounds, where a row of one node is the true row. Every 16th query is
 * decided first; when none of them needed a search and kept to its own cell, the others are only
 * checked for U(q) = 0 (the filter would cost more than it saves). Does nothing when the
 * queries are fewer than 1/64 of the grid (the filter's budget search costs about one solve), when a
 * row of one node would not be exactly 1 (raw = count * voxel volume must be a positive finite
 * double), when the memory budget cannot hold the filter, or when an edge weighs less than 0.
 */
template <class Policy, class P, class D, class Options>
std::size_t write_single_owner_rows(const Policy& policy, const P& p, const D& d, const Options& opt,
                                    const index_t* voxel_of, int k, std::size_t nodes, label_t* node,
                                    typename P::value_type* weight, std::vector<index_t>& queries,
                                    std::size_t& restricted_rows, double& progress_done) {
  using T = typename P::value_type;
  using filter_t = single_owner_filter<P>;
  const double vv = p.geometry.voxel_volume();
  const index_t n = p.geometry.size();
  const std::size_t filter_bytes = std::size_t(n) * (sizeof(double) + 1) + filter_t::scratch_bytes(n);
  if (!opt.skip_single_owner_rows || queries.empty() || queries.size() < std::size_t(n) / 64 || !std::isnormal(vv) ||
      !std::isfinite(vv * double(n)) || filter_bytes > opt.memory_budget)
    return 0;
  std::size_t single_owner = 0;
  auto own_row = [&](index_t r) {
    node[std::size_t(r) * std::size_t(k)] = d.label[voxel_of[r]];
    weight[std::size_t(r) * std::size_t(k)] = T(1);
    ++single_owner;
  };
  const filter_t filter(p, d.distance.data(), d.label.data());
  if (filter.negative_weight()) return 0;  // every query searched: the search reports the weight
  using verdict = typename filter_t::verdict;
  std::vector<verdict> found(queries.size(), verdict::shares);
  const std::size_t workers = (opt.memory_budget - filter.bytes()) / filter_t::scratch_bytes(n);
  using scratch = typename filter_t::scratch;
  scratch_pool<scratch> pool(workers, [&] { return std::make_unique<scratch>(n); });
  constexpr std::size_t per_task = 256, stride = 16;
  const std::size_t max_pops = opt.tuning.single_owner_pops;
  D restricted;  // built when first needed
  // Decides the queries queries[i] for i in @p idx: own_only or shares in found[i].
  // The restricted searches below take the first half of the progress bar at most, in proportion to
  // the queries they may decide (the sample, then the rest), so that the bar moves while they run;
  // the searches after them report on what is left (natural_neighbour_rows).
  const double share = 0.5;
  auto decide = [&](const std::vector<std::size_t>& idx, double from, double to) {
    // 1. a short search per query: most that share find a witness within a few dozen voxels
    host_parallel_for(policy, index_t((idx.size() + per_task - 1) / per_task), [&](index_t t) {
      auto sc = pool.acquire();
      const std::size_t b = std::size_t(t) * per_task, e = std::min(idx.size(), b + per_task);
      for (std::size_t j = b; j < e; ++j) found[idx[j]] = filter.may_share(voxel_of[queries[idx[j]]], *sc, max_pops);
    });
    // 2. the undecided ones with the library's own search on the restricted bounds (it stays near the
    // paths to the frontier); a row of one node there is the true row
    std::vector<std::size_t> undecided;
    for (const std::size_t i : idx)
      if (found[i] == verdict::undecided) undecided.push_back(i);
    if (undecided.empty()) return;
    if (restricted.seeds.empty()) {
      restricted.label = d.label;
      restricted.distance = d.distance;
      filter.restricted_bounds(restricted.distance.data());
      restricted.seeds = d.seeds;
    }
    std::vector<index_t> rvox(undecided.size());
    for (std::size_t j = 0; j < undecided.size(); ++j) rvox[j] = voxel_of[queries[undecided[j]]];
    // two slots whatever K is: a second node in a row is what tells a shared cell (with K = 1 a shared
    // cell's row is also a single 1)
    constexpr int rk = 2;
    std::vector<label_t> rnode(undecided.size() * std::size_t(rk), no_label);
    std::vector<T> rweight(rnode.size(), T(0));
    Options ro = opt;
    ro.skip_single_owner_rows = false;
    ro.stats = nullptr;
    ro.progress = [&opt, from, to](double x) { return opt.progress ? opt.progress(from + (to - from) * x) : true; };
    ro.max_nodes_per_voxel = rk;
    natural_neighbour_rows(policy, p, restricted, ro, false, rvox.data(), rvox.size(), rk, nodes, rnode.data(),
                           rweight.data());
    for (std::size_t j = 0; j < undecided.size(); ++j) {
      const std::size_t at = j * std::size_t(rk);
      const bool own = rnode[at] == d.label[rvox[j]] && rnode[at + 1] == no_label;
      found[undecided[j]] = own ? verdict::own_only : verdict::shares;
      if (own) ++restricted_rows;
    }
  };
  // every 16th query first; when none of those that the backward search reached keeps to its own cell
  // (the beam: no query does), the other reached queries are searched as usual without being decided
  std::vector<std::size_t> sample, rest;
  for (std::size_t i = 0; i < queries.size(); ++i) (i % stride == 0 ? sample : rest).push_back(i);
  const double after_sample = share * double(sample.size()) / double(queries.size());
  decide(sample, 0.0, after_sample);
  progress_done = after_sample;
  bool gains = false;
  for (const std::size_t i : sample)
    gains = gains || (found[i] == verdict::own_only && filter.reached(voxel_of[queries[i]]));
  if (gains) {
    decide(rest, after_sample, share);
    progress_done = share;
  } else
    for (const std::size_t i : rest)
      if (!filter.reached(voxel_of[queries[i]])) found[i] = verdict::own_only;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    if (found[i] == verdict::own_only)
      own_row(queries[i]);
    else
      queries[kept++] = queries[i];
  }
  queries.resize(kept);
  return single_owner;
}

/**
 * Sibson (laplace = false) or Laplace weights of the voxels voxel_of[0, rows), row r written to slots
 * [r * k, r * k + k) of @p node and @p weight (which start empty: -1 and 0). A voxel may appear in
 * several rows; each row is computed on its own, with the same arithmetic as every other row.
 */
template <class Policy, class P, class D, class Options>
void natural_neighbour_rows(const Policy& policy, const P& p, const D& d, const Options& options, bool laplace,
                            const index_t* voxel_of, std::size_t rows, int k, std::size_t nodes, label_t* node,
                            typename P::value_type* weight) {
  using T = typename P::value_type;
  const auto faces = faces_of(p);
  std::vector<index_t> queries;  // rows whose weights come from a new cell
  for (std::size_t r = 0; r < rows; ++r) {
    const index_t v = voxel_of[r];
    const label_t l = d.label[v];
    if (l == no_label) continue;
    if (d.distance[v] > T(0)) {
      queries.push_back(index_t(r));
    } else {  // a node (or a voxel at distance 0 from it): its cell is empty, Kronecker delta
      node[r * std::size_t(k)] = l;
      weight[r * std::size_t(k)] = T(1);
    }
  }
  // Sibson: the rows of queries whose new cell provably stays in their own node's cell, written
  // without their search (single_owner.hpp); they leave `queries`
  std::size_t restricted = 0;
  double progress_done = 0.0;
  const std::size_t single_owner =
      laplace ? 0
              : write_single_owner_rows(policy, p, d, options, voxel_of, k, nodes, node, weight, queries, restricted,
                                        progress_done);
  // the searches below report on the part of the progress bar the single-owner step left
  Options opt = options;
  if (progress_done > 0.0 && options.progress)
    opt.progress = [&options, progress_done](double x) {
      return options.progress(progress_done + (1.0 - progress_done) * x);
    };
  if (opt.stats) {
    opt.stats->single_owner_rows = single_owner;
    opt.stats->single_owner_restricted = restricted;
  }
  // Rows of chosen points come in any order: run them in Morton (Z-curve) order of their voxels, so
  // that consecutive queries are near each other in all axes, their cells overlap and a search finds
  // much of its neighbourhood in the cache. Rows already in voxel order (the whole grid) keep it. Each
  // row is computed on its own, so the order changes no result.
  // The lane search wants Morton order always: its 32 lanes are then a 4x4x2 block of voxels, not
  // a row of 32, and their cells overlap far more.
  const bool lanes_fit = uses_fused_lanes<Policy>(p, nodes, opt.memory_budget);
  if (lanes_fit ||
      !std::is_sorted(queries.begin(), queries.end(), [&](index_t a, index_t b) { return voxel_of[a] < voxel_of[b]; })) {
    std::vector<std::pair<std::uint64_t, index_t>> order;
    order.reserve(queries.size());
    for (index_t r : queries) order.push_back({morton_code(p.geometry.coords(voxel_of[r])), r});
    std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (std::size_t i = 0; i < order.size(); ++i) queries[i] = order[i].second;
  }
  const bool lanes = lanes_fit && clustered_queries(p, queries, voxel_of);
  (void)lanes;  // used by host backends only
  const std::size_t total = queries.size();
  auto write = [&](index_t row, query_scratch<T>& s, bool any_facet) {
    finish_weights(p, faces, laplace, any_facet, s.acc, s.cand);
    const std::size_t at = std::size_t(row) * std::size_t(k);
    if (s.cand.empty()) {  // defensive: only a voxel at distance 0 has an empty cell
      node[at] = d.label[voxel_of[row]];
      weight[at] = T(1);
      return;
    }
    store(s.cand, k, node + at, weight + at);
  };
  // Each task owns its scratch and writes only its queries' slots.
  auto tasks = [](std::size_t count) { return index_t((count + queries_per_task - 1) / queries_per_task); };

  if (total > 0 && translation_invariant(p)) {
    // exact shortcut (translation_invariant.hpp): one backend solve, then every query is a box scan
    const offset_table<P> tab(policy, p);
    for (std::size_t start = 0; start < total; start += opt.batch_size) {
      const std::size_t end = std::min(total, start + opt.batch_size);
      host_parallel_for(policy, tasks(end - start), [&](index_t t) {
        query_scratch<T> s(nodes);
        const std::size_t b = start + std::size_t(t) * queries_per_task;
        const std::size_t e = std::min(end, b + queries_per_task);
        for (std::size_t i = b; i < e; ++i) {
          bool any_facet = false;
          accumulate_offset(tab, d, faces, laplace, voxel_of[queries[i]], s.acc, s.mask, s.members, any_facet);
          write(queries[i], s, any_facet);
        }
      });
      report(opt.progress, double(end) / double(total));
    }
    if (opt.stats) opt.stats->queries = total;
  } else if constexpr (hooks::queries_on_host<Policy>::value) {
    if (total > 0) fused_natural_neighbours(policy, p, d, opt, laplace, nodes, queries, voxel_of, lanes, write);
  } else {
    // a device backend: batches of materialised cells, as many queries per batch as the memory budget
    // allows at the cell sizes seen so far
    std::vector<index_t> batch;
    std::size_t bytes_per_query = 0, peak = 0, visited = 0;
    for (std::size_t start = 0; start < total;) {
      std::size_t size = opt.batch_size;
      if (bytes_per_query > 0) size = std::max<std::size_t>(1, std::min(size, opt.memory_budget / bytes_per_query));
      const std::size_t end = std::min(total, start + size);
      batch.clear();
      for (std::size_t i = start; i < end; ++i) batch.push_back(voxel_of[queries[i]]);
      const auto cells = dispatch::insert_queries(policy, p, d, batch);
      if (cells.size() != batch.size())
        throw std::logic_error("geovoronoi::shape_functions: the backend returned a cell count that differs from the batch");
      const std::size_t bytes = cells_bytes(cells);
      peak = std::max(peak, bytes);
      visited += cells.voxel.size();
      bytes_per_query = std::max(bytes_per_query, bytes / std::max<std::size_t>(1, end - start) + 1);
      host_parallel_for(policy, tasks(cells.size()), [&](index_t t) {
        query_scratch<T> s(nodes);
        const std::size_t b = std::size_t(t) * queries_per_task;
        const std::size_t e = std::min(cells.size(), b + queries_per_task);
        for (std::size_t i = b; i < e; ++i) {
          const std::size_t o = cells.offsets[i];
          const bool any_facet = accumulate_cell(p, d, faces, laplace, cells.voxel.data() + o,
                                                 cells.distance.data() + o, cells.owner.data() + o,
                                                 cells.cell_size(i), s.acc);
          write(queries[start + i], s, any_facet);
        }
      });
      start = end;
      report(opt.progress, double(end) / double(total));
    }
    if (opt.stats) {
      opt.stats->workers = 1;
      opt.stats->peak_scratch_bytes = peak;
      opt.stats->voxels_visited = visited;
      opt.stats->queries = total;
    }
  }
  if (total == 0) report(opt.progress, 1.0);
}

/// Sibson or Laplace at every voxel of the grid, into @p w.
template <class Policy, class P, class D, class W, class Options>
void natural_neighbours(const Policy& policy, const P& p, const D& d, const Options& opt, bool laplace, W& w) {
  std::vector<index_t> all(std::size_t(p.geometry.size()));
  for (std::size_t v = 0; v < all.size(); ++v) all[v] = index_t(v);
  natural_neighbour_rows(policy, p, d, opt, laplace, all.data(), all.size(), w.k, w.nodes, w.node.data(),
                         w.weight.data());
}

}  // namespace geovoronoi::detail::shape
