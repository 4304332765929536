// Canned cycles G73 G81 G82 G83 G85 G86 G89 with G98/G99 retract, in any plane, as LinuxCNC runs them.
//
//   initial ──(rapid, only if below R)──► R          for each of L repeats:
//        │                                              rapid in the plane to the hole (at the current height)
//        ▼                                              rapid down to R (if not there)
//   clear = R (G99) or max(initial, R) (G98)            the cycle's own moves (feed down, dwell, pecks …)
//                                                       retract to clear
// In G91, X/Y are increments per repeat, R is relative to the initial height and Z to R.
#include <cmath>

#include "program/iso/exec.hpp"

namespace softmc::program::iso::detail {

namespace {
constexpr double kRapidDeltaInch = 0.010;  // LinuxCNC G83_RAPID_DELTA: peck back-off
}

std::optional<LineError> Exec::cycle(std::uint32_t col) {
  const PlaneAxes pa = axes_of(st.plane);
  const char la = core::letter(pa.a0), lb = core::letter(pa.a1), lc = core::letter(pa.n);
  for (std::size_t a = 3; a <= 5; ++a)
    if (b.has(core::letter(a))) return error(b.word(core::letter(a))->col, "rotary axes cannot move in a canned cycle");
  if (st.feed_mode == FeedMode::InverseTime) return error(col, "canned cycles cannot run in inverse time feed mode (G93)");
  // A cycle other than the one in effect (motion() then cleared the sticky R) needs all its words.
  const bool first = std::isnan(st.cycle_r);
  const auto& cw = w(lc);
  if (!cw && first)
    return error(col, fmt::format("{} word missing: the canned cycle needs the bottom of the hole", lc));
  const auto& rw = w('R');
  if (!rw && std::isnan(st.cycle_r)) return error(col, "R word missing: the canned cycle needs the retract plane");
  const double kk = k();
  const double cc_word = cw ? cw->value * kk : st.cycle_cc;
  const double r_word = rw ? rw->value * kk : st.cycle_r;
  int repeats = 1;
  if (const auto& l = w('L')) {
    if (l->value < 1 || l->value != std::floor(l->value)) return error(l->col, "canned cycle repeats (L) must be a whole number, 1 or more");
    repeats = static_cast<int>(std::min(l->value, 100000.0));
  }
  double p = st.cycle_p, q = st.cycle_q;
  const bool needs_p = st.motion == Motion::Drill82 || st.motion == Motion::Bore86 || st.motion == Motion::Bore89;
  const bool needs_q = st.motion == Motion::Drill73 || st.motion == Motion::Drill83;
  if (needs_p) {
    if (const auto& pw = w('P')) {
      if (pw->value < 0) return error(pw->col, "dwell time (P) must be 0 or more");
      p = pw->value;
    } else if (first) {
      return error(col, "P word missing: this canned cycle dwells P seconds at the bottom");
    }
  }
  if (needs_q) {
    if (const auto& qw = w('Q')) {
      if (!(qw->value > 0)) return error(qw->col, "peck depth (Q) must be greater than zero");
      q = qw->value * kk;
    } else if (first) {
      return error(col, "Q word missing: the peck cycle needs the peck depth");
    }
  }

  // Program coordinates of the plane and the third axis.
  core::Vec pos = program_position();
  // G98 works from the initial level, kept across consecutive cycles until a non-cycle motion (as
  // LinuxCNC 2.9's rs274 does: a G98 cycle after G99 ones rises back to the height before the first).
  if (std::isnan(st.cycle_il)) st.cycle_il = pos[pa.n];
  double old_cc = st.retract == Retract::RPlane ? pos[pa.n] : st.cycle_il;
  double aa = pos[pa.a0], bb = pos[pa.a1], aa_inc = 0, bb_inc = 0, r = 0, cc = 0;
  if (st.distance == Distance::Absolute) {
    r = r_word;
    cc = cc_word;
    if (const auto& x = w(la)) aa = x->value * kk;
    if (const auto& y = w(lb)) bb = y->value * kk;
  } else {
    if (const auto& x = w(la)) aa_inc = x->value * kk;
    if (const auto& y = w(lb)) bb_inc = y->value * kk;
    r = r_word + old_cc;
    cc = r + cc_word;
  }
  if (r < cc)
    return error(col, fmt::format("the retract plane R is below the bottom of the hole {} ({:.4f} < {:.4f})", lc, r / kk, cc / kk));
  double feed = 0;
  if (auto e = feed_for(col, 1.0, 0.0, feed)) return e;

  // Feed and rapid moves of the cycle at plane point (x, y), height z: program → machine.
  auto point = [&](double x, double y, double z) {
    core::Vec v = pos;
    v[pa.a0] = x;
    v[pa.a1] = y;
    v[pa.n] = z;
    return to_machine(st, v);
  };
  auto rapid = [&](double x, double y, double z) {
    const core::Vec m = point(x, y, z);
    emit(Rapid{m});
    st.position = m;
  };
  auto feed_to = [&](double x, double y, double z) {
    const core::Vec m = point(x, y, z);
    emit(Linear{m, feed});
    st.position = m;
  };

  if (old_cc < r) {
    rapid(pos[pa.a0], pos[pa.a1], r);
    old_cc = r;
  }
  const double clear = st.retract == Retract::RPlane ? r : old_cc;
  // LinuxCNC backs off 0.010 in in inch programs and 0.254 mm in mm programs: 0.254 mm either way.
  const double back_off = kRapidDeltaInch * kMmPerInch;
  std::size_t guard = 0;
  const auto too_many = [&] {
    return error(col, fmt::format("the canned cycle makes more than {} moves: the program's instruction limit "
                                  "(fewer repeats L, or a larger peck Q)", opt.max_ops));
  };
  for (int n = 0; n < repeats; ++n) {
    if (out.ops.size() > opt.max_ops) return too_many();
    aa += aa_inc;
    bb += bb_inc;
    rapid(aa, bb, old_cc);
    if (old_cc != r) rapid(aa, bb, r);
    switch (st.motion) {
      case Motion::Drill81:
        feed_to(aa, bb, cc);
        rapid(aa, bb, clear);
        break;
      case Motion::Drill82:
      case Motion::Bore89:
        feed_to(aa, bb, cc);
        emit(Dwell{p});
        if (st.motion == Motion::Drill82) rapid(aa, bb, clear);
        else feed_to(aa, bb, clear);
        break;
      case Motion::Drill73:
      case Motion::Drill83:
        for (double depth = r - q; depth > cc; depth -= q) {
          if (++guard > 100000) return error(col, "the peck cycle would make more than 100000 pecks: Q is too small");
          if (out.ops.size() > opt.max_ops) return too_many();
          feed_to(aa, bb, depth);
          if (st.motion == Motion::Drill83) rapid(aa, bb, r);  // G83 pecks clear chips at R, not at the retract height
          rapid(aa, bb, depth + back_off);
        }
        feed_to(aa, bb, cc);
        rapid(aa, bb, clear);
        break;
      case Motion::Bore85:
        feed_to(aa, bb, cc);
        feed_to(aa, bb, clear);
        break;
      case Motion::Bore86:
        feed_to(aa, bb, cc);
        emit(Dwell{p});
        emit(ToolSwitch{false});
        rapid(aa, bb, clear);
        emit(ToolSwitch{true});
        break;
      default: break;
    }
    old_cc = clear;
  }
  st.cycle_cc = cc_word;
  st.cycle_r = r_word;
  st.cycle_p = p;
  st.cycle_q = q;
  return std::nullopt;
}

}  // namespace softmc::program::iso::detail
