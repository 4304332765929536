// M70/M72/M73 (LinuxCNC's save and restore of modal state): what brings the state back, as blocks.
//
// M70 (and M73) keep a copy of the ModalState at the current call level; M72 (and, after M73, the
// subroutine's return) brings back the modes LinuxCNC saves: units, plane, cutter compensation off,
// distance and arc distance modes, feed mode, coordinate system, tool length offset, retract mode,
// spindle mode (G96 with its D, G97), path control mode, F and S, the spindle (M3/M4/M5), mist and
// flood (M7/M8/M9) and the overrides (M48/M49). The motion mode is not restored (LinuxCNC neither).
//
// The restore runs as ordinary blocks through the interpreter, so each change emits what the code
// itself would (M functions for the PLC, ToolSwitch, SpindleSpeed, OffsetsChanged), and only modes
// that differ are programmed again. What a word cannot give back to the bit (the path tolerance and
// a G43.1 tool length offset, read in program units, and F in mm/s) is set directly afterwards.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "program/iso/interpreter.hpp"
#include "program/iso/lexer.hpp"
#include "program/iso/modal_state.hpp"

namespace softmc::program::iso {

struct ModalRestore {
  // In order: G20/G21 alone (F, S and lengths are read in the units), G40 alone (the plane, the
  // coordinate system and the tool length cannot change while compensation is on), then the rest.
  // Empty blocks are left out. Every word carries `col`.
  std::vector<std::vector<Word>> blocks;
  // Set where the saved state cannot be brought back; nothing is then to be changed.
  std::optional<std::string> error;
};

// The blocks that bring `now` back to `saved` (what differs only). The errors: `saved` has cutter
// compensation on and `now` has it off or on another side or radius (LinuxCNC would turn it on with
// the current tool's radius); `saved` has no programmed path mode (the machine's default applied)
// and `now` has one.
ModalRestore modal_restore_blocks(const ModalState& saved, const ModalState& now, std::uint32_t col);

// After the blocks ran on `st`: the path mode, a G43.1 tool length offset and F set from `saved` to
// the bit; the PathMode and OffsetsChanged instructions their changes need are appended to `ops`.
// An error (the tool length offset cannot change while compensation is on) changes nothing.
std::optional<std::string> restore_exact_modes(const ModalState& saved, ModalState& st, std::vector<Op>& ops);

}  // namespace softmc::program::iso
