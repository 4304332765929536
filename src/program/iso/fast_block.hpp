// Fast path for the commonest CAM blocks: "[N..] [G0|G1|G2|G3] X.. Y.. Z.. [I.. J..] [F..]".
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "program/ir/program.hpp"
#include "program/iso/modal_state.hpp"

namespace softmc::program::iso {

// What a fast block made: at most one move, located at `col` (its first word).
struct FastBlock {
  std::optional<Op> op;
  std::uint32_t col = 1;
};

// Reads and executes `line` in one pass when it is nothing but an optional N, an optional G0…G3,
// X Y Z words, I J for an arc in the XY plane and an optional F, all plain numbers, and the state
// is the plain one a CAM program runs in (no offsets, no cutter compensation, G94, G0…G3 in
// effect or given, a feed known for feed moves). Then `st` changes exactly as the general path
// (lexer → check_block → execute) would change it, `out` holds what it would emit, and the answer
// is true. Otherwise (anything else, errors included) it changes nothing and answers false: the
// general path reads the line.
// ParseOptions::fast_path turns it off; the fuzz target checks both paths agree.
bool fast_straight_block(std::string_view line, ModalState& st, FastBlock& out);

}  // namespace softmc::program::iso
