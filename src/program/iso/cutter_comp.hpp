// Cutter radius (kerf) compensation G40/G41/G42/G41.1/G42.1: programmed moves in, tool-centre moves out.
//
// The interpreter keeps working in programmed coordinates and routes every canonical instruction
// through this stage while compensation is on. The stage holds the last compensated move back until
// the next move shows what the corner between them is (one move of look-ahead, as LinuxCNC does):
//
//        programmed  ─────────────┐ corner                outside (convex): the held move ends on the
//        tool path   ═════════════╗·╮                     offset, then an arc of the tool radius about
//                                 ║ │ (arc about corner)  the corner joins the next offset move.
//                                 ║ ▼                     inside (concave): both offset moves are cut
//                                                         back to their intersection (line-line,
//                                                         line-arc, arc-arc); a cut-back that would
//                                                         reverse a move is a gouge and an error.
//
// The first move after G41/G42 is the entry (LinuxCNC's rules): a straight move from the current
// tool position to the programmed end point offset perpendicular to the entry move, which must be
// longer than the tool radius; or an arc (LinuxCNC 2.9 convert_arc_comp1) to the programmed end
// point moved by the tool radius along the radius, about a centre moved along that radius so that
// it starts at the tool. G40 flushes the held move; the next move then starts where the tool is
// (the last end the IR gave), while the interpreter's position is the programmed point again, as
// LinuxCNC's (#5420…, G91). Under compensation the interpreter reads where the tool is from
// tool_position() for the position parameters. Moves with no motion in the plane
// (Z plunges) keep the tool at its offset point; non-motion instructions keep their order.
//
// Usage by the interpreter (the hook):
//   comp.start(side, radius, plane axes, position)     on G41/G42 (G41.1/G42.1: radius = D / 2)
//   comp.push(instruction, out)                        every instruction while active()
//   comp.stop(out)                                     on G40 and at program end (M2/M30, EOF)
// Errors come back with the location of the instruction being pushed (file:line:col in the
// diagnostic) and the stage is left unchanged, so the caller may report and go on.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/axes.hpp"
#include "program/ir/program.hpp"

namespace softmc::program::iso {

enum class CompSide : std::uint8_t { Left, Right };  // G41 (tool left of the path), G42 (right)

struct CompError {
  core::SourceLoc loc;  // the instruction that revealed the problem
  std::string message;
};

// Corners that turn by less than this (radians) are taken as tangent: no arc, no cut-back
// (LinuxCNC TOLERANCE_CONCAVE_CORNER).
inline constexpr double kCompTangentTolerance = 0.05;

class CutterComp {
 public:
  bool active() const { return active_; }
  CompSide side() const { return side_; }
  double radius_mm() const { return radius_mm_; }

  // Turns compensation on (G41/G42). `position` is the current tool position (machine
  // coordinates); `axis0`/`axis1` span the active plane (X,Y for G17; Z,X for G18; Y,Z for G19).
  // Refused (with a message) when already on or when the radius is negative or not finite.
  std::optional<std::string> start(CompSide side, double radius_mm, std::uint8_t axis0, std::uint8_t axis1,
                                   const core::Vec& position);

  // One canonical instruction in program order, uncompensated (Rapid/Linear/Arc in programmed
  // coordinates; arcs must lie in the compensation plane). Finished, compensated instructions are
  // appended to `out`; the last move and what follows it are held back until the next move.
  std::optional<CompError> push(const Instruction& in, std::vector<Instruction>& out);

  // G40 (or program end): releases everything held and turns compensation off.
  void stop(std::vector<Instruction>& out);

  // Where the tool is (or will be once the held instructions are released): the compensated end
  // of the last move, before the next move's corner is known (LinuxCNC's #5420… under compensation).
  const core::Vec& tool_position() const { return tool_; }

 private:
  // A compensated move in the plane: its tool-centre path plus the programmed geometry that the
  // next corner needs (programmed end point and tangent direction there).
  struct Held {
    Instruction ins;          // the compensated instruction (its end is moved at inside corners)
    core::Vec start;          // tool-centre start
    bool is_arc = false;
    bool is_rapid = false;
    double cx = 0, cy = 0;    // arc centre (plane coordinates)
    double r = 0;             // compensated arc radius
    int dir = 1;              // +1 counter-clockwise, -1 clockwise
    double sweep = 0;         // |swept angle| of the compensated arc before any cut-back (radians)
    double dx = 0, dy = 0;    // unit direction of a line (programmed)
  };

  std::optional<CompError> push_motion(const Instruction& in, std::vector<Instruction>& out);
  void release(std::vector<Instruction>& out);

  bool active_ = false;
  bool first_move_ = true;  // the next plane move is the entry move
  CompSide side_ = CompSide::Left;
  double radius_mm_ = 0;
  std::uint8_t a0_ = 0, a1_ = 1;
  core::Vec programmed_;     // programmed position (end of the last programmed move)
  core::Vec tool_;           // compensated tool position
  double end_tx_ = 0, end_ty_ = 0;  // programmed tangent at the end of the last plane move
  std::optional<Held> held_;         // the last plane move, not yet released
  std::vector<Instruction> after_;   // instructions after the held move (kept in order)
};

}  // namespace softmc::program::iso
