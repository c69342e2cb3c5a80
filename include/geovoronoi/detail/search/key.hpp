#pragma once
// The keys of every search. For non-negative IEEE floats the bit pattern orders like the value, so
// (bits(d) << 32 | label) compares exactly like the pair (d, label): the tie rule (lowest node index
// wins among equal distances) becomes one integer comparison, and one atomicMin on devices. Searches
// that carry a single label (insert-query) order by the distance alone (distance_key).

#include <geovoronoi/config.hpp>

#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

namespace geovoronoi::detail::search {

template <class T>
struct key_traits;

template <>
struct key_traits<float> {
  using key_type = std::uint64_t;
  static constexpr int bits = 64;
  static constexpr key_type unreached = ~std::uint64_t(0);
  /// The same, callable from device code (static data members of class type are host-only in CUDA).
  GEOVORONOI_HOST_DEVICE static constexpr key_type unreached_key() noexcept { return ~std::uint64_t(0); }
  GEOVORONOI_HOST_DEVICE static key_type make(float d, label_t l) noexcept {
    std::uint32_t b;
    std::memcpy(&b, &d, sizeof b);
    return (std::uint64_t(b) << 32) | std::uint32_t(l);
  }
  GEOVORONOI_HOST_DEVICE static float distance(key_type k) noexcept {
    const std::uint32_t b = std::uint32_t(k >> 32);
    float d;
    std::memcpy(&d, &b, sizeof d);
    return d;
  }
  GEOVORONOI_HOST_DEVICE static label_t label(key_type k) noexcept { return label_t(std::uint32_t(k)); }
  /// 0 if equal, else 1 + index of the highest differing bit (radix-heap bucket).
  static int bucket(key_type a, key_type b) noexcept { return a == b ? 0 : 64 - __builtin_clzll(a ^ b); }
};

/// For double the key is 96 bits: the distance bits and the label, compared lexicographically.
struct wide_key {
  std::uint64_t d;
  std::uint32_t l;
  GEOVORONOI_HOST_DEVICE friend bool operator<(const wide_key& a, const wide_key& b) noexcept {
    return a.d < b.d || (a.d == b.d && a.l < b.l);
  }
  GEOVORONOI_HOST_DEVICE friend bool operator==(const wide_key& a, const wide_key& b) noexcept {
    return a.d == b.d && a.l == b.l;
  }
  GEOVORONOI_HOST_DEVICE friend bool operator!=(const wide_key& a, const wide_key& b) noexcept { return !(a == b); }
};

template <>
struct key_traits<double> {
  using key_type = wide_key;
  static constexpr int bits = 96;
  static constexpr key_type unreached = {~std::uint64_t(0), ~std::uint32_t(0)};
  /// The same, callable from device code (static data members of class type are host-only in CUDA).
  GEOVORONOI_HOST_DEVICE static constexpr key_type unreached_key() noexcept { return {~std::uint64_t(0), ~std::uint32_t(0)}; }
  GEOVORONOI_HOST_DEVICE static key_type make(double d, label_t l) noexcept {
    std::uint64_t b;
    std::memcpy(&b, &d, sizeof b);
    return {b, std::uint32_t(l)};
  }
  GEOVORONOI_HOST_DEVICE static double distance(key_type k) noexcept {
    double d;
    std::memcpy(&d, &k.d, sizeof d);
    return d;
  }
  GEOVORONOI_HOST_DEVICE static label_t label(key_type k) noexcept { return label_t(k.l); }
  static int bucket(key_type a, key_type b) noexcept {
    if (a.d != b.d) return 96 - __builtin_clzll(a.d ^ b.d);
    if (a.l != b.l) return 32 - __builtin_clz(a.l ^ b.l);
    return 0;
  }
};

/// Keys of the searches that carry one label: the bit pattern of a non-negative distance alone.
template <class T>
struct distance_key {
  static_assert(sizeof(T) == 4 || sizeof(T) == 8, "distance_key: T must be float or double");
  using key_type = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
  static constexpr int bits = int(sizeof(key_type) * 8);
  static key_type make(T d) noexcept {
    key_type b;
    std::memcpy(&b, &d, sizeof b);
    return b;
  }
  static T distance(key_type k) noexcept {
    T d;
    std::memcpy(&d, &k, sizeof d);
    return d;
  }
  /// 0 if equal, else 1 + index of the highest differing bit (radix-heap bucket).
  static int bucket(key_type a, key_type b) noexcept {
    if (a == b) return 0;
    if constexpr (sizeof(key_type) == 4)
      return 32 - __builtin_clz(a ^ b);
    else
      return 64 - __builtin_clzll(a ^ b);
  }
};

}  // namespace geovoronoi::detail::search
