// Walks a Program into segments and positions, without the planner.
#include "report/programmed_path.hpp"

#include <algorithm>
#include <limits>

#include "control/path.hpp"

namespace softmc::report {

ProgrammedPath programmed_path(const program::Program& prog) {
  ProgrammedPath pp;
  const std::size_t n = prog.instructions.size();
  pp.move_of.resize(n);
  pp.before.resize(n);
  pp.after.resize(n);
  pp.start = prog.start;
  // The same geometry the channel plans (curves expanded into several pieces).
  const auto geo = control::program_geometry(prog);
  std::size_t next_piece = 0;
  core::Vec pos = prog.start;
  bool tool_on = false;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& op = prog.instructions[i].op;
    pp.before[i] = pos;
    if (const auto* t = std::get_if<program::ToolSwitch>(&op)) tool_on = t->on;
    while (next_piece < geo.pieces.size() && geo.pieces[next_piece].instruction == i) {
      ProgrammedMove m;
      m.instruction = i;
      m.kind = std::holds_alternative<program::Rapid>(op) ? MoveKind::Rapid : tool_on ? MoveKind::Cut : MoveKind::Feed;
      m.segment = geo.pieces[next_piece].segment;
      pos = m.segment.end;
      if (!pp.move_of[i]) pp.move_of[i] = pp.moves.size();
      pp.moves.push_back(m);
      ++next_piece;
    }
    pp.after[i] = pos;
  }
  pp.end = pos;
  return pp;
}

double ProgrammedPath::deviation_mm(const core::Vec& p, std::uint32_t tag, std::uint32_t tag_last, bool moving, double enough) const {
  if (tag >= before.size()) return core::distance(p, end);
  // The segments of moves[first - pad] .. moves[last + pad]: every piece of the instructions (a
  // curve has several), and `pad` motions on either side.
  const auto from_moves = [&](std::size_t pad) {
    const std::size_t first = *move_of[tag];
    std::size_t last = first;
    while (last + 1 < moves.size() && moves[last + 1].instruction <= std::max(tag, tag_last)) ++last;
    double d = std::numeric_limits<double>::infinity();
    for (std::size_t m = first > pad ? first - pad : 0; d > enough && m <= std::min(last + pad, moves.size() - 1); ++m)
      d = std::min(d, moves[m].segment.distance_to(p, enough));
    return d;
  };
  if (moving && move_of[tag]) return from_moves(1);
  // At rest: where the instruction began or ended; a merged line ends where its last one does.
  const std::uint32_t last = std::max(tag, tag_last) < after.size() ? std::max(tag, tag_last) : tag;
  const double d = std::min({core::distance(p, before[tag]), core::distance(p, after[tag]), core::distance(p, after[last])});
  // Or inside it: a stop (P-5) brakes to rest on the path and ends the run there.
  return d > enough && move_of[tag] ? std::min(d, from_moves(0)) : d;
}

}  // namespace softmc::report
