// SPC registers and flags (S-5): position registers @0..@99 per axis, integer registers R0..R99, flags F0..F63.
//
// The cycle owns the values in memory; persistence never touches the cycle. Every retentive write
// stores the value (a relaxed atomic: a plain store on x86) and sets a dirty bit; the persistence
// side (io::RetentiveStore) drains the dirty bits outside the cycle and writes one SQLite
// transaction per batch. Nothing can overflow or block: a register written twice before a flush is
// persisted once, with its newest value.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

#include "program/ir/spc_ops.hpp"

namespace softmc::control::spc {

using program::kSpcAxes;
using program::kSpcFlags;
using program::kSpcRegisters;

enum class RegResult : std::uint8_t { Ok, IndexOutOfRange, ValueOutOfRange, Overflow };
const char* to_string(RegResult r);

enum class RegKind : std::uint8_t { Position = 0, Integer = 1 };

class Registers {
 public:
  Registers();
  Registers(const Registers&) = delete;
  Registers& operator=(const Registers&) = delete;

  // Position registers in 0.01 mm (exact two decimals). rt-safe.
  std::int32_t position_centi(int axis, int i) const { return pos_[axis][i].load(std::memory_order_relaxed); }
  double position_mm(int axis, int i) const { return position_centi(axis, i) / 100.0; }
  RegResult set_position_centi(int axis, int i, std::int64_t v);
  RegResult add_position_centi(int axis, int i, std::int64_t dv);  // out of range = error, register unchanged

  // Integer registers. rt-safe. Overflow is an error, not a wrap (S-5).
  std::int32_t integer(int i) const { return int_[i].load(std::memory_order_relaxed); }
  RegResult set_integer(int i, std::int64_t v);
  RegResult add_integer(int i, std::int64_t dv);

  // Flags: not retentive, start at 0. rt-safe.
  bool flag(int i) const { return (flags_ >> i) & 1u; }
  void set_flag(int i, bool v) { flags_ = v ? flags_ | (1ull << i) : flags_ & ~(1ull << i); }
  void clear_flags() { flags_ = 0; }

  // Persistence side. `restore` loads a value at start-up without marking it dirty.
  void restore(RegKind kind, int axis, int i, std::int32_t v);
  // Calls f(kind, axis, index, value) for every register written since the last drain and clears its
  // dirty bit first (a write racing with the drain is seen now or at the next drain, never lost).
  template <class F>
  void drain_dirty(F&& f) {
    for (int a = 0; a < static_cast<int>(kSpcAxes); ++a)
      drain_words(pos_dirty_[a], [&](int i) { f(RegKind::Position, a, i, position_centi(a, i)); });
    drain_words(int_dirty_, [&](int i) { f(RegKind::Integer, 0, i, integer(i)); });
  }
  bool any_dirty() const;

 private:
  using DirtyBits = std::array<std::atomic<std::uint64_t>, 2>;  // 100 registers → 2 words
  static void mark(DirtyBits& d, int i) { d[i >> 6].fetch_or(1ull << (i & 63), std::memory_order_release); }
  template <class G>
  static void drain_words(DirtyBits& d, G&& g) {
    for (int w = 0; w < 2; ++w) {
      std::uint64_t bits = d[w].exchange(0, std::memory_order_acquire);
      while (bits) {
        const int b = __builtin_ctzll(bits);
        bits &= bits - 1;
        g(w * 64 + b);
      }
    }
  }

  std::array<std::array<std::atomic<std::int32_t>, kSpcRegisters>, kSpcAxes> pos_;
  std::array<std::atomic<std::int32_t>, kSpcRegisters> int_;
  std::array<DirtyBits, kSpcAxes> pos_dirty_;
  DirtyBits int_dirty_;
  std::uint64_t flags_ = 0;
};

}  // namespace softmc::control::spc
