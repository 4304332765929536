// Canned cycles G73 G74 G81…G89 with G98/G99 retract, in any plane, as LinuxCNC 2.9 runs them.
//
//   initial level (the height before the first cycle of a run of cycles; kept until a non-cycle motion)
//   initial < R: rapid up to R first                    for each of L repeats:
//                                                         rapid in the plane to the hole: the first at
//   clear = R (G99) or max(initial, R) (G98)                the current height, the others at clear
//                                                         rapid down to R (if above it)
//                                                         the cycle's own moves (feed down, dwell, pecks …)
//                                                         retract to clear
// In G91, X/Y are increments per repeat, R is relative to the initial level and Z to R. Polar
// coordinates @ ^ (G17): in G90 the hole; in G91 a radius and an angle step about the origin per repeat.
// Spindle events of a cycle (G74/G84 reversal, G86/G87/G88 stop and restart, G87 orientation) are
// emitted as an M function of group 2 with its ToolSwitch, as an M3/M4/M5/M19 block would be, so
// the PLC sees the spindle state through P-10 exactly as for programmed M functions.
#include <cmath>
#include <optional>

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
  const bool needs_p = st.motion == Motion::Drill82 || st.motion == Motion::Bore86 || st.motion == Motion::Bore89 ||
                       st.motion == Motion::Bore88;
  const bool tap = st.motion == Motion::Tap84 || st.motion == Motion::Tap74;
  // LinuxCNC 2.9 checks the spindle before each cycle that stops or reverses it.
  const SpindleDir dir = st.spindle;
  if (tap) {
    const bool right = st.motion == Motion::Tap84;
    const char* name = right ? "G84" : "G74";
    if (dir == SpindleDir::Stopped)
      return error(col, fmt::format("spindle not turning in {}: program {} S… first", name, right ? "M3" : "M4"));
    if (dir != (right ? SpindleDir::Cw : SpindleDir::Ccw))
      return error(col, fmt::format("spindle turning {} in {}: {} taps need {}", right ? "counterclockwise" : "clockwise", name,
                                    right ? "right-hand" : "left-hand", right ? "M3" : "M4"));
  }
  if ((st.motion == Motion::Bore86 || st.motion == Motion::BackBore87 || st.motion == Motion::Bore88) &&
      dir == SpindleDir::Stopped)
    return error(col, fmt::format("spindle not turning in {}: program M3 or M4 first (the cycle stops and restarts it)",
                                  st.motion == Motion::Bore86 ? "G86" : st.motion == Motion::BackBore87 ? "G87" : "G88"));
  const bool needs_q = st.motion == Motion::Drill73 || st.motion == Motion::Drill83;
  if (needs_p || tap) {  // G74/G84: P (dwell at the bottom) is optional, as in LinuxCNC 2.9
    if (const auto& pw = w('P')) {
      if (pw->value < 0) return error(pw->col, "dwell time (P) must be 0 or more");
      p = pw->value;
    } else if (first && needs_p) {
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

  // G87: the offset of the tool's way in and out (the centre words of the plane axes, always
  // incremental) and the top of the back bore (the centre word of the third axis: absolute in G90,
  // from the bottom in G91). All three are needed when G87 starts and are kept while it repeats.
  static constexpr char kCentre[3] = {'I', 'J', 'K'};
  double off_a = 0, off_b = 0, middle_word = 0;
  if (st.motion == Motion::BackBore87) {
    double* sticky[3] = {&st.cycle_i, &st.cycle_j, &st.cycle_k};
    for (char c : {'I', 'J', 'K'}) {
      const auto& x = w(c);
      if (x) *sticky[c - 'I'] = x->value * kk;
      else if (first)
        return error(col, fmt::format("{} word missing with G87: G87 needs I, J and K (offset of the way in, top of the bore)", c));
    }
    off_a = *sticky[kCentre[pa.a0] - 'I'];
    off_b = *sticky[kCentre[pa.a1] - 'I'];
    middle_word = *sticky[kCentre[pa.n] - 'I'];
  }

  // Program coordinates of the plane and the third axis.
  core::Vec pos = program_position();
  // G98 works from the initial level, kept across consecutive cycles until a non-cycle motion (as
  // LinuxCNC 2.9's rs274 does: a G98 cycle after G99 ones rises back to the height before the first).
  if (std::isnan(st.cycle_il)) st.cycle_il = pos[pa.n];
  // LinuxCNC 2.9's old_cc is that initial level (also for G91's R); current_cc the height now.
  double old_cc = st.cycle_il;
  double current_cc = pos[pa.n];
  double aa = pos[pa.a0], bb = pos[pa.a1], aa_inc = 0, bb_inc = 0, r = 0, cc = 0;
  // Polar coordinates (G17 only, never with X or Y: polar.cpp) as LinuxCNC's convert_cycle_xy reads
  // them: in G90 the hole itself, with the current radius or angle for a missing word (and, unlike a
  // straight move, angle 0 at the origin); in G91 increments about the origin for every repeat.
  const auto& pr = b.polar_radius;
  const auto& pt = b.polar_angle;
  std::optional<double> dr, dt;
  if (st.distance == Distance::Absolute) {
    r = r_word;
    cc = cc_word;
    if (const auto& x = w(la)) aa = x->value * kk;
    if (const auto& y = w(lb)) bb = y->value * kk;
    if (b.has_polar())
      polar_point(aa, bb, pr ? std::optional<double>(pr->value * kk) : std::nullopt,
                  pt ? std::optional<double>(polar_radians(pt->value)) : std::nullopt);
  } else {
    if (const auto& x = w(la)) aa_inc = x->value * kk;
    if (const auto& y = w(lb)) bb_inc = y->value * kk;
    // LinuxCNC steps only by increments that are not zero: ^0 and @0 pass the origin without an error.
    if (pr && pr->value != 0) dr = pr->value * kk;
    if (pt && pt->value != 0) dt = polar_radians(pt->value);
    r = r_word + old_cc;
    cc = r + cc_word;
  }
  if (r < cc)
    return error(col, fmt::format("the retract plane R is below the bottom of the hole {} ({:.4f} < {:.4f})", lc, r / kk, cc / kk));
  const double middle = st.distance == Distance::Incremental ? cc + middle_word : middle_word;  // G87
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

  auto spindle = [&](SpindleDir d) {
    const int n = d == SpindleDir::Cw ? 3 : d == SpindleDir::Ccw ? 4 : 5;
    emit(MFunction{n, static_cast<std::uint8_t>(opt.mtable->get(n).group)});
    emit(ToolSwitch{d != SpindleDir::Stopped});
  };
  auto orient = [&] { emit(MFunction{19, static_cast<std::uint8_t>(opt.mtable->get(19).group)}); };
  auto override_switch = [&](bool on) {  // G74/G84: no feed override while the tap is in the hole
    if (!st.feed_override) return;
    const int n = on ? 48 : 49;
    emit(MFunction{n, static_cast<std::uint8_t>(opt.mtable->get(n).group)});
  };
  const SpindleDir reverse = dir == SpindleDir::Cw ? SpindleDir::Ccw : SpindleDir::Cw;

  if (old_cc < r) {
    rapid(pos[pa.a0], pos[pa.a1], r);
    old_cc = r;
    current_cc = r;
  }
  const double clear = st.retract == Retract::RPlane ? r : old_cc;
  // LinuxCNC convert_cycle_*: the cycle's moves (after the rise to R) run in exact path mode (G61),
  // and the mode in effect comes back after them: no corner of a cycle is blended, so neither the
  // approach of a hole nor G87's moves inside a bore cut a corner.
  const bool exact_already = st.path_programmed && st.path.kind == PathKind::ExactPath;
  if (!exact_already) {
    PathMode exact;
    exact.kind = PathKind::ExactPath;
    emit(exact);
  }
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
    // G91 polar: the radius increment, then the angle increment, about the origin (LinuxCNC CYCLE_MACRO).
    if (const PolarStep s = polar_increment(aa, bb, dr, dt); s != PolarStep::Ok) {
      const bool radius = s == PolarStep::RadiusAtOrigin;
      return error(radius ? pr->col : pt->col,
                   fmt::format("incremental polar coordinates (G91 {}) at the origin in repeat {} of the canned cycle: "
                               "the current angle is undefined there", radius ? '@' : '^', n + 1));
    }
    // The first hole is reached at the current height, the others at the clear height; then down to R.
    if (n == 0 && current_cc > r) {
      rapid(aa, bb, current_cc);
      rapid(aa, bb, r);
    } else {
      rapid(aa, bb, clear);
      if (clear > r) rapid(aa, bb, r);
    }
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
        // LinuxCNC 2.9 convert_cycle_g85: out to R at the feed, then a rapid to the clear height (G98).
        feed_to(aa, bb, cc);
        feed_to(aa, bb, r);
        if (clear > r) rapid(aa, bb, clear);
        break;
      case Motion::Bore86:
        feed_to(aa, bb, cc);
        emit(Dwell{p});
        spindle(SpindleDir::Stopped);
        rapid(aa, bb, clear);
        spindle(dir);
        break;
      case Motion::Tap74:
      case Motion::Tap84:
        // A floating (tension/compression) tap holder, as LinuxCNC 2.9's G84: the feed is the
        // programmed F (= pitch × S), not synchronised to the spindle; overrides are off meanwhile.
        override_switch(false);
        feed_to(aa, bb, cc);
        spindle(SpindleDir::Stopped);
        spindle(reverse);
        emit(Dwell{p});
        feed_to(aa, bb, clear);
        spindle(SpindleDir::Stopped);
        spindle(dir);
        override_switch(true);
        break;
      case Motion::BackBore87:
        rapid(aa + off_a, bb + off_b, r);
        spindle(SpindleDir::Stopped);
        orient();
        rapid(aa + off_a, bb + off_b, cc);
        rapid(aa, bb, cc);
        spindle(dir);
        feed_to(aa, bb, middle);
        feed_to(aa, bb, cc);
        spindle(SpindleDir::Stopped);
        orient();
        rapid(aa + off_a, bb + off_b, cc);
        rapid(aa + off_a, bb + off_b, clear);
        rapid(aa, bb, clear);
        spindle(dir);
        break;
      case Motion::Bore88:
        feed_to(aa, bb, cc);
        emit(Dwell{p});
        spindle(SpindleDir::Stopped);
        emit(Pause{false});  // the operator may retract by hand (LinuxCNC: PROGRAM_STOP)
        // softmc's addition: on cycle start the tool leaves the hole straight along its axis, with
        // the spindle still stopped, instead of the next move starting from the bottom.
        rapid(aa, bb, clear);
        spindle(dir);
        break;
      default: break;
    }
  }
  if (!exact_already) {
    // Back to the program's mode; a program that named none goes back to the machine's default
    // (a blend without P: channel.cpp takes the configured tolerance).
    PathMode back;
    back.kind = PathKind::Blend;
    emit(st.path_programmed ? st.path : back);
  }
  st.cycle_cc = cc_word;
  st.cycle_r = r_word;
  st.cycle_p = p;
  st.cycle_q = q;
  return std::nullopt;
}

}  // namespace softmc::program::iso::detail
