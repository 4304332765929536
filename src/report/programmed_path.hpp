// The programmed geometry of a Program, indexed by instruction: what reports measure the trace against.
#pragma once

#include <cassert>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "core/axes.hpp"
#include "motion/geometry/segment.hpp"
#include "program/ir/program.hpp"

namespace softmc::report {

enum class MoveKind : std::uint8_t { Rapid, Feed, Cut };  // Cut = feed move with the tool on

// A line is kept as its end (a whole motion::Segment is 1.3 kB, most of it a curve's: a 200 000-line
// CAM program's moves were 300 MB); its start is the move before's end (or the path's start), its
// direction derived from both as motion::make_line derives it. Arcs and curves are a Segment in
// ProgrammedPath::curves. The end is ProgrammedPath::end_of: the path keeps the moves' ends on the
// axes the program uses only (a Vec is nine coordinates, a CAM program's three).
struct ProgrammedMove {
  std::uint32_t instruction = 0;  // index into Program::instructions
  std::uint32_t curve = 0;        // not a line: its index into ProgrammedPath::curves
  MoveKind kind = MoveKind::Feed;
  bool line = true;
  double length = 0;  // mm
  // (Its bounding box is ProgrammedPath::box: a line's from its ends, a curve's kept with it.)
};

// A bounding box: of a curve (Segment::bounds), or of kMovesPerGroup consecutive moves (the deviation
// search skips the group where its box is farther than the nearest move found so far).
struct MoveGroup {
  core::Vec lo, hi;
};

// The program walked from its start position, tracking the tool from ToolSwitch, independently of
// the planner: every motion as a segment, and where the machine stands before and after each
// instruction.
struct ProgrammedPath {
  std::vector<ProgrammedMove> moves;                // in program order
  std::vector<motion::Segment> curves;              // the moves that are not lines (ProgrammedMove::curve)
  std::vector<MoveGroup> curve_box;                 // their bounding boxes (Segment::bounds)
  // Instruction index → the number of moves of it and the instructions before it. What else a
  // report asks of an instruction is taken from it (a CAM program's per-instruction position and
  // first move, 88 bytes a line, were kept apart before): the same values.
  std::vector<std::uint32_t> moves_upto;
  // The instruction's first move, nothing for an instruction without motion.
  std::optional<std::size_t> move_of(std::size_t i) const {
    const std::size_t first = i > 0 ? moves_upto[i - 1] : 0;
    return moves_upto[i] > first ? std::optional<std::size_t>(first) : std::nullopt;
  }
  // Position when instruction i starts and when it has finished (where the next one starts), i < the
  // number of instructions: the end of the last move before it, or the path's start.
  core::Vec before(std::size_t i) const { return i > 0 ? after(i - 1) : start; }
  core::Vec after(std::size_t i) const { return moves_upto[i] > 0 ? end_of(moves[moves_upto[i] - 1]) : start; }
  core::Vec start, end;
  std::vector<double> along_mm;  // path length from the start to the start of each move (and the end)
  // A setpoint on a smoothing piece may lie on moves a little before or after the instructions it
  // is tagged with: the spline's points are low-pass filtered, and a leg over thinned 1 µm lines
  // (control::Channel) stands for up to 65 of them. The search reaches one move either side, and
  // further along up to kReach_mm of path (at most kReachMoves moves) each way.
  static constexpr double kReach_mm = 0.5;
  static constexpr std::size_t kReachMoves = 256;
  static constexpr std::size_t kMovesPerGroup = 32;
  std::vector<MoveGroup> groups;  // moves [k·kMovesPerGroup, (k+1)·kMovesPerGroup) in groups[k]

  // Where move m starts: where the move before it ended (the path's start for the first). The
  // functions below take a move of `moves` (by reference, as iterating them gives it).
  core::Vec start_of(const ProgrammedMove& m) const {
    assert(&m >= moves.data() && &m < moves.data() + moves.size());  // one of moves, not a copy
    return &m == moves.data() ? start : end_of(*(&m - 1));
  }
  // Where move m ends, every coordinate as the walk's segment ended.
  core::Vec end_of(const ProgrammedMove& m) const {
    assert(&m >= moves.data() && &m < moves.data() + moves.size());
    core::Vec e;
    const double* p = ends_.data() + static_cast<std::size_t>(&m - moves.data()) * stride_;
    for (std::size_t i = 0; i < stride_; ++i) e[i] = p[i];
    return e;
  }
  // The move's bounding box (every point of it inside: p's distance from the box is a lower bound of
  // its distance from the move), as Segment::bounds gives it.
  void box(const ProgrammedMove& m, core::Vec& lo, core::Vec& hi) const;
  // The move as a segment (a line's built again, as make_line builds it).
  motion::Segment segment(const ProgrammedMove& m) const;
  // Distance of p from the move: Segment::distance_to, a line's without building its Segment.
  double distance(const ProgrammedMove& m, const core::Vec& p, double enough = 0) const;

  // Distance of p from the programmed path around instructions `tag`..`tag_last` (a line the planner
  // merged from several programmed ones stands for all of them). Moving: from those motions'
  // segments or the motions on either side (a corner blend belongs to both and the tag switches at a
  // cycle boundary, so measuring against one segment alone would overstate it; a P-5 stop that
  // ends the run inside a motion is measured so too: pass moving). Standing: from the position
  // before or after that instruction (tag names the motion that just finished). A caller
  // after the largest deviation passes it as `enough`: at or below it, any value at or below it.
  // The search starts at the move nearest the last point asked about (a trace moves along the
  // path), then skips what the move and group boxes rule out: a curve of thousands of pieces costs
  // about a box per group per row instead of a Newton search per piece. It keeps that start in the
  // path (a const method that writes a hint): one ProgrammedPath per thread.
  double deviation_mm(const core::Vec& p, std::uint32_t tag, std::uint32_t tag_last, bool moving, double enough = 0) const;
  // The instruction whose motion lies nearest p among those deviation_mm measures from (a setpoint
  // on a smoothing piece or a blend carries one instruction's tag, but may lie on its neighbour);
  // nothing for an instruction without motion.
  std::optional<std::size_t> nearest_instruction(const core::Vec& p, std::uint32_t tag, std::uint32_t tag_last) const;

 private:
  // The moves of instructions tag..tag_last, one on either side and the reach (first, last).
  std::pair<std::size_t, std::size_t> moves_around(std::uint32_t tag, std::uint32_t tag_last) const;
  // Least distance from p of moves[range.first..range.second], or any value ≤ enough once one is
  // found; hint_ is then the move it came from.
  double nearest_move_mm(const core::Vec& p, std::pair<std::size_t, std::size_t> range, double enough) const;
  // Appends the end of the move just pushed to `moves`.
  void push_end(const core::Vec& e);
  // The moves' ends, stride_ coordinates each: the axes up to the last one any end has off zero (in
  // its bits: a −0 is kept); the others are zero.
  std::vector<double> ends_;
  std::size_t stride_ = 0;
  mutable std::size_t hint_ = 0;  // the move found nearest last time
  friend ProgrammedPath programmed_path(const program::Program& prog);
};

ProgrammedPath programmed_path(const program::Program& prog);

}  // namespace softmc::report
