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

// ---- printable(): how every message echoes a piece of its input ----------------------------------

namespace {
namespace gv2 = geovoronoi;

TEST_CASE("printable: plain text and valid UTF-8 pass through") {
  CHECK(gv2::printable("abc 1,2,3") == "abc 1,2,3");
  CHECK(gv2::printable("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80") == "caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80");
  CHECK(gv2::printable("") == "");
}

TEST_CASE("printable: control bytes, C1 controls and bytes that are not UTF-8 are written \\xNN") {
  CHECK(gv2::printable("a\x1b[31mred\nb\x7f") == "a\\x1b[31mred\\x0ab\\x7f");
  CHECK(gv2::printable("\x9b" "31m") == "\\x9b31m");                     // a raw C1 byte (8-bit CSI)
  CHECK(gv2::printable("\xc2\x9b" "31m") == "\\xc2\\x9b31m");            // U+009B, well-formed UTF-8
  CHECK(gv2::printable("x\xffy") == "x\\xffy");                          // never valid
  CHECK(gv2::printable("\xc0\xaf") == "\\xc0\\xaf");                     // overlong '/'
  CHECK(gv2::printable("\xed\xa0\x80") == "\\xed\\xa0\\x80");            // a UTF-16 surrogate
  CHECK(gv2::printable("\xe2\x82") == "\\xe2\\x82");                     // truncated sequence
  CHECK(gv2::printable("\xf4\x90\x80\x80") == "\\xf4\\x90\\x80\\x80");   // beyond U+10FFFF
  CHECK(gv2::printable("\xe2\x80\xa8") == "\\xe2\\x80\\xa8");            // U+2028, a line separator
  CHECK(gv2::printable(std::string("a\0b", 3)) == "a\\x00b");
}

TEST_CASE("printable: a long piece is cut to its first bytes, at a character boundary, and says its length") {
  const std::string digits(100000, '7');
  const std::string p = gv2::printable(digits);
  INFO(p);
  CHECK(p.size() < 100);
  CHECK(p.compare(0, gv2::echo_limit, digits, 0, gv2::echo_limit) == 0);
  CHECK(p.find("... (100000 bytes)") != std::string::npos);
  std::string accents;
  for (int i = 0; i < 100; ++i) accents += "\xc3\xa9";
  const std::string q = gv2::printable(accents);
  CHECK(q.find("\\x") == std::string::npos);  // no character split in two
  CHECK(q.find("(200 bytes)") != std::string::npos);
  // no limit: only escaped
  CHECK(gv2::printable(digits, std::string::npos) == digits);
  // escaping counts the bytes of the input, not of the escapes
  CHECK(gv2::printable(std::string(10, '\x01'), 16) == std::string("\\x01\\x01\\x01\\x01\\x01\\x01\\x01\\x01\\x01\\x01"));
}

}  // namespace
