// Fixed-capacity FIFO ring, sized once at configuration; push/pop never allocate (rt-safe).
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace softmc::core {

template <class T>
class Ring {
 public:
  explicit Ring(std::size_t capacity = 0) : buf_(capacity), cap_(capacity) {}

  // Configuration time only: allocates.
  void reserve(std::size_t capacity) {
    buf_.assign(capacity, T{});
    cap_ = capacity;
    head_ = size_ = 0;
    ++changes_;
  }

  std::size_t capacity() const { return cap_; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  bool full() const { return size_ == cap_; }

  // rt-safe
  bool push(const T& x) {
    if (full()) return false;
    buf_[slot(size_)] = x;
    ++size_;
    return true;
  }
  // rt-safe
  void pop() {
    assert(size_ > 0);
    head_ = slot(1);
    --size_;
    ++changes_;
    ++pops_;
  }
  T& front() { return buf_[head_]; }
  const T& front() const { return buf_[head_]; }
  // i-th element from the front (i < capacity: one compare instead of a division, which the jerk
  // guard's walks over the window would pay per block).
  T& at(std::size_t i) { return buf_[slot(i)]; }
  const T& at(std::size_t i) const { return buf_[slot(i)]; }
  T& back() { return at(size_ - 1); }
  void clear() {
    head_ = size_ = 0;
    ++changes_;
  }
  // Elements were changed in place: counted like a clear by changes(), so readers derive again.
  void touch() { ++changes_; }
  // Counts pops, clears and touches: while it stays the same, at(i) is the same element for every
  // i < size() (pushes only append). Lets a reader keep what it derived from the elements between calls.
  std::uint64_t changes() const { return changes_; }
  // Counts pops alone: where changes() moved by as much, the elements were only popped (no clear),
  // and at(i) now is at(i + that many) before.
  std::uint64_t pops() const { return pops_; }

 private:
  std::size_t slot(std::size_t i) const {
    assert(i < cap_ || (i == 1 && cap_ == 1));
    const std::size_t j = head_ + i;
    return j >= cap_ ? j - cap_ : j;
  }
  std::vector<T> buf_;
  std::size_t cap_ = 0;  // buf_.size(), kept: the vector's size is a division by sizeof(T)
  std::size_t head_ = 0;
  std::size_t size_ = 0;
  std::uint64_t changes_ = 0;
  std::uint64_t pops_ = 0;
};

}  // namespace softmc::core
