// ISO (RS274/NGC) payloads of the Program IR beyond lines, arcs and dwells: splines, path mode,
// tool, spindle, offsets, I/O, messages. Lengths in mm, machine coordinates; rotary axes in degrees.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/axes.hpp"

namespace softmc::program {

// G5 (degree 3) and G5.1 (degree 2): a polynomial Bézier from the current position through the
// control points to `end`, in the plane (axis0, axis1). ctrl2 is unused for degree 2.
struct Bezier {
  core::Vec ctrl1, ctrl2, end;
  std::uint8_t degree = 3;
  std::uint8_t axis0 = 0, axis1 = 1;
  double feed_mm_s = 0;
};

// G5.2 … G5.3: a NURBS with LinuxCNC's uniform clamped knots. ctrl[0] is the position before the
// block (the curve starts there); weights[i] belongs to ctrl[i]; order = degree + 1.
struct Nurbs {
  std::vector<core::Vec> ctrl;
  std::vector<double> weights;
  int order = 3;
  double feed_mm_s = 0;
};

// Path control mode (G61 exact path, G61.1 exact stop, G64 blending, G23 continuous path of
// plc_interface.md P-12). tolerance_mm = 0 means "as fast as possible" (G64 without P).
enum class PathKind : std::uint8_t { ExactPath /*G61*/, ExactStop /*G61.1*/, Blend /*G64, G23*/ };
struct PathMode {
  PathKind kind = PathKind::ExactPath;
  double tolerance_mm = 0;        // G64 P
  double naive_tolerance_mm = 0;  // G64 Q: collinear short moves may be merged within this
  bool continuous = false;        // G23 (P-12 continuous_active follows it)
  bool operator==(const PathMode&) const = default;
};

// S word (G97 rpm) or constant surface speed (G96 S in m/min or ft/min converted to m/min, D max rpm).
struct SpindleSpeed {
  double rpm = 0;               // G97; under G96 the speed at program start is unknown: 0
  bool css = false;             // G96
  double surface_m_min = 0;     // G96 S
  double max_rpm = 0;           // G96 D (0 = no limit)
};

// T word (select) and M6 (change to the selected tool).
struct ToolSelect {
  int tool = 0;
};
struct ToolChange {
  int tool = 0;
};

// M0 (program stop), M1 (optional stop) and M60 (pallet change stop): wait for cycle start.
struct Pause {
  bool optional = false;
};

// The offsets in effect changed (G54…G59.3, G10, G92.x, G43/G49): positions in the IR are already
// machine positions; this tells status displays how program coordinates relate (P-1 position
// spaces): program = rotate⁻¹(machine − tool − work) − axis.
struct OffsetsChanged {
  int coord_system = 1;  // 1 = G54 … 9 = G59.3
  core::Vec work;        // G5x origin offset
  core::Vec axis;        // G92 offset
  core::Vec tool;        // tool length offset
  double rotation_deg = 0;  // XY rotation of the coordinate system (G10 L2 R)
};

// M62/M63 (synchronised with the next motion) and M64/M65 (immediate): digital output P on/off.
struct DigitalOutput {
  int index = 0;
  bool on = false;
  bool synced = false;
};

// M67 (synchronised with the next motion) and M68 (immediate): analog output E (0 … 3, LinuxCNC's
// four) set to Q: a laser's power, a torch height's reference.
inline constexpr int kAnalogOutputs = 4;
struct AnalogOutput {
  int index = 0;
  double value = 0;
  bool synced = false;
};

// M66: wait for input P (digital) or E (analog). mode 0 = no wait (read), 1 rise, 2 fall, 3 high,
// 4 low. timeout_s = Q. The result (#5399) is a run-time value the program may not branch on.
struct WaitInput {
  int index = 0;
  bool digital = true;
  int mode = 0;
  double timeout_s = 0;
};

// (MSG, …) for the operator, (DEBUG, …) and (PRINT, …) with parameters substituted.
enum class MessageKind : std::uint8_t { Msg, Debug, Print };
struct Message {
  MessageKind kind = MessageKind::Msg;
  std::string text;
};

}  // namespace softmc::program

namespace softmc::program {

// Canonical dump text of each ISO payload (used by dump(); defined in program/iso/dump_ops.cpp).
std::string iso_text(const Bezier& op);
std::string iso_text(const Nurbs& op);
std::string iso_text(const PathMode& op);
std::string iso_text(const SpindleSpeed& op);
std::string iso_text(const ToolSelect& op);
std::string iso_text(const ToolChange& op);
std::string iso_text(const Pause& op);
std::string iso_text(const OffsetsChanged& op);
std::string iso_text(const DigitalOutput& op);
std::string iso_text(const AnalogOutput& op);
std::string iso_text(const WaitInput& op);
std::string iso_text(const Message& op);

}  // namespace softmc::program
