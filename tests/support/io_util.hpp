// Helpers of the tests/io_*.test.cpp files: a private scratch folder and raw file access.
#pragma once
#include <geovoronoi/io/common.hpp>

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <unistd.h>

namespace io_test {

/// The process's scratch folder, removed with everything in it when the test program exits.
class scratch_folder {
 public:
  scratch_folder()
      : path_(std::filesystem::temp_directory_path() / ("geovoronoi-io-test-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path_);
  }
  ~scratch_folder() {
    std::error_code ec;  // nothing to report at exit: a folder left behind is only litter
    std::filesystem::remove_all(path_, ec);
  }
  scratch_folder(const scratch_folder&) = delete;
  scratch_folder& operator=(const scratch_folder&) = delete;
  const std::filesystem::path& path() const noexcept { return path_; }

 private:
  std::filesystem::path path_;
};

inline std::string scratch(const std::string& name) {
  static const scratch_folder dir;
  return (dir.path() / name).string();
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

inline void write_bytes(const std::string& path, const std::string& header, const void* data, std::size_t n) {
  std::ofstream f(path, std::ios::binary);
  f << header;
  f.write(static_cast<const char*>(data), std::streamsize(n));
}

inline std::string read_all(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

/// Runs f, expects geovoronoi::io::io_error whose message names `file` and contains `words`.
template <class F>
void expect_io_error(F&& f, const std::string& file, const std::string& words) {
  bool thrown = false;
  try {
    f();
  } catch (const geovoronoi::io::io_error& e) {
    thrown = true;
    const std::string what = e.what();
    INFO("message: " << what);
    CHECK(what.find(file) != std::string::npos);
    CHECK(what.find(words) != std::string::npos);
  }
  CHECK_MESSAGE(thrown, "expected an io_error mentioning '" << words << "'");
}

}  // namespace io_test
