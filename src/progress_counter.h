// Internal: turns per-item ticks from parallel loops into at most ~100
// serialized calls of a ProgressFn.
#pragma once

#include <atomic>
#include <cstddef>
#include <mutex>

#include "detexture/types.h"

namespace detexture {

class ProgressCounter {
 public:
  ProgressCounter(const ProgressFn& fn, std::size_t total) : fn_(fn), total_(total) {}

  /// Record that n more items are done. Safe to call from many threads.
  void advance(std::size_t n) {
    if (!fn_ || total_ == 0) return;
    const std::size_t done = done_.fetch_add(n, std::memory_order_relaxed) + n;
    const int percent = static_cast<int>(100.0 * static_cast<double>(done) / total_);
    int reported = reported_.load(std::memory_order_relaxed);
    if (percent <= reported) return;
    std::lock_guard<std::mutex> lock(mutex_);
    reported = reported_.load(std::memory_order_relaxed);
    if (percent <= reported) return;
    reported_.store(percent, std::memory_order_relaxed);
    fn_(percent >= 100 ? 1.0 : percent / 100.0);
  }

 private:
  const ProgressFn& fn_;
  const std::size_t total_;
  std::atomic<std::size_t> done_{0};
  std::atomic<int> reported_{-1};
  std::mutex mutex_;
};

}  // namespace detexture
