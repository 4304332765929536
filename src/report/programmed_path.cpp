// Walks a Program into segments and positions, without the planner.
#include "report/programmed_path.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>

#include "control/path.hpp"

namespace softmc::report {

namespace {
// Distance of p from the box [lo, hi] (0 inside it).
double box_distance(const core::Vec& p, const core::Vec& lo, const core::Vec& hi) {
  double d2 = 0;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    const double e = std::max({lo[i] - p[i], 0.0, p[i] - hi[i]});
    d2 += e * e;
  }
  return std::sqrt(d2);
}
}  // namespace

ProgrammedPath programmed_path(const program::Program& prog) {
  ProgrammedPath pp;
  const std::size_t n = prog.instructions.size();
  pp.moves_upto.resize(n);
  pp.start = prog.start;
  pp.moves.reserve(n);  // one move an instruction, most of them
  // The same geometry the channel plans (curves expanded into several pieces), taken piece by piece
  // as the walk builds them: a copy of the whole program's pieces was a third of a large CAM run's memory.
  core::Vec pos = prog.start;
  bool tool_on = false;
  // Begins every instruction up to i: its position before, its tool switch; and ends the one
  // before it (its position after and the moves so far), which has had all its pieces by then.
  std::size_t next = 0;  // the next instruction to begin
  const auto begin_through = [&](std::size_t i) {
    for (; next <= i; ++next) {
      if (next > 0) pp.moves_upto[next - 1] = static_cast<std::uint32_t>(pp.moves.size());
      if (const auto* t = std::get_if<program::ToolSwitch>(&prog.instructions[next].op)) tool_on = t->on;
    }
  };
  control::visit_program_geometry(prog, [&](std::uint32_t i, const motion::Segment& seg) {
    begin_through(i);
    const auto& op = prog.instructions[i].op;
    ProgrammedMove m;
    m.instruction = i;
    m.kind = std::holds_alternative<program::Rapid>(op) ? MoveKind::Rapid : tool_on ? MoveKind::Cut : MoveKind::Feed;
    m.line = seg.kind == motion::SegmentKind::Line;
    // A line starts where the walk stands (control::to_segment builds it from there): the move
    // before's end, which start_of gives back.
    assert(!m.line || seg.start == pos);
    m.length = seg.length;
    if (!m.line) {
      m.curve = static_cast<std::uint32_t>(pp.curves.size());
      pp.curves.push_back(seg);
      MoveGroup b;
      seg.bounds(b.lo, b.hi);
      pp.curve_box.push_back(b);
    }
    pos = seg.end;
    pp.moves.push_back(m);
    pp.push_end(seg.end);
  });
  if (n > 0) {  // the rest, none with motion, and the last one's end
    begin_through(n - 1);
    pp.moves_upto[n - 1] = static_cast<std::uint32_t>(pp.moves.size());
  }
  pp.end = pos;
  pp.along_mm.resize(pp.moves.size() + 1);
  for (std::size_t m = 0; m < pp.moves.size(); ++m) pp.along_mm[m + 1] = pp.along_mm[m] + pp.moves[m].length;
  // Each group's box: the union of its moves'.
  for (std::size_t g = 0; g * ProgrammedPath::kMovesPerGroup < pp.moves.size(); ++g) {
    const std::size_t a = g * ProgrammedPath::kMovesPerGroup;
    const std::size_t b = std::min(pp.moves.size(), a + ProgrammedPath::kMovesPerGroup);
    MoveGroup grp;
    pp.box(pp.moves[a], grp.lo, grp.hi);
    for (std::size_t m = a + 1; m < b; ++m) {
      core::Vec lo, hi;
      pp.box(pp.moves[m], lo, hi);
      for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
        grp.lo[i] = std::min(grp.lo[i], lo[i]);
        grp.hi[i] = std::max(grp.hi[i], hi[i]);
      }
    }
    pp.groups.push_back(grp);
  }
  return pp;
}

void ProgrammedPath::push_end(const core::Vec& e) {
  std::size_t need = stride_;
  for (std::size_t i = stride_; i < core::kMaxAxes; ++i)
    if (std::bit_cast<std::uint64_t>(e[i]) != 0) need = i + 1;
  if (need > stride_) {  // an axis no end used before: every end before it takes it as zero
    const std::size_t n = moves.size() - 1;  // the ends kept so far
    std::vector<double> wider;
    wider.reserve(moves.capacity() * need);  // programmed_path reserves the moves: no growth by doubling
    wider.resize(n * need, 0.0);
    for (std::size_t m = 0; m < n; ++m)
      for (std::size_t i = 0; i < stride_; ++i) wider[m * need + i] = ends_[m * stride_ + i];
    ends_.swap(wider);
    stride_ = need;
  }
  for (std::size_t i = 0; i < stride_; ++i) ends_.push_back(e[i]);
}

void ProgrammedPath::box(const ProgrammedMove& m, core::Vec& lo, core::Vec& hi) const {
  if (!m.line) {
    lo = curve_box[m.curve].lo;
    hi = curve_box[m.curve].hi;
    return;
  }
  motion::line_bounds(start_of(m), end_of(m), lo, hi);
}

motion::Segment ProgrammedPath::segment(const ProgrammedMove& m) const {
  return m.line ? motion::make_line(start_of(m), end_of(m)) : curves[m.curve];
}

namespace {
// Distance from p to a line move from a to b (its direction derived as set_line derives it).
double line_move_distance(const core::Vec& a, const core::Vec& b, double length, const core::Vec& p) {
  return motion::line_distance(a, motion::line_direction(a, b, length), length, p);
}
}  // namespace

double ProgrammedPath::distance(const ProgrammedMove& m, const core::Vec& p, double enough) const {
  if (!m.line) return curves[m.curve].distance_to(p, enough);
  return line_move_distance(start_of(m), end_of(m), m.length, p);
}

std::pair<std::size_t, std::size_t> ProgrammedPath::moves_around(std::uint32_t tag, std::uint32_t tag_last) const {
  const std::size_t first = *move_of(tag);
  const std::uint32_t upto = std::max(tag, tag_last);
  const std::size_t last = std::max(first, (upto < moves_upto.size() ? moves_upto[upto] : moves.size()) - 1);
  std::size_t lo = first > 0 ? first - 1 : 0, hi = std::min(last + 1, moves.size() - 1);
  const std::size_t lo_most = lo > kReachMoves ? lo - kReachMoves : 0, hi_most = std::min(hi + kReachMoves, moves.size() - 1);
  // along_mm rises: the first move starting within the reach before, the last one after.
  lo = static_cast<std::size_t>(std::lower_bound(along_mm.begin() + static_cast<std::ptrdiff_t>(lo_most), along_mm.begin() + static_cast<std::ptrdiff_t>(lo),
                                                 along_mm[first] - kReach_mm) - along_mm.begin());
  hi = static_cast<std::size_t>(std::upper_bound(along_mm.begin() + static_cast<std::ptrdiff_t>(hi) + 1, along_mm.begin() + static_cast<std::ptrdiff_t>(hi_most) + 1,
                                                 along_mm[last + 1] + kReach_mm) - along_mm.begin()) - 1;
  return {lo, hi};
}

std::optional<std::size_t> ProgrammedPath::nearest_instruction(const core::Vec& p, std::uint32_t tag,
                                                               std::uint32_t tag_last) const {
  if (tag >= moves_upto.size() || !move_of(tag)) return std::nullopt;
  nearest_move_mm(p, moves_around(tag, tag_last), 0);
  return moves[hint_].instruction;
}

double ProgrammedPath::nearest_move_mm(const core::Vec& p, std::pair<std::size_t, std::size_t> range, double enough) const {
  const auto [lo, hi] = range;
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_m = hint_;
  const auto try_move = [&](std::size_t m) {
    const auto& mv = moves[m];
    core::Vec lo, hi;
    if (!mv.line) {
      box(mv, lo, hi);
      if (box_distance(p, lo, hi) >= best) return;
      const double d = distance(mv, p, enough);
      if (d < best) best = d, best_m = m;
      return;
    }
    // A line's ends are rebuilt from the kept ones (start_of, end_of): once for its box and distance.
    const core::Vec a = start_of(mv), b = end_of(mv);
    motion::line_bounds(a, b, lo, hi);
    if (box_distance(p, lo, hi) >= best) return;
    const double d = line_move_distance(a, b, mv.length, p);
    if (d < best) best = d, best_m = m;
  };
  if (hint_ >= lo && hint_ <= hi) try_move(hint_);
  for (std::size_t g = lo / kMovesPerGroup; best > enough && g * kMovesPerGroup <= hi; ++g) {
    if (box_distance(p, groups[g].lo, groups[g].hi) >= best) continue;
    const std::size_t a = std::max(lo, g * kMovesPerGroup), b = std::min(hi + 1, (g + 1) * kMovesPerGroup);
    for (std::size_t m = a; m < b && best > enough; ++m)
      if (m != hint_) try_move(m);
  }
  hint_ = best_m;
  return best;
}

double ProgrammedPath::deviation_mm(const core::Vec& p, std::uint32_t tag, std::uint32_t tag_last, bool moving, double enough) const {
  if (tag >= moves_upto.size()) return core::distance(p, end);
  // The segments of every piece of the instructions (a curve has several) and of the motions on
  // either side: a corner blend belongs to both, and a smoothing piece reaches into the line before.
  const auto from_moves = [&] { return nearest_move_mm(p, moves_around(tag, tag_last), enough); };
  if (moving && move_of(tag)) return from_moves();
  // At rest: where the instruction began or ended; a merged line ends where its last one does.
  const std::uint32_t last = std::max(tag, tag_last) < moves_upto.size() ? std::max(tag, tag_last) : tag;
  return std::min({core::distance(p, before(tag)), core::distance(p, after(tag)), core::distance(p, after(last))});
}

}  // namespace softmc::report
