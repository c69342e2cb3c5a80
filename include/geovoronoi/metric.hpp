#pragma once
/// @file metric.hpp
/// @brief Edge-weight policies: how a field (stiffness or cost) biases the length of a grid edge,
///        and which voxels the field excludes from the domain.
///
/// A metric is any trivially copyable type with a host-device call operator
/// `T operator()(T length, T from, T to) const` returning the weight (>= 0) of the edge from a voxel
/// with field value @c from to an adjacent voxel with value @c to, and optionally a static
/// `bool inside(T value)` giving the domain-mask rule (default: the stiffness rule, value > 0).
/// See docs/policies.md for a user-defined example.

#include <geovoronoi/config.hpp>

#include <cmath>
#include <limits>
#include <type_traits>

namespace geovoronoi {

/// Domain rule of the stiffness metrics: a voxel is inside when its value is > 0 (NaN is outside).
struct stiffness_domain {
  template <class T>
  GEOVORONOI_HOST_DEVICE static bool inside(T value) noexcept {
    return value > T(0);
  }
};

/// Domain rule of cost metrics: a voxel is inside when its value is >= 0 and finite.
struct cost_domain {
  template <class T>
  GEOVORONOI_HOST_DEVICE static bool inside(T value) noexcept {
    return value >= T(0) && value < std::numeric_limits<T>::infinity();
  }
};

/// w = l. Plain chamfer (graph) distance; the field only masks (stiffness rule).
struct uniform : stiffness_domain {
  template <class T>
  GEOVORONOI_HOST_DEVICE T operator()(T length, T, T) const noexcept {
    return length;
  }
};

/// w = l / min(b_u, b_v): the softer voxel governs. SOFA's bias since 2013.
struct min_stiffness : stiffness_domain {
  template <class T>
  GEOVORONOI_HOST_DEVICE T operator()(T length, T bu, T bv) const noexcept {
    return length / (bu < bv ? bu : bv);
  }
};

/// w = 2 l / (b_u + b_v): division by the arithmetic mean stiffness. SOFA's bias before 2013.
struct mean_stiffness : stiffness_domain {
  template <class T>
  GEOVORONOI_HOST_DEVICE T operator()(T length, T bu, T bv) const noexcept {
    return (T(2) * length) / (bu + bv);
  }
};

/// w = l (c_u + c_v) / 2 with c a cost (compliance) field, as scikit-image's MCP_Geometric.
/// Zero costs are allowed (zero-weight edges); negative, NaN or infinite costs are outside.
struct mean_cost : cost_domain {
  template <class T>
  GEOVORONOI_HOST_DEVICE T operator()(T length, T cu, T cv) const noexcept {
    return length * ((cu + cv) * T(0.5));
  }
};

namespace detail {

template <class M, class T, class = void>
struct has_inside : std::false_type {};
template <class M, class T>
struct has_inside<M, T, std::void_t<decltype(M::inside(std::declval<T>()))>> : std::true_type {};

/// The metric's domain rule, defaulting to the stiffness rule.
template <class M, class T>
GEOVORONOI_HOST_DEVICE inline bool inside(T value) noexcept {
  if constexpr (has_inside<M, T>::value)
    return M::inside(value);
  else
    return stiffness_domain::inside(value);
}

template <class M, class T>
inline constexpr bool is_metric_v = std::is_invocable_r_v<T, const M&, T, T, T>;

}  // namespace detail
}  // namespace geovoronoi
