// SPC registers: range-checked writes that mark the register dirty for the persistence side.
#include "control/spc/registers.hpp"

namespace softmc::control::spc {

const char* to_string(RegResult r) {
  switch (r) {
    case RegResult::Ok: return "ok";
    case RegResult::IndexOutOfRange: return "register index out of range";
    case RegResult::ValueOutOfRange: return "register value out of range";
    case RegResult::Overflow: return "register overflow";
  }
  return "?";
}

Registers::Registers() {
  for (auto& axis : pos_)
    for (auto& r : axis) r.store(0, std::memory_order_relaxed);
  for (auto& r : int_) r.store(0, std::memory_order_relaxed);
  for (auto& d : pos_dirty_)
    for (auto& w : d) w.store(0, std::memory_order_relaxed);
  for (auto& w : int_dirty_) w.store(0, std::memory_order_relaxed);
}

namespace {
bool valid(int axis, int i) {
  return axis >= 0 && axis < static_cast<int>(kSpcAxes) && i >= 0 && i < kSpcRegisters;
}
}  // namespace

RegResult Registers::set_position_centi(int axis, int i, std::int64_t v) {
  if (!valid(axis, i)) return RegResult::IndexOutOfRange;
  if (v < -program::kSpcPosMaxCenti || v > program::kSpcPosMaxCenti) return RegResult::ValueOutOfRange;
  pos_[axis][i].store(static_cast<std::int32_t>(v), std::memory_order_relaxed);
  mark(pos_dirty_[axis], i);
  return RegResult::Ok;
}

RegResult Registers::add_position_centi(int axis, int i, std::int64_t dv) {
  if (!valid(axis, i)) return RegResult::IndexOutOfRange;
  const std::int64_t v = std::int64_t{position_centi(axis, i)} + dv;
  if (v < -program::kSpcPosMaxCenti || v > program::kSpcPosMaxCenti) return RegResult::Overflow;
  return set_position_centi(axis, i, v);
}

RegResult Registers::set_integer(int i, std::int64_t v) {
  if (i < 0 || i >= kSpcRegisters) return RegResult::IndexOutOfRange;
  if (v < -program::kSpcIntMax || v > program::kSpcIntMax) return RegResult::ValueOutOfRange;
  int_[i].store(static_cast<std::int32_t>(v), std::memory_order_relaxed);
  mark(int_dirty_, i);
  return RegResult::Ok;
}

RegResult Registers::add_integer(int i, std::int64_t dv) {
  if (i < 0 || i >= kSpcRegisters) return RegResult::IndexOutOfRange;
  const std::int64_t v = std::int64_t{integer(i)} + dv;
  if (v < -program::kSpcIntMax || v > program::kSpcIntMax) return RegResult::Overflow;
  return set_integer(i, v);
}

void Registers::restore(RegKind kind, int axis, int i, std::int32_t v) {
  if (kind == RegKind::Position) {
    if (valid(axis, i)) pos_[axis][i].store(v, std::memory_order_relaxed);
  } else if (i >= 0 && i < kSpcRegisters) {
    int_[i].store(v, std::memory_order_relaxed);
  }
}

bool Registers::any_dirty() const {
  for (const auto& d : pos_dirty_)
    for (const auto& w : d)
      if (w.load(std::memory_order_acquire)) return true;
  for (const auto& w : int_dirty_)
    if (w.load(std::memory_order_acquire)) return true;
  return false;
}

}  // namespace softmc::control::spc
