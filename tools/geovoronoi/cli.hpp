#pragma once
// Plumbing of the geovoronoi command-line tool: argument parsing, bad-input errors, seed files,
// the progress bar. The output folder is in output_dir.hpp, the exit-code contract in errors.hpp.

#include "errors.hpp"      // require_regular_file
#include "output_dir.hpp"  // output_dir
#include "solve.hpp"       // usage_error

#include <geovoronoi/io/common.hpp>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

namespace gvcli {

namespace fs = std::filesystem;
using geovoronoi::index_t;

/// Parsed command line: --name value pairs, flags without a value, and which were given.
class arguments {
 public:
  /// `flags` take no value; every other allowed option takes exactly one.
  arguments(const std::vector<std::string>& args, const std::set<std::string>& with_value,
            const std::set<std::string>& flags) {
    for (std::size_t i = 0; i < args.size(); ++i) {
      const std::string& a = args[i];
      std::string name = a, value;
      bool inline_value = false;
      if (a.rfind("--", 0) != 0) throw usage_error("unexpected argument '" + a + "'");
      const auto eq = a.find('=');
      if (eq != std::string::npos) name = a.substr(0, eq), value = a.substr(eq + 1), inline_value = true;
      if (flags.count(name)) {
        if (inline_value) throw usage_error("option " + name + " takes no value");
        values_[name] = "1";
      } else if (with_value.count(name)) {
        if (!inline_value) {
          if (i + 1 >= args.size() || args[i + 1].rfind("--", 0) == 0) throw usage_error("option " + name + " needs a value");
          value = args[++i];
        }
        if (values_.count(name)) throw usage_error("option " + name + " given twice");
        values_[name] = value;
      } else {
        throw usage_error("unknown option '" + name + "'");
      }
    }
  }
  bool has(const std::string& n) const { return values_.count(n) != 0; }
  std::string get(const std::string& n, const std::string& fallback = {}) const {
    const auto it = values_.find(n);
    return it == values_.end() ? fallback : it->second;
  }
  std::string require(const std::string& n) const {
    if (!has(n)) throw usage_error("missing required option " + n);
    return get(n);
  }
  long long integer(const std::string& n, long long fallback, long long lo, long long hi) const {
    if (!has(n)) return fallback;
    const std::string s = get(n);
    char* end = nullptr;
    const long long x = std::strtoll(s.c_str(), &end, 10);
    if (s.empty() || *end != '\0' || x < lo || x > hi)
      throw usage_error("option " + n + " must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi) +
                        ", got '" + s + "'");
    return x;
  }

 private:
  std::map<std::string, std::string> values_;
};

/// `--threads N`: how many OpenMP threads the thrust backend uses, 1 to max_threads() (4 x the
/// hardware threads); overrides OMP_NUM_THREADS. No effect on seq (one thread) or cuda.
inline void use_threads(const arguments& a) {
  if (!a.has("--threads")) return;
  const int n = int(a.integer("--threads", 0, 1, max_threads()));
#if defined(_OPENMP)
  omp_set_num_threads(n);
#else
  (void)n;
#endif
}

/// Every seed must own its voxel in the diagram @p d: seed i's voxel carries label i. It does not when a
/// path of zero-weight edges (cost 0 under mean_cost) joins two seeds: both are at distance 0 and the
/// lower index wins the tie, so the later seed has no cell and every result built on it is garbage.
/// That is an input problem (exit 2), reported before anything is written.
inline void require_own_voxels(const geovoronoi::diagram<float, 3>& d, const std::string& seeds_path) {
  const auto& g = d.geometry();
  for (std::size_t i = 0; i < d.seeds.size(); ++i) {
    const long long l = d.label[d.seeds[i]];
    if (l == static_cast<long long>(i)) continue;
    const auto c = g.coords(d.seeds[i]);
    throw usage_error(seeds_path + ": seed " + std::to_string(i) + " (" + std::to_string(c[0]) + "," + std::to_string(c[1]) +
                      "," + std::to_string(c[2]) + ") is at geodesic distance 0 from seed " + std::to_string(l) +
                      " (a path of zero-weight edges, e.g. cost 0 under mean_cost, joins them), so it has no cell; "
                      "give the voxels between them a positive value or use another metric");
  }
}

/// One seed as read from the CSV file: up to three numbers and the line it came from.
struct seed_row {
  double x[3] = {0, 0, 0};
  int count = 0;
  int line = 0;
};

/// Reads `i,j,k` (or `x,y,z` in world units) per line; `#` starts a comment; blank lines are skipped.
/// Two values are accepted for single-slice volumes (k = 0).
/// A UTF-8 byte-order mark at the start (Excel's "CSV UTF-8") is skipped.
inline std::vector<seed_row> read_seed_rows(const std::string& path, bool integers) {
  require_regular_file(path, "a seed file");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw usage_error(path + ": cannot open the seed file");
  std::string text;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) {
    text.append(buf, n);
    if (text.size() > (std::size_t(1) << 30)) {
      std::fclose(f);
      throw usage_error(path + ": seed file larger than 1 GiB");
    }
  }
  const bool read_error = std::ferror(f) != 0;
  std::fclose(f);
  if (read_error) throw usage_error(path + ": cannot read the seed file");
  std::vector<seed_row> rows;
  std::size_t pos = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  int line = 0;
  while (pos < text.size()) {
    auto end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string l = text.substr(pos, end - pos);
    pos = end + 1;
    ++line;
    if (const auto h = l.find('#'); h != std::string::npos) l.erase(h);
    for (char& c : l)
      if (c == '\t' || c == '\r') c = ' ';
    if (l.find_first_not_of(' ') == std::string::npos) continue;
    seed_row r;
    r.line = line;
    std::size_t p = 0;
    while (true) {
      const auto comma = l.find(',', p);
      std::string field = l.substr(p, comma == std::string::npos ? std::string::npos : comma - p);
      const auto b = field.find_first_not_of(' ');
      const auto e = field.find_last_not_of(' ');
      field = b == std::string::npos ? std::string() : field.substr(b, e - b + 1);
      if (r.count == 3) throw usage_error(path + ":" + std::to_string(line) + ": more than 3 values");
      char* stop = nullptr;
      const double v = std::strtod(field.c_str(), &stop);
      if (field.empty() || *stop != '\0' || !std::isfinite(v))
        throw usage_error(path + ":" + std::to_string(line) + ": '" + field + "' is not a number");
      if (integers && (v != std::floor(v) || field.find_first_of(".eE") != std::string::npos))
        throw usage_error(path + ":" + std::to_string(line) + ": '" + field +
                          "' is not an integer voxel index (use --world for physical coordinates)");
      r.x[r.count++] = v;
      if (comma == std::string::npos) break;
      p = comma + 1;
    }
    if (r.count < 2) throw usage_error(path + ":" + std::to_string(line) + ": expected i,j,k (3 comma-separated values)");
    rows.push_back(r);
  }
  if (rows.empty()) throw usage_error(path + ": no seeds in the file");
  return rows;
}

/// A progress bar on stderr, drawn only when stderr is a terminal and the run has lasted > 1 s.
class progress_bar {
 public:
  explicit progress_bar(std::string what) : what_(std::move(what)), start_(clock::now()), tty_(isatty(2) != 0) {
    if (tty_) ticker_ = std::thread([this] { run(); });
  }
  ~progress_bar() { finish(); }
  progress_bar(const progress_bar&) = delete;
  progress_bar& operator=(const progress_bar&) = delete;

  /// Current phase and fraction done in [0, 1] (negative: unknown).
  void update(const std::string& phase, double fraction = -1.0) {
    std::lock_guard<std::mutex> lock(mutex_);
    phase_ = phase;
    fraction_ = fraction;
  }
  void set_fraction(double f) { fraction_ = f; }
  double seconds() const { return std::chrono::duration<double>(clock::now() - start_).count(); }

  void finish() {
    if (!ticker_.joinable()) return;
    stop_ = true;
    ticker_.join();
    if (drawn_) std::fprintf(stderr, "\r\033[K");
  }

 private:
  using clock = std::chrono::steady_clock;
  void run() {
    while (!stop_) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      if (stop_ || seconds() < 1.0) continue;
      std::string phase;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        phase = phase_;
      }
      const double f = fraction_;
      char bar[41];
      const int filled = f < 0 ? 0 : int(std::min(1.0, f) * 40);
      for (int i = 0; i < 40; ++i) bar[i] = i < filled ? '#' : (f < 0 ? ' ' : '.');
      bar[40] = '\0';
      if (f < 0) std::fprintf(stderr, "\r\033[K%s: %s %6.1f s", what_.c_str(), phase.c_str(), seconds());
      else std::fprintf(stderr, "\r\033[K%s: %s [%s] %3d%% %6.1f s", what_.c_str(), phase.c_str(), bar, int(f * 100), seconds());
      std::fflush(stderr);
      drawn_ = true;
    }
  }
  std::string what_;
  clock::time_point start_;
  bool tty_;
  std::mutex mutex_;
  std::string phase_ = "starting";
  std::atomic<double> fraction_{-1.0};
  std::atomic<bool> stop_{false};
  bool drawn_ = false;
  std::thread ticker_;
};

}  // namespace gvcli
