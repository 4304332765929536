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
  // Every point of the segment lies within half_mm (half its length) of mid, its point halfway
  // along: |p − mid| − half_mm is a lower bound of its distance from p.
  core::Vec mid;
  double half_mm = 0;
};

// A bounding ball of kMovesPerGroup consecutive moves (the deviation search skips the group where
// its ball is farther than the nearest move found so far).
struct MoveGroup {
  core::Vec centre;
  double radius_mm = 0;
};

// The program walked from its start position, tracking the tool from ToolSwitch, independently of
// the planner: every motion as a segment, and where the machine stands before and after each
// instruction.
struct ProgrammedPath {
  std::vector<ProgrammedMove> moves;                // in program order
  std::vector<std::optional<std::size_t>> move_of;  // instruction index → index into moves
  std::vector<std::size_t> moves_upto;              // instruction index → moves of it and before it
  std::vector<core::Vec> before;                    // position when instruction i starts
  std::vector<core::Vec> after;                     // position when instruction i has finished
  core::Vec start, end;
  static constexpr std::size_t kMovesPerGroup = 32;
  std::vector<MoveGroup> groups;  // moves [k·kMovesPerGroup, (k+1)·kMovesPerGroup) in groups[k]

  // Distance of p from the programmed path around instructions `tag`..`tag_last` (a line the planner
  // merged from several programmed ones stands for all of them). Moving: from those motions'
  // segments or the motions on either side (a corner blend belongs to both and the tag switches at a
  // cycle boundary, so measuring against one segment alone would overstate it). Standing: from the
  // position before or after that instruction (tag names the motion that just finished), or from its
  // segments (a P-5 stop ends the run at rest inside it). A caller
  // after the largest deviation passes it as `enough`: at or below it, any value at or below it.
  // The search starts at the move nearest the last point asked about (a trace moves along the
  // path), then skips what the move and group bounds rule out: a curve of thousands of pieces costs
  // about a group's bounds per row instead of a Newton search per piece.
  double deviation_mm(const core::Vec& p, std::uint32_t tag, std::uint32_t tag_last, bool moving, double enough = 0) const;

 private:
  // Least distance from p of moves[lo..hi], or any value ≤ enough once one is found.
  double nearest_move_mm(const core::Vec& p, std::size_t lo, std::size_t hi, double enough) const;
  mutable std::size_t hint_ = 0;  // the move found nearest last time
  friend ProgrammedPath programmed_path(const program::Program& prog);
};

ProgrammedPath programmed_path(const program::Program& prog);

}  // namespace softmc::report
