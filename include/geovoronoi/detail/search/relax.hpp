#pragma once
// The relaxation step, the one rule that makes every backend return the same bits.
//
// A search that settles voxel v at distance d(v) offers each neighbour u, over the edge v -> u of
// stencil length l, the candidate fl(d(v) + w) with w = metric(l, field(v), field(u)): the metric's
// own float expression (from, to order), then one addition in the distance type, nothing fused, no
// other rounding. A candidate enters u when its key (distance, label) is smaller than u's (key.hpp);
// a weight that is negative or NaN is the metric's error (bad_weight). Every search of the library
// relaxes through the functions below: the dense and sparse engines, the count-only insert-queries
// (one lane or many, scalar, SSE2 or AVX-512), the diagram update, the parent rule, the Thrust and
// CUDA kernels (edge_weight and extend, which device code can call).
//
// The SIMD forms evaluate the built-in metrics' expressions on four float lanes with the same IEEE
// operations in the same order (SSE arithmetic rounds like scalar arithmetic), so each lane holds the
// bits the scalar step gives.

#include <geovoronoi/config.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/metric.hpp>

#include <limits>
#include <string>
#include <type_traits>

#if defined(__SSE2__) && !defined(__CUDA_ARCH__)
#include <emmintrin.h>
#endif
// AVX-512 forms, for searches that choose AVX-512 at run time (the library is compiled for plain
// x86-64): GCC and Clang on x86-64, whose target attribute compiles one function for AVX-512; not
// under nvcc (its front end is kept away from that attribute).
#if defined(__SSE2__) && !defined(__CUDA_ARCH__) && defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && \
    !defined(__CUDACC__) && !defined(__NVCOMPILER)
#define GEOVORONOI_SIMD_AVX512 1
#include <immintrin.h>
#endif

namespace geovoronoi::detail::search {

/// The metric's error for a weight @p w that is negative or NaN.
[[noreturn]] inline void bad_weight(double w) {
  throw metric_error("geovoronoi: the metric returned the edge weight " + std::to_string(w) +
                     "; weights must be >= 0 and not NaN");
}
/// The same error where the offending value is not known (device backends report a flag).
[[noreturn]] inline void bad_weight() {
  throw metric_error("geovoronoi: the metric returned a negative or NaN edge weight; weights must be >= 0 and not NaN");
}

/// Whether metric M returns weights >= 0 for every pair of field values inside the domain (the
/// built-in metrics: lengths are positive, stiffness > 0, costs >= 0). Searches may then skip the
/// per-candidate check of the weight.
template <class M>
inline constexpr bool never_negative_v = std::is_same_v<M, uniform> || std::is_same_v<M, min_stiffness> ||
                                         std::is_same_v<M, mean_stiffness> || std::is_same_v<M, mean_cost>;

/// The weight of the edge of length @p length walked from a voxel of field value @p from to one of
/// field value @p to.
template <class M, class T>
GEOVORONOI_HOST_DEVICE inline T edge_weight(const M& metric, T length, T from, T to) noexcept {
  return metric(length, from, to);
}

/// The candidate distance over an edge of weight @p w from a voxel at distance @p d: one addition
/// rounded to nearest, which no compiler may fuse with the metric's operations (the targets carry
/// -ffp-contract=off and --fmad=false; device code says it with __fadd_rn / __dadd_rn too).
template <class T>
GEOVORONOI_HOST_DEVICE inline T extend(T d, T w) noexcept {
#ifdef __CUDA_ARCH__
  if constexpr (sizeof(T) == 4)
    return __fadd_rn(d, w);
  else
    return __dadd_rn(d, w);
#else
  return d + w;
#endif
}

/// Throws bad_weight unless @p w >= 0.
template <class T>
inline void check_weight(T w) {
  if (!(w >= T(0))) bad_weight(double(w));
}

/// The relaxation of the edge v -> u on the host: the checked weight, then the candidate
/// fl(dv + w).
template <class M, class T>
inline T relax(const M& metric, T length, T dv, T fv, T fu) {
  const T w = edge_weight(metric, length, fv, fu);
  check_weight(w);
  return extend(dv, w);
}

#if defined(__SSE2__) && !defined(__CUDA_ARCH__)
/// The built-in metrics' weights on four float lanes: the operations of their scalar expressions
/// (metric.hpp), in the same order and with the same operands. `value` is false for other metrics.
template <class M>
struct sse_weight : std::false_type {};
template <>
struct sse_weight<uniform> : std::true_type {
  static __m128 apply(__m128 len, __m128, __m128) noexcept { return len; }
};
template <>
struct sse_weight<min_stiffness> : std::true_type {
  // bu < bv ? bu : bv is minps(bu, bv) exactly, NaN included (both give bv when unordered)
  static __m128 apply(__m128 len, __m128 bu, __m128 bv) noexcept { return _mm_div_ps(len, _mm_min_ps(bu, bv)); }
};
template <>
struct sse_weight<mean_stiffness> : std::true_type {
  static __m128 apply(__m128 len, __m128 bu, __m128 bv) noexcept {
    return _mm_div_ps(_mm_mul_ps(_mm_set1_ps(2.0f), len), _mm_add_ps(bu, bv));
  }
};
template <>
struct sse_weight<mean_cost> : std::true_type {
  static __m128 apply(__m128 len, __m128 cu, __m128 cv) noexcept {
    return _mm_mul_ps(len, _mm_mul_ps(_mm_add_ps(cu, cv), _mm_set1_ps(0.5f)));
  }
};

/// extend() on four lanes.
inline __m128 extend(__m128 d, __m128 w) noexcept { return _mm_add_ps(d, w); }
#ifdef GEOVORONOI_SIMD_AVX512
/// extend() on sixteen lanes, for functions compiled for AVX-512.
__attribute__((target("avx512f"))) inline __m512 extend(__m512 d, __m512 w) noexcept { return _mm512_add_ps(d, w); }
#endif

/// The candidates of four edges at once: extend(dv, weight(len, fv, fu)) lane by lane (unchecked: the
/// metrics with an SSE form never return a negative weight between domain voxels).
template <class M>
inline __m128 sse_relax(__m128 len, __m128 dv, __m128 fv, __m128 fu) noexcept {
  static_assert(sse_weight<M>::value && never_negative_v<M>, "sse_relax: a built-in metric");
  return extend(dv, sse_weight<M>::apply(len, fv, fu));
}

/// The domain rule of a built-in metric on four lanes (all ones where inside), the comparisons of
/// stiffness_domain::inside and cost_domain::inside (a NaN is outside in both). `value` is false
/// for a metric with a rule of its own.
template <class M, class = void>
struct sse_inside : std::false_type {};
template <class M>
struct sse_inside<M, std::enable_if_t<std::is_same_v<M, uniform> || std::is_same_v<M, min_stiffness> ||
                                      std::is_same_v<M, mean_stiffness>>> : std::true_type {
  static_assert(std::is_base_of_v<stiffness_domain, M>, "sse_inside: a stiffness metric without the stiffness rule");
  static __m128 apply(__m128 f) noexcept { return _mm_cmpgt_ps(f, _mm_setzero_ps()); }
};
template <class M>
struct sse_inside<M, std::enable_if_t<std::is_same_v<M, mean_cost>>> : std::true_type {
  static_assert(std::is_base_of_v<cost_domain, M>, "sse_inside: a cost metric without the cost rule");
  static __m128 apply(__m128 f) noexcept {
    return _mm_and_ps(_mm_cmpge_ps(f, _mm_setzero_ps()),
                      _mm_cmplt_ps(f, _mm_set1_ps(std::numeric_limits<float>::infinity())));
  }
};
#endif

}  // namespace geovoronoi::detail::search
