#pragma once
/// @file bench/common.hpp
/// @brief Shared plumbing of every backend's benchmark executable: cached phantom fields, deterministic
///        seeds, registration of the `voronoi/<backend>/<field>/<n>/<seeds>/<conn>` case matrix, and a
///        main() that runs one-off checks, then every registered case.
///
/// A backend's benchmark file looks like this:
/// @code
/// #include "common.hpp"
/// GEOVORONOI_BENCH_REGISTER(my_cases) {
///   geovoronoi::bench::register_voronoi_cases("mine", my::par, {64, 128}, {10, 100}, {6, 26},
///                                             {"constant", "gradient", "steak"});
/// }
/// #ifndef GEOVORONOI_BENCH_COMBINED
/// GEOVORONOI_BENCH_MAIN()
/// #endif
/// @endcode
/// Several backend files can be linked into one executable (so speed-ups are measured in one run):
/// compile them with GEOVORONOI_BENCH_COMBINED defined and add one file that expands
/// GEOVORONOI_BENCH_MAIN() unconditionally (bench/voronoi/cpu.cpp does this).
///
/// Timing: every case reports real (wall-clock) time. Setup (field, problem, seeds) happens before the
/// timed loop; the loop times the whole front-end call (validation, solve, result allocation).
/// Counters: `voxels_per_second` (n^3 voxels per solve, a rate over real time) and `ns_per_voxel` (its
/// inverse in nanoseconds). Voxel counts are always the full n^3 grid, also for `steak`, whose domain
/// is only part of the grid, so figures of different fields compare the same volume.

#include <geovoronoi.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace geovoronoi::bench {

/// Seed salt of every benchmark: all backends solve the same seed sets.
inline constexpr std::uint64_t seed_salt = 2016;

/// Names of the phantom fields the benchmarks know.
inline const std::vector<std::string>& field_names() {
  static const std::vector<std::string> names{"constant", "gradient", "steak"};
  return names;
}

/// The phantom @p name ("constant", "gradient" or "steak") on an n^3 grid of unit spacing, or "mri"
/// (phantom::mri_like on phantom::mri_like_grid(n): n x 1.23n x 0.31n voxels of 0.9 x 0.9 x 2.5, the
/// pelvis MRI's shape at n = 221), built once per (name, n) and kept for the life of the process
/// (64 MiB per field at n = 256).
/// @throws std::invalid_argument for an unknown name or n < 1.
inline const image<float, 3>& bench_field(const std::string& name, int n) {
  static std::map<std::pair<std::string, int>, std::unique_ptr<image<float, 3>>> cache;
  auto& slot = cache[{name, n}];
  if (!slot) {
    if (n < 1) throw std::invalid_argument("bench_field: edge length must be >= 1, got " + std::to_string(n));
    const grid<3> g({n, n, n});
    if (name == "constant")
      slot = std::make_unique<image<float, 3>>(phantom::constant(g));
    else if (name == "gradient")
      slot = std::make_unique<image<float, 3>>(phantom::gradient(g));
    else if (name == "steak")
      slot = std::make_unique<image<float, 3>>(phantom::steak(g));
    else if (name == "mri")
      slot = std::make_unique<image<float, 3>>(phantom::mri_like(phantom::mri_like_grid(n)));
    else {
      cache.erase({name, n});
      throw std::invalid_argument("bench_field: unknown field '" + name + "' (constant, gradient, steak, mri)");
    }
  }
  return *slot;
}

/// @p count distinct pseudo-random seed voxels inside @p field's domain, always the same for the same
/// field and count (phantom::random_seeds with the fixed salt seed_salt).
/// @throws std::runtime_error if the domain has fewer than @p count voxels.
inline std::vector<coord<3>> bench_seeds(const image<float, 3>& field, int count) {
  auto s = phantom::random_seeds(field, count, seed_salt);
  if (static_cast<int>(s.size()) != count)
    throw std::runtime_error("bench_seeds: only " + std::to_string(s.size()) + " of " + std::to_string(count) +
                             " seeds fit in the domain");
  return s;
}

/// Identification of one benchmark case, passed to hooks.
struct case_info {
  std::string backend;
  std::string field;
  int n = 0;
  int seeds = 0;
  int conn = 0;
  /// `voronoi/<backend>/<field>/<n>/<seeds>/<conn>`
  std::string name() const {
    return "voronoi/" + backend + "/" + field + "/" + std::to_string(n) + "/" + std::to_string(seeds) + "/" +
           std::to_string(conn);
  }
};

/// Optional per-case callbacks of a backend.
struct case_hooks {
  /// Called once after the timed loop, e.g. to add counters such as relaxations per voxel.
  std::function<void(benchmark::State&)> after;
  /// Called once before the timed loop (after setup), e.g. to reset a backend's statistics.
  std::function<void(benchmark::State&)> before;
};

/// Iteration counts that keep the full matrix at a few minutes: solves of 256^3 take seconds.
inline benchmark::IterationCount default_iterations(int n) { return n <= 64 ? 5 : n <= 128 ? 2 : 1; }

/// Smoke mode (environment GEOVORONOI_BENCH_SMOKE set, as the ctest entries `smoke_bench_*` do): each
/// case runs once, on the smallest size only and never above smoke_size_cap voxels per side (a call
/// registering only 221 or 256 runs at 32: same code paths, a fraction of a second), so a test run
/// checks that every benchmark still works without spending minutes timing it.
inline bool smoke_run() {
  static const bool smoke = std::getenv("GEOVORONOI_BENCH_SMOKE") != nullptr;
  return smoke;
}

/// Largest grid side a smoke run uses (see smoke_run()).
inline constexpr int smoke_size_cap = 32;

/// For Apply(): a minimum of one second of timing, or one iteration in smoke mode.
inline void min_time_1s(benchmark::internal::Benchmark* b) {
  if (smoke_run())
    b->Iterations(1);
  else
    b->MinTime(1.0);
}

namespace detail {

/// Runs one case with connectivity N: builds the problem, then times @p solve(problem, seeds).
/// If @p manual_time is set and @p solve returns a double, that value (seconds) is the iteration's
/// time (a device backend can time with its own events); if it returns anything else, the call is
/// timed with a steady clock. Without manual time the library's real-time clock is used.
template <int N, class Solve>
void run_case(benchmark::State& state, const case_info& c, Solve& solve, bool manual_time, const case_hooks& hooks) {
  const auto& field = bench_field(c.field, c.n);
  const auto seeds = bench_seeds(field, c.seeds);
  const auto p = make_problem(field.geometry(), field, min_stiffness{}, connectivity<N>{});
  using result_t = std::invoke_result_t<Solve&, const decltype(p)&, const std::vector<coord<3>>&>;
  if (hooks.before) hooks.before(state);
  double total = 0;  // seconds, the same measure the library reports (manual or wall-clock)
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    if (manual_time) {
      const auto t0 = std::chrono::steady_clock::now();
      if constexpr (std::is_same_v<result_t, double>) {
        const double secs = solve(p, seeds);
        state.SetIterationTime(secs);
        total += secs;
      } else {
        auto r = solve(p, seeds);
        benchmark::DoNotOptimize(r);
        benchmark::ClobberMemory();
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        state.SetIterationTime(secs);
        total += secs;
      }
    } else {
      auto r = solve(p, seeds);
      benchmark::DoNotOptimize(r);
      benchmark::ClobberMemory();
    }
  }
  if (!manual_time) total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double voxels = double(field.size()) * double(state.iterations());
  state.counters["voxels_per_second"] = benchmark::Counter(voxels, benchmark::Counter::kIsRate);
  state.counters["ns_per_voxel"] = benchmark::Counter(voxels > 0 ? total * 1e9 / voxels : 0.0);
  if (hooks.after) hooks.after(state);
}

}  // namespace detail

/**
 * @brief Register `voronoi/<backend>/<field>/<n>/<seeds>/<conn>` for every combination, timing an
 *        arbitrary solver.
 *
 * @param solve a callable `R solve(const problem<float,3,min_stiffness,N>& p, const std::vector<coord<3>>& seeds)`
 *              for N = 6 and 26 (a generic lambda); its result is kept alive until the iteration ends.
 * @param conns each 6 or 26 (dispatched at run time to connectivity<6> / connectivity<26>).
 * @param iterations fixed iteration count per case; 0 = default_iterations(n).
 * @return the registered benchmarks, for further tuning.
 */
template <class Solve>
std::vector<benchmark::internal::Benchmark*> register_solver_cases(const std::string& backend, Solve solve,
                                                                   const std::vector<int>& sizes,
                                                                   const std::vector<int>& seeds,
                                                                   const std::vector<int>& conns,
                                                                   const std::vector<std::string>& fields,
                                                                   bool manual_time = false, case_hooks hooks = {},
                                                                   benchmark::IterationCount iterations = 0) {
  std::vector<benchmark::internal::Benchmark*> out;
  const std::vector<int> run_sizes =
      smoke_run() && !sizes.empty()
          ? std::vector<int>{std::min(smoke_size_cap, *std::min_element(sizes.begin(), sizes.end()))}
          : sizes;
  for (const auto& f : fields)
    for (int n : run_sizes)
      for (int s : seeds)
        for (int k : conns) {
          if (k != 6 && k != 26)
            throw std::invalid_argument("register_voronoi_cases: connectivity must be 6 or 26, got " +
                                        std::to_string(k));
          const case_info c{backend, f, n, s, k};
          auto fn = [c, solve, manual_time, hooks](benchmark::State& state) mutable {
            if (c.conn == 6)
              detail::run_case<6>(state, c, solve, manual_time, hooks);
            else
              detail::run_case<26>(state, c, solve, manual_time, hooks);
          };
          auto* b = benchmark::RegisterBenchmark(c.name().c_str(), fn);
          b->Unit(benchmark::kMillisecond)
              ->Iterations(smoke_run() ? 1 : iterations > 0 ? iterations : default_iterations(n));
          if (manual_time)
            b->UseManualTime();
          else
            b->UseRealTime();
          out.push_back(b);
        }
  return out;
}

/// @brief register_solver_cases() for a library backend: times `geovoronoi::voronoi(policy, p, seeds)`.
template <class Policy>
std::vector<benchmark::internal::Benchmark*> register_voronoi_cases(const std::string& backend, Policy policy,
                                                                    std::vector<int> sizes, std::vector<int> seeds,
                                                                    std::vector<int> conns,
                                                                    std::vector<std::string> fields,
                                                                    bool manual_time = false, case_hooks hooks = {},
                                                                    benchmark::IterationCount iterations = 0) {
  auto solve = [policy](const auto& p, const std::vector<coord<3>>& s) { return geovoronoi::voronoi(policy, p, s); };
  return register_solver_cases(backend, solve, sizes, seeds, conns, fields, manual_time, std::move(hooks),
                               iterations);
}

// ---- registration and main ---------------------------------------------------------------------------

/// Functions that register cases, run by main() before the benchmarks start.
inline std::vector<void (*)()>& registrations() {
  static std::vector<void (*)()> r;
  return r;
}
/// One-off correctness checks (not timed), run by main() first; a check throws or returns false on failure.
inline std::vector<std::pair<const char*, bool (*)()>>& checks() {
  static std::vector<std::pair<const char*, bool (*)()>> c;
  return c;
}
struct registrar {
  explicit registrar(void (*f)()) { registrations().push_back(f); }
  registrar(const char* name, bool (*f)()) { checks().emplace_back(name, f); }
};

/// main() of every benchmark executable: runs the checks (exit 1 if one fails; `--checks_only` stops
/// after them, for ctest), then the registration functions, then Google Benchmark.
inline int run_main(int argc, char** argv) {
  bool checks_only = false;
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--checks_only") == 0) {
      checks_only = true;
      for (int j = i; j + 1 < argc; ++j) argv[j] = argv[j + 1];
      --argc;
      break;
    }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  for (const auto& [name, check] : checks()) {
    bool ok = false;
    try {
      ok = check();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "check %s threw: %s\n", name, e.what());
    }
    std::fprintf(stderr, "check %s: %s\n", name, ok ? "ok" : "FAILED");
    if (!ok) return 1;
  }
  if (checks_only) return 0;
  for (auto f : registrations()) f();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace geovoronoi::bench

#define GEOVORONOI_BENCH_CAT2(a, b) a##b
#define GEOVORONOI_BENCH_CAT(a, b) GEOVORONOI_BENCH_CAT2(a, b)

/// Define a function that registers cases; main() calls it. Usage: `GEOVORONOI_BENCH_REGISTER(name) { ... }`.
#define GEOVORONOI_BENCH_REGISTER(fn)                                                        \
  static void fn();                                                                          \
  static const ::geovoronoi::bench::registrar GEOVORONOI_BENCH_CAT(fn, _registrar_){&fn};    \
  static void fn()

/// Define a one-off check returning bool; main() runs it before any benchmark.
/// Usage: `GEOVORONOI_BENCH_CHECK(name) { ...; return ok; }`.
#define GEOVORONOI_BENCH_CHECK(fn)                                                           \
  static bool fn();                                                                          \
  static const ::geovoronoi::bench::registrar GEOVORONOI_BENCH_CAT(fn, _registrar_){#fn, &fn}; \
  static bool fn()

/// The executable's main(); expand it in exactly one translation unit.
#define GEOVORONOI_BENCH_MAIN() \
  int main(int argc, char** argv) { return ::geovoronoi::bench::run_main(argc, argv); }
