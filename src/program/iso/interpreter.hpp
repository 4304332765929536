// Interpreter: applies one checked block to the modal state and emits canonical IR operations.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "program/ir/program.hpp"
#include "program/iso/block.hpp"
#include "program/iso/cutter_comp.hpp"
#include "program/iso/line_error.hpp"
#include "program/iso/m_functions.hpp"
#include "program/iso/modal_state.hpp"
#include "program/iso/parameters.hpp"
#include "program/iso/tool_table.hpp"

namespace softmc::program::iso {

// What the interpreter needs besides the state: the machine's tables and settings.
struct InterpOptions {
  const ToolTable* tools = nullptr;  // null = no tool table: H and D words name no tool
  const MTable* mtable = nullptr;    // null = the fixed P-10 table
  double g23_tolerance_mm = 0.05;    // G23: G64 with this tolerance (P-12)
  // Instructions one block may still make (the program's remaining budget): a canned cycle with
  // many repeats (L) or pecks stops with an error at this many moves instead of running on.
  std::size_t max_ops = static_cast<std::size_t>(-1);
};

// Everything one block produced. Nothing of it takes effect unless the whole block succeeded:
// the caller applies the parameter writes, hands the ops to the output (through the cutter
// compensation stage while it is on) and switches compensation at `comp->at`.
struct BlockOutput {
  std::vector<Op> ops;
  std::vector<std::pair<int, double>> param_writes;  // numbered parameters, in order
  struct CompChange {
    std::size_t at = 0;  // before ops[at]
    bool on = false;
    CompSide side = CompSide::Left;
    double radius_mm = 0;
    std::uint8_t axis0 = 0, axis1 = 1;
  };
  std::optional<CompChange> comp;
  bool m66 = false;  // #5399 becomes a run-time value

  void clear() {
    ops.clear();
    param_writes.clear();
    comp.reset();
    m66 = false;
  }
};

// Executes a block in RS274's order of execution (LinuxCNC "G code order of execution"):
// feed mode, F, S, T, M6, spindle M3 M4 M5, coolant and other M functions, I/O M62…M66, dwell G4,
// plane, units, cutter compensation, tool length, coordinate system, path mode, distance modes,
// retract mode, G10/G28/G30/G92, motion (G53 applies to it), stops M0 M1 M2 M30 M60.
// On error `state` is left unchanged and `out` must be discarded.
std::optional<LineError> execute(const Block& b, ModalState& state, const Parameters& params, const InterpOptions& opt,
                                 BlockOutput& out);

// Machine position of a program point under the state's offsets, and back (P-1 position spaces).
// Turns (x, y) by `deg` degrees counter-clockwise (the G10 L2 R rotation of a coordinate system).
void rotate_xy(core::Vec& v, double deg);
core::Vec to_machine(const ModalState& st, const core::Vec& program);
// No offset at all (bit for bit, so that a -0 offset takes the general path): the common case of a
// CAM program, where to_machine and to_program are the identity.
bool no_offsets(const ModalState& st);
core::Vec to_program(const ModalState& st, const core::Vec& machine);
// The same under given offsets (G10 L20 works out a position in a system not in effect).
core::Vec to_program(const core::Vec& machine, const core::Vec& tool, const core::Vec& work, double rotation_deg,
                     const core::Vec& axis);

// The OffsetsChanged op describing the state's offsets.
OffsetsChanged offsets_of(const ModalState& st);

}  // namespace softmc::program::iso
