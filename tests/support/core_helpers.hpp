#pragma once
// Small helpers shared by the per-header core tests (not by the backend suite).

#include <doctest/doctest.h>

#include <geovoronoi/config.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace gvcore {

/// Runs f and returns the message of the std::invalid_argument it throws; fails the test (and
/// returns "") if it throws nothing or something else.
template <class F>
std::string invalid_argument_message(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  } catch (const std::exception& e) {
    FAIL_CHECK("expected std::invalid_argument, got another exception: " << e.what());
    return "";
  }
  FAIL_CHECK("expected std::invalid_argument, nothing was thrown");
  return "";
}

/// True when @p text contains @p part.
inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// Exact bit pattern of a float or double.
inline std::uint32_t bits_of(float x) {
  std::uint32_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}
inline std::uint64_t bits_of(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

template <class T>
constexpr T nan_v = std::numeric_limits<T>::quiet_NaN();
template <class T>
constexpr T inf_v = std::numeric_limits<T>::infinity();

}  // namespace gvcore

/// Checks that EXPR throws std::invalid_argument whose message contains every listed substring.
#define GV_CHECK_INVALID(EXPR, ...)                                                          \
  do {                                                                                       \
    const std::string gv_msg_ = ::gvcore::invalid_argument_message([&] { (void)(EXPR); }); \
    for (const std::string gv_part_ : {__VA_ARGS__}) {                                       \
      INFO("message: \"" << gv_msg_ << "\" should contain \"" << gv_part_ << "\"");          \
      CHECK(::gvcore::contains(gv_msg_, gv_part_));                                          \
    }                                                                                        \
  } while (0)
