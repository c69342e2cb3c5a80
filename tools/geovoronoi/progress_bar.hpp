#pragma once
// The geovoronoi tool's progress bar on stderr.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

#include <unistd.h>

namespace gvcli {

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
