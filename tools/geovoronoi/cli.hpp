#pragma once
// Plumbing of the geovoronoi command-line tool: argument parsing, bad-input errors, seed files,
// the progress bar, and the temporary output folder that is renamed into place only when complete.

#include "solve.hpp"  // usage_error

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

/// One seed as read from the CSV file: up to three numbers and the line it came from.
struct seed_row {
  double x[3] = {0, 0, 0};
  int count = 0;
  int line = 0;
};

/// Reads `i,j,k` (or `x,y,z` in world units) per line; `#` starts a comment; blank lines are skipped.
/// Two values are accepted for single-slice volumes (k = 0).
inline std::vector<seed_row> read_seed_rows(const std::string& path, bool integers) {
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
  std::fclose(f);
  std::vector<seed_row> rows;
  std::size_t pos = 0;
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

/// The output folder: everything is written to DIR.partial-<pid> and moved into DIR by commit();
/// if the command fails, the partial folder is removed, so no half-written output looks complete.
class output_dir {
 public:
  explicit output_dir(const std::string& dir) : final_(dir) {
    if (dir.empty()) throw usage_error("--out needs a folder name");
    if (fs::exists(final_) && !fs::is_directory(final_)) throw usage_error(dir + ": exists and is not a folder");
    fs::path parent = final_.parent_path();
    if (!parent.empty() && !fs::is_directory(parent))
      throw usage_error(dir + ": the parent folder " + parent.string() + " does not exist");
    temp_ = final_;
    temp_ += ".partial-" + std::to_string(::getpid());
    std::error_code ec;
    fs::remove_all(temp_, ec);
    if (!fs::create_directory(temp_, ec) || ec) throw usage_error(dir + ": cannot create the output folder " + temp_.string());
  }
  ~output_dir() {
    if (!committed_) {
      std::error_code ec;
      fs::remove_all(temp_, ec);
    }
  }
  output_dir(const output_dir&) = delete;
  output_dir& operator=(const output_dir&) = delete;

  /// Path of a file (or subfolder, created) inside the temporary folder.
  std::string file(const std::string& name) const { return (temp_ / name).string(); }
  std::string subdir(const std::string& name) const {
    fs::create_directories(temp_ / name);
    return (temp_ / name).string();
  }

  /// Moves the finished outputs into place: the whole folder when DIR does not exist (or is empty),
  /// else file by file (each rename replaces the old file at once).
  void commit() {
    std::error_code ec;
    if (fs::exists(final_) && fs::is_empty(final_)) fs::remove(final_, ec);
    if (!fs::exists(final_)) {
      fs::rename(temp_, final_, ec);
      if (ec) throw std::runtime_error(final_.string() + ": cannot move the outputs into place: " + ec.message());
    } else {
      move_into(temp_, final_);
      fs::remove_all(temp_, ec);
    }
    committed_ = true;
  }

 private:
  static void move_into(const fs::path& from, const fs::path& to) {
    for (const auto& e : fs::directory_iterator(from)) {
      const fs::path target = to / e.path().filename();
      if (e.is_directory()) {
        if (fs::exists(target) && !fs::is_directory(target)) fs::remove(target);
        fs::create_directories(target);
        move_into(e.path(), target);
      } else {
        fs::rename(e.path(), target);
      }
    }
  }
  fs::path final_, temp_;
  bool committed_ = false;
};

}  // namespace gvcli
