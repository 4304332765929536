// Fast path for the commonest CAM blocks: "[N..] [G0|G1|G2|G3] X.. Y.. Z.. [I.. J..] [F..]".
//
// Nearly every line of a CAM program is a short straight move or an arc; lexing them into words,
// sorting the words into a Block and running the whole interpreter for them costs most of the time
// of a million-line program. This reads such a line in one pass and applies the few rules that can
// apply to it (interpreter.cpp: Exec::run, motion, straight, arc). Anything unusual answers false
// before anything has changed, and the general path reads the line as it always did.
#include "program/iso/fast_block.hpp"

#include <cmath>

#include "program/iso/arc.hpp"
#include "program/iso/expression.hpp"
#include "program/iso/interpreter.hpp"

namespace softmc::program::iso {
namespace {

bool plain_state(const ModalState& st) {
  if (st.ended || st.comp != Comp::Off || st.feed_mode != FeedMode::PerMinute || st.arc_not_allowed) return false;
  return no_offsets(st);  // machine = program + 0
}

}  // namespace

bool fast_straight_block(std::string_view s, ModalState& st, FastBlock& out) {
  out.op.reset();
  if (!plain_state(st)) return false;
  double axis[3] = {0, 0, 0};
  bool named[3] = {false, false, false};
  double ij[2] = {0, 0};
  bool has_ij[2] = {false, false};
  double g = -1, f = 0;
  bool has_f = false, any = false;
  std::size_t i = 0;
  while (i < s.size() && is_space(s[i])) ++i;
  out.col = col_of(i);
  while (i < s.size()) {
    const char c = static_cast<char>(s[i] & ~0x20);  // upper case for letters
    const bool first = !any;
    any = true;
    ++i;
    double v = 0;
    if (!read_plain_number(s, i, v)) return false;
    switch (c) {
      case 'X': case 'Y': case 'Z': {
        const int a = c == 'Z' ? 2 : c - 'X';
        if (named[a]) return false;
        named[a] = true;
        axis[a] = v;
        break;
      }
      case 'I': case 'J': {
        const int a = c - 'I';
        if (has_ij[a]) return false;
        has_ij[a] = true;
        ij[a] = v;
        break;
      }
      case 'G':
        if (g >= 0 || (v != 0 && v != 1 && v != 2 && v != 3)) return false;
        g = v;
        break;
      case 'F':
        if (has_f || !(v > 0)) return false;
        has_f = true;
        f = v;
        break;
      case 'N':
        if (!first || v < 0 || v != std::floor(v)) return false;
        break;
      default: return false;  // another word, a comment, '#', '/', '%', a stray byte
    }
  }
  if (!any) return false;
  const bool has_axes = named[0] || named[1] || named[2];
  // The motion after this block: G0/G1 given, or G0/G1 in effect for axis words alone.
  Motion motion = st.motion;
  if (g >= 0) {
    if (st.motion == Motion::Nurbs) return false;  // an error: a G5.2 block is open
    motion = g == 0 ? Motion::Rapid : g == 1 ? Motion::Linear : g == 2 ? Motion::ArcCw : Motion::ArcCcw;
  } else if (has_axes && st.motion != Motion::Rapid && st.motion != Motion::Linear && st.motion != Motion::ArcCw &&
             st.motion != Motion::ArcCcw) {
    return false;  // splines, cycles, or no motion mode (an error)
  }
  const bool arc = motion == Motion::ArcCw || motion == Motion::ArcCcw;
  const bool has_ij_any = has_ij[0] || has_ij[1];
  if (has_ij_any != arc) return false;  // I J only with arcs (else "I word with nothing to use it")
  const double k = mm_per_unit(st.units);
  // Exec::run: F is per minute in the block's units; inside, mm/s.
  std::optional<double> feed_mm_s = st.feed_mm_s;
  if (has_f) feed_mm_s = f * k / 60.0;
  const bool moves = has_axes || g >= 0;
  if (moves && (motion == Motion::Linear || arc) && !(feed_mm_s && *feed_mm_s > 0)) return false;  // missing or 0
  std::optional<Arc> a;  // not constructed (zeroed) for the straight moves
  if (arc) {
    // Exec::arc in the XY plane, centre format: anything else (other planes, R, P, K, no X and no
    // Y, an end off the circle) is left to it.
    if (st.plane != Plane::XY || (!named[0] && !named[1])) return false;
    core::Vec end = st.position, centre = st.position;
    for (std::size_t i = 0; i < 3; ++i)
      if (named[i]) end[i] = (st.distance == Distance::Absolute ? axis[i] * k : st.position[i] + axis[i] * k) + 0.0;
    const bool incremental = st.arc_distance == Distance::Incremental;
    for (std::size_t i = 0; i < 2; ++i) {
      const double d = has_ij[i] ? ij[i] * k : 0.0;
      centre[i] = (incremental ? st.position[i] + d : d) + 0.0;
    }
    ArcRequest rq;
    rq.start = st.position;
    rq.end = end;
    rq.plane = axes_of(Plane::XY);
    rq.clockwise = motion == Motion::ArcCw;
    rq.turns = 1;
    rq.units = st.units;
    rq.center0 = centre[0];
    rq.center1 = centre[1];
    a.emplace();
    if (make_arc(rq, *a)) return false;  // the general path reports why
    a->feed_mm_s = *feed_mm_s;  // G94: the feed as it is (Exec::feed_for)
  }
  // From here on the block is good: apply it.
  st.feed_in_block = has_f;
  if (has_f) st.feed_word = f;
  st.feed_mm_s = feed_mm_s;
  if (g >= 0) {
    st.g5_continues = false;
    st.cycle_il = NAN;  // a run of canned cycles ends
    st.motion = motion;
  }
  if (!moves || motion == Motion::None) return true;  // "F300", "N10": nothing moves
  if (arc) {
    st.position = a->end;
    out.op.emplace(std::move(*a));
    return true;
  }
  core::Vec end = st.position;
  for (std::size_t i = 0; i < 3; ++i) {
    if (!named[i]) continue;
    const double v = axis[i] * k;
    end[i] = (st.distance == Distance::Absolute ? v : st.position[i] + v) + 0.0;  // + 0: as the zero offsets
  }
  if (has_axes) {
    if (motion == Motion::Rapid) out.op.emplace(Rapid{end});
    else out.op.emplace(Linear{end, *feed_mm_s});
  }
  st.position = end;
  return true;
}

}  // namespace softmc::program::iso
