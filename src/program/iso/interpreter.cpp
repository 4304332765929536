// Interpreter: applies one checked block to the modal state and emits canonical IR operations.
#include "program/iso/interpreter.hpp"

#include <cmath>

#include "program/iso/arc.hpp"

namespace softmc::program::iso {
namespace {

constexpr std::size_t kX = core::index(core::Axis::X);
constexpr std::size_t kY = core::index(core::Axis::Y);

LineError error(std::uint32_t col, std::string message) { return LineError{col, std::move(message)}; }

// Words that only some codes use must have such a code in the block (LinuxCNC refuses them too):
// a stray I or P is usually a typo that would otherwise be silently ignored.
std::optional<LineError> check_unused_words(const Block& b, bool arc_move) {
  if (!arc_move) {
    if (b.i) return error(b.i->col, "I word with no G2 or G3 to use it");
    if (b.j) return error(b.j->col, "J word with no G2 or G3 to use it");
  }
  if (b.p && !b.dwell_col && !arc_move) return error(b.p->col, "P word with no G4, G2 or G3 to use it");
  return std::nullopt;
}

// Turns the block's arc words into an IR arc from st.position to `end`.
std::optional<LineError> arc_move(const Block& b, const ModalState& st, std::uint32_t col, const core::Vec& end,
                                  Op& out) {
  if (!b.axes[kX] && !b.axes[kY])
    return error(col, "X and Y words both missing for an arc in the XY plane (a full circle repeats the end point)");
  if (!b.i && !b.j) return error(col, "I and J words both missing: give the arc centre with I and/or J");
  int turns = 1;
  if (b.p) {
    if (b.p->value < 1 || b.p->value != std::floor(b.p->value))
      return error(b.p->col, "arc turns (P) must be a whole number, 1 or more");
    turns = static_cast<int>(b.p->value);  // |P| <= 1e9 (lexer bound) fits an int
  }
  const double k = mm_per_unit(st.units);
  const double ci = b.i ? b.i->value * k : 0.0;
  const double cj = b.j ? b.j->value * k : 0.0;
  const bool incremental = st.arc_distance == Distance::Incremental;
  ArcRequest rq;
  rq.start = st.position;
  rq.end = end;
  rq.center0 = incremental ? st.position[kX] + ci : ci;
  rq.center1 = incremental ? st.position[kY] + cj : cj;
  rq.clockwise = st.motion == Motion::ArcCw;
  rq.turns = turns;
  rq.units = st.units;
  rq.feed_mm_s = st.feed_mm_s.value_or(0.0);
  Arc arc;
  if (auto msg = make_arc(rq, arc)) return error(col, std::move(*msg));
  out = arc;
  return std::nullopt;
}

}  // namespace

std::optional<LineError> execute(const Block& b, ModalState& state, std::vector<Op>& out) {
  ModalState st = state;
  std::vector<Op> ops;

  // Every length and the F word of a block are read in the units in effect after the block's own
  // G20/G21, so "G20 F10" is 10 in/min.
  if (b.units) st.units = b.units->value;
  const double k = mm_per_unit(st.units);

  if (b.f) st.feed_mm_s = b.f->value * k / 60.0;  // F is per minute; inside, mm/s

  // The PLC sees every M function (P-10) before the action it stands for.
  if (b.m_spindle) {
    ops.emplace_back(MFunction{b.m_spindle->value});
    ops.emplace_back(ToolSwitch{b.m_spindle->value != 5});
  }

  if (b.dwell_col) {
    if (!b.p) return error(*b.dwell_col, "G4 needs a P word: the dwell time in seconds");
    if (b.p->value < 0) return error(b.p->col, "dwell time (P) must be 0 or more");
    ops.emplace_back(Dwell{b.p->value});
  }

  if (b.plane) st.plane = b.plane->value;
  if (b.distance) st.distance = b.distance->value;
  if (b.arc_distance) st.arc_distance = b.arc_distance->value;
  if (b.motion) st.motion = b.motion->value;

  // A motion word moves (or at least sets the mode); axis words alone move in the modal motion.
  const bool moves = b.has_axes() || (b.motion && b.motion->value != Motion::None);
  if (b.has_axes() && st.motion == Motion::None && !st.motion_uncertain)
    return error(b.first_axis_col(), "axis words with no motion mode: program G0, G1, G2 or G3 first");
  if (auto e = check_unused_words(b, moves && is_arc(st.motion))) return e;

  if (moves && st.motion != Motion::None) {
    const std::uint32_t col = b.motion ? b.motion->col : b.first_axis_col();
    core::Vec end = st.position;
    for (std::size_t a = 0; a < core::kMaxAxes; ++a) {
      if (!b.axes[a]) continue;
      const double v = b.axes[a]->value * k;
      end[a] = st.distance == Distance::Absolute ? v : st.position[a] + v;
    }
    if (is_feed_motion(st.motion) && !st.feed_mm_s && !st.feed_uncertain)
      return error(col, "feed rate missing: program an F word before the first feed move");
    const double feed = st.feed_mm_s.value_or(0.0);
    if (st.motion == Motion::Rapid && b.has_axes()) ops.emplace_back(Rapid{end});
    if (st.motion == Motion::Linear && b.has_axes()) ops.emplace_back(Linear{end, feed});
    if (is_arc(st.motion)) {
      Op arc;
      if (auto e = arc_move(b, st, col, end, arc)) return e;
      ops.push_back(arc);
    }
    st.position = end;
  }

  if (b.m_stop) {
    ops.emplace_back(MFunction{b.m_stop->value});
    ops.emplace_back(ProgramEnd{b.m_stop->value == 30});
    st.ended = true;
  }

  state = st;
  out.insert(out.end(), ops.begin(), ops.end());
  return std::nullopt;
}

}  // namespace softmc::program::iso
