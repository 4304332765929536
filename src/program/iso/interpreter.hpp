// Interpreter: applies one checked block to the modal state and emits canonical IR operations.
#pragma once

#include <optional>
#include <vector>

#include "program/ir/program.hpp"
#include "program/iso/block.hpp"
#include "program/iso/line_error.hpp"
#include "program/iso/modal_state.hpp"

namespace softmc::program::iso {

// Executes a block in RS274's order of execution (LinuxCNC "G code order of execution"):
// feed, spindle/torch M3 M4 M5, dwell G4, plane/units/distance modes, motion, program end M2 M30.
// On error the state is left unchanged and nothing is appended to `out`.
std::optional<LineError> execute(const Block& b, ModalState& state, std::vector<Op>& out);

}  // namespace softmc::program::iso
