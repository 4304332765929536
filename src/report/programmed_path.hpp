// The programmed geometry of a Program, indexed by instruction: what reports measure the trace against.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/axes.hpp"
#include "motion/geometry/segment.hpp"
#include "program/ir/program.hpp"

namespace softmc::report {

enum class MoveKind : std::uint8_t { Rapid, Feed, Cut };  // Cut = feed move with the tool on

struct ProgrammedMove {
  std::size_t instruction = 0;  // index into Program::instructions
  MoveKind kind = MoveKind::Feed;
  motion::Segment segment;
};

// The program walked from its start position, tracking the tool from ToolSwitch, independently of
// the planner: every motion as a segment, and where the machine stands before and after each
// instruction.
struct ProgrammedPath {
  std::vector<ProgrammedMove> moves;                // in program order
  std::vector<std::optional<std::size_t>> move_of;  // instruction index → index into moves
  std::vector<core::Vec> before;                    // position when instruction i starts
  std::vector<core::Vec> after;                     // position when instruction i has finished
  core::Vec start, end;

  // Distance of p from the programmed path around instructions `tag`..`tag_last` (a line the planner
  // merged from several programmed ones stands for all of them). Moving: from those motions'
  // segments or the motions on either side (a corner blend belongs to both and the tag switches at a
  // cycle boundary, so measuring against one segment alone would overstate it). Standing: from the
  // position before or after that instruction (tag names the motion that just finished), or from its
  // segments (a P-5 stop ends the run at rest inside it). A caller
  // after the largest deviation passes it as `enough`: at or below it, any value at or below it.
  double deviation_mm(const core::Vec& p, std::uint32_t tag, std::uint32_t tag_last, bool moving, double enough = 0) const;
};

ProgrammedPath programmed_path(const program::Program& prog);

}  // namespace softmc::report
