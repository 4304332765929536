// The Program IR: what every dialect's parser produces and the Channel executes.
//
// A Program is a flat list of Instructions, each with the source location it came from.
// ISO G-code is interpreted into canonical instructions (motions in machine coordinates with the
// feed in effect, dwells, M functions); the SPC dialect adds control flow (jumps, calls, register
// and I/O operations) that the Channel executes at run time. New dialect features add payload
// types to `Instruction::Op`; existing ones never change meaning.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "core/axes.hpp"
#include "core/diagnostic.hpp"
#include "program/ir/iso_ops.hpp"
#include "program/ir/spc_ops.hpp"

namespace softmc::program {

using core::AxisMask;
using core::SourceLoc;
using core::Vec;

// Straight move at the highest speed the machine permits (G0). `end` is in machine coordinates.
struct Rapid {
  Vec end;
};

// Straight move at the programmed feed (G1).
struct Linear {
  Vec end;
  double feed_mm_s = 0;
};

// Circular arc or helix (G2/G3). The arc lies in the plane of axes (axis0, axis1); a positive
// `turns` goes counter-clockwise seen from the positive normal axis (from axis0 towards axis1).
// |turns| = 1 is an arc of less than or equal to one full revolution; each further unit adds a
// full circle. Axes outside the plane move linearly to `end` (a helix when the normal axis moves).
struct Arc {
  Vec end;
  double center0 = 0, center1 = 0;  // centre in the plane, machine coordinates
  std::uint8_t axis0 = 0, axis1 = 1, normal = 2;
  std::int32_t turns = 1;
  double feed_mm_s = 0;
};

// Wait with no motion (G4).
struct Dwell {
  double seconds = 0;
};

// The cutting tool (torch/spindle) on or off: M3/M4 switch it on, M5 off.
struct ToolSwitch {
  bool on = false;
};

// Any M function, recorded for the PLC interface (groups and change bits, plc_interface.md P-10).
struct MFunction {
  int number = 0;
  std::uint8_t group = 14;  // P-10 group 1..14 (14 = none of the others)
};

// Program end (M2/M30). `rewind` is true for M30.
struct ProgramEnd {
  bool rewind = false;
};

// A payload kept on the heap, shared and immutable, so that the rare large ones (a G5's control
// points, the offsets: 232 bytes each) do not set the size of every Instruction: a CAM program's
// lines are 128 bytes each instead of 256. Read it through op_if / op_holds, which see through
// the box.
template <class T>
class Boxed {
 public:
  Boxed(T v) : p_(std::make_shared<const T>(std::move(v))) {}  // NOLINT: implicit, as the payload itself
  const T& operator*() const { return *p_; }
  const T* operator->() const { return p_.get(); }

 private:
  std::shared_ptr<const T> p_;
};

using Op = std::variant<Rapid, Linear, Arc, Dwell, ToolSwitch, MFunction, ProgramEnd,
                        SpcMove, SpcAxisSetting, SpcDwell, SpcJump, SpcCall, SpcReturn, SpcEnd, SpcSync,
                        SpcPosReg, SpcIntReg, SpcBitTest, SpcBitWrite,
                        Boxed<Bezier>, Nurbs, PathMode, SpindleSpeed, ToolSelect, ToolChange, Pause,
                        Boxed<OffsetsChanged>, DigitalOutput, AnalogOutput, WaitInput, Message>;

namespace detail {
template <class T, class V>
struct IsAlternative;
template <class T, class... Ts>
struct IsAlternative<T, std::variant<Ts...>> : std::disjunction<std::is_same<T, Ts>...> {};
}  // namespace detail

// The op's payload of type T, or nullptr: std::get_if that sees through Boxed.
template <class T>
const T* op_if(const Op& op) {
  if constexpr (detail::IsAlternative<Boxed<T>, Op>::value) {
    const auto* b = std::get_if<Boxed<T>>(&op);
    return b ? &**b : nullptr;
  } else {
    return std::get_if<T>(&op);
  }
}
template <class T>
bool op_holds(const Op& op) {
  return op_if<T>(op) != nullptr;
}
// The payload of a visited alternative (Boxed<T> → T).
template <class T>
const T& unboxed(const T& v) {
  return v;
}
template <class T>
const T& unboxed(const Boxed<T>& v) {
  return *v;
}

struct Instruction {
  SourceLoc loc;
  Op op;
};

// A CAM program's IR is mostly lines: keep each Instruction at 128 bytes (a new large payload goes
// in a Boxed, as Bezier and OffsetsChanged do).
static_assert(sizeof(Instruction) <= 128, "a large IR payload belongs in a Boxed");

struct Program {
  std::vector<std::string> files;  // files[loc.file]; files[0] is the main program
  std::vector<Instruction> instructions;
  Vec start;  // machine position the program assumes at its start (the interpreter's initial state)

  const std::string& file_of(const SourceLoc& l) const { return files.at(l.file); }
};

// True for instructions that move axes.
inline bool is_motion(const Op& op) {
  return std::holds_alternative<Rapid>(op) || std::holds_alternative<Linear>(op) || std::holds_alternative<Arc>(op);
}

// Canonical, deterministic text form (one line per instruction) for golden tests and the CLI.
std::string dump(const Program& p);

}  // namespace softmc::program
