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
  pp.moves_upto.resize(n);
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
      m.half_mm = 0.5 * m.segment.length;
      m.mid = m.segment.point(m.half_mm);
      pos = m.segment.end;
      if (!pp.move_of[i]) pp.move_of[i] = pp.moves.size();
      pp.moves.push_back(m);
      ++next_piece;
    }
    pp.after[i] = pos;
    pp.moves_upto[i] = pp.moves.size();
  }
  pp.end = pos;
  // Each group's ball: centred on the middle of its moves' mids' box, wide enough for every move's own ball.
  for (std::size_t g = 0; g * ProgrammedPath::kMovesPerGroup < pp.moves.size(); ++g) {
    const std::size_t a = g * ProgrammedPath::kMovesPerGroup;
    const std::size_t b = std::min(pp.moves.size(), a + ProgrammedPath::kMovesPerGroup);
    core::Vec lo = pp.moves[a].mid, hi = lo;
    for (std::size_t m = a; m < b; ++m)
      for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
        lo[i] = std::min(lo[i], pp.moves[m].mid[i]);
        hi[i] = std::max(hi[i], pp.moves[m].mid[i]);
      }
    MoveGroup grp;
    grp.centre = (lo + hi) * 0.5;
    for (std::size_t m = a; m < b; ++m)
      grp.radius_mm = std::max(grp.radius_mm, core::distance(grp.centre, pp.moves[m].mid) + pp.moves[m].half_mm);
    pp.groups.push_back(grp);
  }
  return pp;
}

double ProgrammedPath::nearest_move_mm(const core::Vec& p, std::size_t lo, std::size_t hi, double enough) const {
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_m = hint_;
  const auto try_move = [&](std::size_t m) {
    const auto& mv = moves[m];
    if (core::distance(p, mv.mid) - mv.half_mm >= best) return;
    const double d = mv.segment.distance_to(p, enough);
    if (d < best) best = d, best_m = m;
  };
  if (hint_ >= lo && hint_ <= hi) try_move(hint_);
  for (std::size_t g = lo / kMovesPerGroup; best > enough && g * kMovesPerGroup <= hi; ++g) {
    if (core::distance(p, groups[g].centre) - groups[g].radius_mm >= best) continue;
    const std::size_t a = std::max(lo, g * kMovesPerGroup), b = std::min(hi + 1, (g + 1) * kMovesPerGroup);
    for (std::size_t m = a; m < b && best > enough; ++m)
      if (m != hint_) try_move(m);
  }
  hint_ = best_m;
  return best;
}

double ProgrammedPath::deviation_mm(const core::Vec& p, std::uint32_t tag, std::uint32_t tag_last, bool moving, double enough) const {
  if (tag >= before.size()) return core::distance(p, end);
  // The segments of moves[first - pad] .. moves[last + pad]: every piece of the instructions (a
  // curve has several), and `pad` motions on either side.
  const auto from_moves = [&](std::size_t pad) {
    const std::size_t first = *move_of[tag];
    const std::uint32_t upto = std::max(tag, tag_last);
    const std::size_t last = std::max(first, (upto < moves_upto.size() ? moves_upto[upto] : moves.size()) - 1);
    return nearest_move_mm(p, first > pad ? first - pad : 0, std::min(last + pad, moves.size() - 1), enough);
  };
  if (moving && move_of[tag]) return from_moves(1);
  // At rest: where the instruction began or ended; a merged line ends where its last one does.
  const std::uint32_t last = std::max(tag, tag_last) < after.size() ? std::max(tag, tag_last) : tag;
  const double d = std::min({core::distance(p, before[tag]), core::distance(p, after[tag]), core::distance(p, after[last])});
  // Or inside it: a stop (P-5) brakes to rest on the path and ends the run there.
  return d > enough && move_of[tag] ? std::min(d, from_moves(0)) : d;
}

}  // namespace softmc::report
