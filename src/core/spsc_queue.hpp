// Lock-free single-producer single-consumer queue: how commands reach the cycle (rt-safe on both ends).
#pragma once

#include <atomic>
#include <cstddef>
#include <optional>
#include <vector>

namespace softmc::core {

template <class T>
class SpscQueue {
 public:
  explicit SpscQueue(std::size_t capacity) : buf_(capacity + 1) {}

  bool push(const T& x) {
    const auto h = head_.load(std::memory_order_relaxed);
    const auto n = (h + 1) % buf_.size();
    if (n == tail_.load(std::memory_order_acquire)) return false;
    buf_[h] = x;
    head_.store(n, std::memory_order_release);
    return true;
  }

  std::optional<T> pop() {
    const auto t = tail_.load(std::memory_order_relaxed);
    if (t == head_.load(std::memory_order_acquire)) return std::nullopt;
    T x = buf_[t];
    tail_.store((t + 1) % buf_.size(), std::memory_order_release);
    return x;
  }

 private:
  std::vector<T> buf_;
  alignas(64) std::atomic<std::size_t> head_{0};
  alignas(64) std::atomic<std::size_t> tail_{0};
};

}  // namespace softmc::core
