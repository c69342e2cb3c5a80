#pragma once
/// @file policy.hpp
/// @brief The trait that marks a type as a backend policy, the first argument of every solver.

#include <type_traits>

namespace geovoronoi {

/**
 * @brief Whether @p T is a backend policy (like std::is_execution_policy): true for the policy types
 *        of geovoronoi::seq, geovoronoi::thrust::par / par_on(...) and geovoronoi::cuda::par.
 *
 * Every solver entry point checks it with a static_assert, so passing anything else first (an int, a
 * problem, a Thrust execution policy without geovoronoi::thrust::par_on) fails with one message naming
 * the requirement instead of a cascade of lookup errors. A new backend specialises it for its policy
 * type declares the member type `backend_policy_tag` (inherited by types derived from it, as a
 * test's wrapper of thrust::par_on_t is), or specialises this trait, and provides the hooks described
 * in docs/backends.md.
 *
 * @code
 * namespace mine { struct par_t { using backend_policy_tag = void; }; }
 * static_assert(geovoronoi::is_backend_policy_v<mine::par_t>);
 * @endcode
 */
namespace detail {
template <class T, class = void>
struct has_backend_policy_tag : std::false_type {};
template <class T>
struct has_backend_policy_tag<T, std::void_t<typename T::backend_policy_tag>> : std::true_type {};
}  // namespace detail

template <class T>
struct is_backend_policy : detail::has_backend_policy_tag<T> {};

/// @brief is_backend_policy<T>::value, with cv-qualifiers and references removed.
template <class T>
inline constexpr bool is_backend_policy_v = is_backend_policy<std::remove_cv_t<std::remove_reference_t<T>>>::value;

namespace detail {
/// The entry points' check of their first argument.
template <class Policy>
constexpr void require_policy() {
  static_assert(is_backend_policy_v<Policy>,
                "geovoronoi: the first argument must be a backend policy: geovoronoi::seq, geovoronoi::thrust::par, "
                "geovoronoi::thrust::par_on(...) or geovoronoi::cuda::par (is_backend_policy<Policy> is false)");
}
}  // namespace detail

}  // namespace geovoronoi
