#pragma once
/// @file backend/choose.hpp
/// @brief Which backend to run a problem on by default: the one measured faster for its size, its
///        field and the threads available (docs/backends.md, "Choosing a backend").
///
/// Plain C++ (no Thrust or CUDA headers): a tool decides here, then dispatches to the backend
/// headers it was built with.
/// @code
/// const auto b = geovoronoi::recommended_backend(problem, std::thread::hardware_concurrency());
/// if (b == geovoronoi::backend_kind::thrust) ...  // geovoronoi::thrust::par
/// std::puts(geovoronoi::to_string(b));             // "seq", "thrust" or "cuda"
/// @endcode

#include <geovoronoi/config.hpp>
#include <geovoronoi/metric.hpp>

#include <cstdint>

namespace geovoronoi {

/// The library's backends: `sequential` is geovoronoi::seq, `thrust` geovoronoi::thrust::par,
/// `cuda` geovoronoi::cuda::par.
enum class backend_kind { sequential, thrust, cuda };

/// "seq", "thrust" or "cuda".
constexpr const char* to_string(backend_kind b) noexcept {
  return b == backend_kind::thrust ? "thrust" : b == backend_kind::cuda ? "cuda" : "seq";
}

/// What the choice looks at, also returned for logging (backend_choice::reason).
struct backend_facts {
  index_t voxels = 0;  ///< grid voxels
  index_t domain = 0;  ///< voxels inside the domain (the metric's mask rule)
  unsigned threads = 1;
  bool cuda_device = false;
};

/// A recommendation and the rule that made it (a static string, e.g. for a --verbose line).
struct backend_choice {
  backend_kind kind = backend_kind::sequential;
  const char* reason = "";
  backend_facts facts{};
};

/// Thresholds of the rule, from the measurements in docs/benchmarks.md ("Choosing a backend").
struct backend_rule {
  /// Below this many domain voxels a Thrust solve's steps are too small to share (they run on the
  /// calling thread) and its fixed passes over the grid cost more than they save: seq.
  index_t min_domain = index_t(1) << 18;
  /// Below this domain fraction of the grid the Thrust backend's passes over the whole grid
  /// (initialisation, unpacking) dominate the work on the domain: seq.
  double min_domain_fraction = 0.05;
  /// Threads the Thrust host systems need to beat seq.
  unsigned min_threads = 2;
};

/**
 * @brief The backend to use for @p problem by default, from measurement on CPU backends:
 *  1. cuda when @p cuda_device (a CUDA device answers and the cuda backend is built): every
 *     published GPU figure for this workload is far ahead of the CPU backends (docs/backends.md);
 *  2. seq when fewer than rule.min_threads hardware threads, when the domain has fewer than
 *     rule.min_domain voxels, or when it fills less than rule.min_domain_fraction of the grid;
 *  3. thrust otherwise.
 * One pass over the field (counting the domain); nothing is allocated.
 * @param threads hardware threads the Thrust backend may use (e.g. std::thread::hardware_concurrency()
 *        or the OpenMP thread limit); 0 counts as 1.
 */
template <class P>
backend_choice recommended_backend_explained(const P& problem, unsigned threads, bool cuda_device = false,
                                             const backend_rule& rule = {}) {
  backend_choice c;
  c.facts.voxels = problem.geometry.size();
  c.facts.threads = threads == 0 ? 1 : threads;
  c.facts.cuda_device = cuda_device;
  index_t in = 0;
  for (index_t v = 0; v < c.facts.voxels; ++v) in += problem.inside(v) ? 1 : 0;
  c.facts.domain = in;
  if (cuda_device) {
    c.kind = backend_kind::cuda;
    c.reason = "a CUDA device is available";
  } else if (c.facts.threads < rule.min_threads) {
    c.kind = backend_kind::sequential;
    c.reason = "one hardware thread: the Thrust host systems have nothing to share";
  } else if (in < rule.min_domain) {
    c.kind = backend_kind::sequential;
    c.reason = "small domain: Thrust's steps would run on one thread";
  } else if (double(in) < rule.min_domain_fraction * double(c.facts.voxels)) {
    c.kind = backend_kind::sequential;
    c.reason = "the domain is a small part of the grid";
  } else {
    c.kind = backend_kind::thrust;
    c.reason = "large domain and several threads: Thrust measured faster";
  }
  return c;
}

/// recommended_backend_explained(...).kind.
template <class P>
backend_kind recommended_backend(const P& problem, unsigned threads, bool cuda_device = false,
                                 const backend_rule& rule = {}) {
  return recommended_backend_explained(problem, threads, cuda_device, rule).kind;
}

/**
 * @brief The backend to compute shape functions on @p problem by default (the diagram solve before
 *        them included). Their work is many independent searches (one per query for Sibson and
 *        Laplace, two per node for Distance Ratio), which the Thrust policies share among the host's
 *        threads at any problem size, so the domain-size lines of recommended_backend_explained()
 *        do not apply (measured with two threads below its 2^18 voxels: docs/backends.md,
 *        "Choosing a backend"):
 *  1. cuda when @p cuda_device (as recommended_backend_explained());
 *  2. seq when fewer than rule.min_threads threads;
 *  3. thrust otherwise.
 */
template <class P>
backend_choice recommended_shape_backend_explained(const P& problem, unsigned threads, bool cuda_device = false,
                                                   const backend_rule& rule = {}) {
  backend_choice c = recommended_backend_explained(problem, threads, cuda_device, rule);
  if (c.kind == backend_kind::sequential && c.facts.threads >= rule.min_threads) {
    c.kind = backend_kind::thrust;
    c.reason = "shape functions and several threads: their searches are shared among the threads at any size";
  }
  return c;
}

/// recommended_shape_backend_explained(...).kind.
template <class P>
backend_kind recommended_shape_backend(const P& problem, unsigned threads, bool cuda_device = false,
                                       const backend_rule& rule = {}) {
  return recommended_shape_backend_explained(problem, threads, cuda_device, rule).kind;
}

}  // namespace geovoronoi
