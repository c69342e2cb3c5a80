#pragma once
// The exit-code contract of the geovoronoi command-line tool (docs/cli.md, "Exit codes"):
//   0  success;
//   1  runtime failure: writing the outputs failed (disk full, I/O error, libpng), another run
//      replaced the output folder meanwhile, out of memory, any other failure that is not the input;
//   2  usage or bad input: command line, input files, seeds, --out that cannot be used.
// Every failure prints exactly one line on stderr, `geovoronoi: error: ...` (exit 2) or
// `geovoronoi: failed: ...` (exit 1), with control bytes from files or arguments escaped as \xNN.
// Also here: input files that would hang a reader (FIFO, device) are refused, and the thread count
// of the OpenMP runtime is clamped to a sane maximum.

#include "output_dir.hpp"  // runtime_failure, is_output_failure
#include "usage_error.hpp"

#include <geovoronoi/error.hpp>
#include <geovoronoi/io/common.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <stdexcept>
#include <string>
#include <thread>

#include <sys/stat.h>
#if defined(_OPENMP)
#include <omp.h>
#endif

namespace gvcli {

/// The whole of @p s, escaped as the library escapes what it echoes (geovoronoi::printable without a
/// limit): control bytes, C1 controls and bytes that are not UTF-8 as \xNN, so a message stays one line
/// and never sends terminal escape sequences read from an input file.
inline std::string printable(const std::string& s) { return geovoronoi::printable(s, std::string::npos); }

/// Refuses an input that is not a regular file before anything opens it: a folder is an error (not
/// an empty file), a FIFO, socket or device would block or never end.
inline void require_regular_file(const std::string& path, const char* what) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) return;  // missing: the reader says so
  if (S_ISDIR(st.st_mode)) throw usage_error(path + ": is a folder, not " + what);
  if (!S_ISREG(st.st_mode))
    throw usage_error(path + ": is not a regular file (a FIFO, socket or device); " + what + " must be a file");
}

/// The most OpenMP threads the tool lets the runtime start: 4 x the hardware threads.
inline int max_threads() {
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  return int(std::min(4u * hw, 4096u));
}

/// OMP_NUM_THREADS beyond max_threads() (e.g. 100000, which crashes the OpenMP runtime when it starts
/// that many threads) is clamped to it, and 0 or a negative count (which the runtime refuses) to 1,
/// with a note on stderr. Call before any parallel region.
inline void clamp_thread_count() {
  const char* env = std::getenv("OMP_NUM_THREADS");
  if (!env || !*env) return;
  errno = 0;
  char* end = nullptr;
  const long long n = std::strtoll(env, &end, 10);  // the first entry of a list such as "8,2"
  if (end == env) return;
  const bool too_many = errno == ERANGE ? n > 0 : n > max_threads();
  if (!too_many && n >= 1) return;
  const int use = too_many ? max_threads() : 1;
  // (GNU libgomp reads the variable when it is loaded, before main(): for 0 or a negative count it has
  // already printed its own "Invalid value" line and taken its default, which this overrides)
#if defined(_OPENMP)
  omp_set_num_threads(use);
#endif
  if (too_many)
    std::fprintf(stderr, "geovoronoi: note: OMP_NUM_THREADS=%s is more than 4 x the %u hardware threads; using %d\n",
                 printable(env).c_str(), std::max(1u, std::thread::hardware_concurrency()), use);
  else
    std::fprintf(stderr, "geovoronoi: note: OMP_NUM_THREADS=%s is not a thread count (1 or more); using 1\n",
                 printable(env).c_str());
}

/// The message of the library's exception @p e without its "geovoronoi: " prefix (the tool's error
/// line adds its own).
inline std::string library_message(const std::exception& e) {
  std::string m = e.what();
  if (m.compare(0, 12, "geovoronoi: ") == 0) m.erase(0, 12);
  return m;
}

/// Inside a catch block: prints the one error line of the current exception, returns the exit code.
inline int report_current_exception() noexcept {
  int code = 1;
  std::string message;
  try {
    throw;
  } catch (const usage_error& e) {
    code = 2, message = e.what();
  } catch (const runtime_failure& e) {
    code = 1, message = e.what();
  } catch (const geovoronoi::io::out_of_memory& e) {  // the input may be fine: memory ran out, exit 1
    code = 1, message = e.what();
    is_output_failure(message);
  } catch (const geovoronoi::io::io_error& e) {
    message = e.what();
    code = is_output_failure(message) ? 1 : 2;  // writing an output failed: 1; a bad input file: 2
  } catch (const std::invalid_argument& e) {
    message = e.what();
    code = is_output_failure(message) ? 1 : 2;
  } catch (const std::bad_alloc&) {
    code = 1, message = "out of memory";
  } catch (const std::exception& e) {
    message = e.what();
    is_output_failure(message);
    code = 1;
  } catch (...) {
    code = 1, message = "unknown failure";
  }
  try {
    std::fprintf(stderr, "geovoronoi: %s: %s\n", code == 2 ? "error" : "failed", printable(message).c_str());
  } catch (...) {
    std::fputs("geovoronoi: failed: out of memory\n", stderr);
  }
  return code;
}

}  // namespace gvcli
