// Shared by the libFuzzer targets: writes the input to a private temporary file (the readers take
// file names) and runs a reader on it; io_error is the expected outcome for junk, anything else
// (a crash, a sanitizer report, another exception escaping, a timeout) is a finding.
#pragma once
#include <geovoronoi/io/common.hpp>

#include <cstdint>
#include <cstdio>
#include <string>
#include <unistd.h>

inline std::string fuzz_path(const char* ext) {
  return "/tmp/geovoronoi-fuzz-" + std::to_string(::getpid()) + ext;
}

inline void fuzz_write(const std::string& path, const std::uint8_t* data, std::size_t size) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return;
  if (size) std::fwrite(data, 1, size, f);
  std::fclose(f);
}
