// Shared by the libFuzzer targets: the parsers take the bytes in memory (the file readers only add
// reading the file); io_error is the expected outcome for junk, anything else (a crash, a sanitizer
// report, another exception escaping, a timeout, a huge allocation) is a finding.
#pragma once
#include <geovoronoi/io/common.hpp>

#include <cstdint>
#include <vector>

inline std::vector<unsigned char> fuzz_bytes(const std::uint8_t* data, std::size_t size) {
  return std::vector<unsigned char>(data, data + size);
}
