// Walks a Program into segments and positions, without the planner.
#include "report/programmed_path.hpp"

#include <algorithm>

#include "control/path.hpp"

namespace softmc::report {

ProgrammedPath programmed_path(const program::Program& prog) {
  ProgrammedPath pp;
  const std::size_t n = prog.instructions.size();
  pp.move_of.resize(n);
  pp.before.resize(n);
  pp.after.resize(n);
  pp.start = prog.start;
  core::Vec pos = prog.start;
  bool tool_on = false;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& op = prog.instructions[i].op;
    pp.before[i] = pos;
    if (const auto* t = std::get_if<program::ToolSwitch>(&op)) tool_on = t->on;
    if (auto seg = control::to_segment(op, pos)) {
      ProgrammedMove m;
      m.instruction = i;
      m.kind = std::holds_alternative<program::Rapid>(op) ? MoveKind::Rapid : tool_on ? MoveKind::Cut : MoveKind::Feed;
      m.segment = *seg;
      pos = seg->end;
      pp.move_of[i] = pp.moves.size();
      pp.moves.push_back(m);
    }
    pp.after[i] = pos;
  }
  pp.end = pos;
  return pp;
}

double ProgrammedPath::deviation_mm(const core::Vec& p, std::uint32_t tag, bool moving) const {
  if (tag >= before.size()) return core::distance(p, end);
  if (moving && move_of[tag]) {
    const std::size_t m = *move_of[tag];
    double d = moves[m].segment.distance_to(p);
    if (m > 0) d = std::min(d, moves[m - 1].segment.distance_to(p));
    if (m + 1 < moves.size()) d = std::min(d, moves[m + 1].segment.distance_to(p));
    return d;
  }
  return std::min(core::distance(p, before[tag]), core::distance(p, after[tag]));
}

}  // namespace softmc::report
