#pragma once
// The geovoronoi tool's progress bar on stderr.
#include <geovoronoi/error.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

#include <unistd.h>

namespace gvcli {

/// Progress on stderr, only when stderr is a terminal: a bar redrawn in place once the run has lasted
/// > 1 s, with the time left, estimated from the current phase's rate, once the phase has run 2 s and
/// done 1 % (the libraries' fractions follow the work done, not the count of queries or nodes, see
/// docs/shape-functions.md). Elsewhere (a log file, a pipe) nothing: stderr then holds only the notes
/// and warnings of note(), and a failure's one line.
class progress_bar {
 public:
  explicit progress_bar(std::string what)
      : what_(std::move(what)), start_(clock::now()), phase_start_(start_), tty_(isatty(2) != 0) {
    if (tty_) ticker_ = std::thread([this] { run(); });
  }
  ~progress_bar() { finish(); }
  progress_bar(const progress_bar&) = delete;
  progress_bar& operator=(const progress_bar&) = delete;

  /// Current phase and fraction done in [0, 1] (negative: unknown).
  void update(const std::string& phase, double fraction = -1.0) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (phase != phase_) phase_start_ = clock::now();
    phase_ = phase;
    fraction_ = fraction;
  }
  void set_fraction(double f) { fraction_ = f; }
  /// One line on stderr (a warning or a note), on its own line even while the bar is drawn; escaped
  /// as the error line is (geovoronoi::printable), since it may name input files.
  void note(const std::string& line) {
    std::lock_guard<std::mutex> lock(print_mutex_);
    if (drawn_ && tty_) std::fprintf(stderr, "\r\033[K");
    std::fprintf(stderr, "%s\n", geovoronoi::printable(line, std::string::npos).c_str());
    std::fflush(stderr);
  }
  double seconds() const { return std::chrono::duration<double>(clock::now() - start_).count(); }

  void finish() {
    if (!ticker_.joinable()) return;
    stop_ = true;
    ticker_.join();
    if (drawn_ && tty_) std::fprintf(stderr, "\r\033[K");
  }

  /// "about 1 min 20 s left" for a phase that has run @p elapsed seconds and done @p f; empty while
  /// the estimate would be noise.
  static std::string time_left(double elapsed, double f) {
    if (!(f >= 0.01) || f >= 1.0 || elapsed < 2.0) return {};
    const double left = elapsed * (1.0 - f) / f;
    char buf[64];
    if (left < 60) std::snprintf(buf, sizeof buf, "about %.0f s left", left);
    else if (left < 3600) std::snprintf(buf, sizeof buf, "about %d min %02d s left", int(left / 60), int(left) % 60);
    else std::snprintf(buf, sizeof buf, "about %d h %02d min left", int(left / 3600), int(left / 60) % 60);
    return buf;
  }

 private:
  using clock = std::chrono::steady_clock;
  void run() {
    while (!stop_) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      const double now = seconds();
      if (stop_ || now < 1.0) continue;
      std::string phase;
      double phase_seconds;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        phase = phase_;
        phase_seconds = std::chrono::duration<double>(clock::now() - phase_start_).count();
      }
      const double f = fraction_;
      std::lock_guard<std::mutex> print_lock(print_mutex_);
      std::string left = time_left(phase_seconds, f);
      if (!left.empty()) left = ", " + left;
      char bar[41];
      const int filled = f < 0 ? 0 : int(std::min(1.0, f) * 40);
      for (int i = 0; i < 40; ++i) bar[i] = i < filled ? '#' : (f < 0 ? ' ' : '.');
      bar[40] = '\0';
      if (f < 0) std::fprintf(stderr, "\r\033[K%s: %s %6.1f s", what_.c_str(), phase.c_str(), seconds());
      else
        std::fprintf(stderr, "\r\033[K%s: %s [%s] %3d%% %6.1f s%s", what_.c_str(), phase.c_str(), bar, int(f * 100), now,
                     left.c_str());
      std::fflush(stderr);
      drawn_ = true;
    }
  }
  std::string what_;
  clock::time_point start_;
  clock::time_point phase_start_;  // guarded by mutex_
  bool tty_;
  std::mutex mutex_;
  std::mutex print_mutex_;  // one writer at a time on stderr; guards drawn_
  std::string phase_ = "starting";
  std::atomic<double> fraction_{-1.0};
  std::atomic<bool> stop_{false};
  bool drawn_ = false;
  std::thread ticker_;
};

}  // namespace gvcli
