#pragma once
// The built-in metrics on four float lanes (SSE2): their weights with the IEEE operations of the
// scalar expressions in metric.hpp, and their domain rules. The vectorised relaxations (the shape
// functions' fused searches, the diagram update's settle loop) use them to stay bit for bit equal to
// the scalar code.
#include <geovoronoi/metric.hpp>

#include <limits>
#include <type_traits>

#if defined(__SSE2__) && !defined(__CUDA_ARCH__)
#include <emmintrin.h>
#endif

namespace geovoronoi::detail {

#if defined(__SSE2__) && !defined(__CUDA_ARCH__)
/// The built-in metrics' weights on four float lanes: the operations of their scalar expressions
/// (metric.hpp), in the same order and with the same operands.
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

}  // namespace geovoronoi::detail
