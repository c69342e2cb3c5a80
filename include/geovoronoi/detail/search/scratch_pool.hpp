#pragma once
// Worker scratch for host-parallel query loops under a memory budget: each task leases one worker's
// scratch (the searches' key arrays are the size of the grid), at most as many as the budget holds.

#include <geovoronoi/config.hpp>

#include <condition_variable>
#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <type_traits>
#include <utility>
#include <vector>

namespace geovoronoi::detail::search {

/**
 * At most @p limit scratch objects, created on demand and handed to tasks one at a time. A task that
 * finds none free while @p limit exist waits for one (only when the budget allows fewer scratches than
 * the backend has threads). Each scratch is built by make() outside the lock.
 */
template <class S>
class scratch_pool {
 public:
  template <class Make>
  scratch_pool(std::size_t limit, Make&& make) : limit_(limit < 1 ? 1 : limit), make_(std::forward<Make>(make)) {}

  class lease {
   public:
    lease(scratch_pool& pool, S* s) : pool_(pool), s_(s) {}
    lease(const lease&) = delete;
    lease& operator=(const lease&) = delete;
    ~lease() { pool_.release(s_); }
    S& operator*() const noexcept { return *s_; }
    S* operator->() const noexcept { return s_; }

   private:
    scratch_pool& pool_;
    S* s_;
  };

  lease acquire() {
    std::unique_lock<std::mutex> lk(m_);
    for (;;) {
      if (!free_.empty()) {
        S* s = free_.back();
        free_.pop_back();
        return lease(*this, s);
      }
      if (created_ < limit_) {
        ++created_;
        lk.unlock();
        std::unique_ptr<S> made;
        try {
          made = make_();
        } catch (...) {
          lk.lock();
          --created_;
          cv_.notify_one();
          throw;
        }
        S* s = made.get();
        lk.lock();
        all_.push_back(std::move(made));
        return lease(*this, s);
      }
      cv_.wait(lk);
    }
  }

  /// Calls f(scratch) for every scratch created so far (not concurrently with tasks).
  template <class F>
  void for_each(F&& f) const {
    for (const auto& s : all_) f(*s);
  }
  std::size_t created() const noexcept { return all_.size(); }

 private:
  void release(S* s) {
    {
      std::lock_guard<std::mutex> lk(m_);
      free_.push_back(s);
    }
    cv_.notify_one();
  }

  std::size_t limit_;
  std::function<std::unique_ptr<S>()> make_;
  std::size_t created_ = 0;
  std::mutex m_;
  std::condition_variable cv_;
  std::vector<S*> free_;
  std::vector<std::unique_ptr<S>> all_;
};

}  // namespace geovoronoi::detail::search
