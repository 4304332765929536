// Seqlock snapshot: the cycle publishes a value without blocking; readers retry until they see a whole one.
#pragma once

#include <atomic>
#include <type_traits>

namespace softmc::core {

template <class T>
class Snapshot {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  // Writer (the cycle): rt-safe, wait-free.
  void publish(const T& v) {
    const auto s = seq_.load(std::memory_order_relaxed);
    seq_.store(s + 1, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    value_ = v;
    std::atomic_thread_fence(std::memory_order_release);
    seq_.store(s + 2, std::memory_order_release);
  }

  // Reader: retries while a write is under way.
  T read() const {
    for (;;) {
      const auto s0 = seq_.load(std::memory_order_acquire);
      if (s0 & 1) continue;
      T v = value_;
      std::atomic_thread_fence(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == s0) return v;
    }
  }

 private:
  std::atomic<unsigned> seq_{0};
  T value_{};
};

}  // namespace softmc::core
