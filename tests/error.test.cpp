// Tests of geovoronoi/error.hpp: the exception hierarchy.

#include <doctest/doctest.h>

#include <geovoronoi/error.hpp>

#include <stdexcept>
#include <string>
#include <type_traits>

namespace {
namespace gv = geovoronoi;

static_assert(std::is_base_of_v<std::runtime_error, gv::error>);
static_assert(std::is_base_of_v<gv::error, gv::metric_error>);
static_assert(std::is_base_of_v<gv::error, gv::cancelled>);
// invalid arguments are reported with the standard type, not the library's base
static_assert(!std::is_base_of_v<gv::error, std::invalid_argument>);
static_assert(!std::is_base_of_v<std::invalid_argument, gv::error>);

TEST_CASE("error: messages are kept and the types are caught by their bases") {
  try {
    throw gv::metric_error("weight -1");
  } catch (const gv::error& e) {
    CHECK(std::string(e.what()) == "weight -1");
  }
  bool caught = false;
  try {
    throw gv::cancelled();
  } catch (const std::runtime_error& e) {
    caught = true;
    CHECK(std::string(e.what()).find("cancel") != std::string::npos);
  }
  CHECK(caught);
  CHECK_THROWS_AS(throw gv::metric_error("x"), gv::metric_error);
  CHECK_THROWS_AS(throw gv::metric_error("x"), std::runtime_error);
}

}  // namespace
