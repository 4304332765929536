// Helpers the guard's two files share (jerk_guard.cpp, jerk_certificate.cpp): the slack of every
// limit comparison, one cycle's phases with their bounds, ramps to rest in closed form.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "motion/interp/jerk_guard.hpp"
#include "motion/profile/jerk_path.hpp"
#include "motion/profile/jerk_ramp.hpp"

namespace softmc::motion::guard_detail {

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kRel = 1e-9;       // relative slack of every limit comparison (rounding)
inline constexpr double kAbs = 1e-9;       // absolute slack (mm/s, mm/s², mm/s³)
inline constexpr double kTouch_mm = 1e-12;  // a cycle ending this near a block's end lands on the next block's start
                                     // (the interpolator passes the block a cycle later, at s ≥ length)
inline constexpr int kMaxBrakeCycles = 200000;  // 200 s of braking at 1 ms: beyond, the state is refused

inline bool over(double x, double lim) { return x > lim * (1 + kRel) + kAbs; }

// Integrates phases of constant jerk over one cycle and keeps the bounds reached within it.
struct Cycle {
  PathStep st;
  double left;
  Cycle(const ProfileState& x0, double dt) : left(dt) {
    st.x = x0;
    st.x.s = 0;
    st.x.j = 0;
    st.a_abs = std::abs(x0.a);
    st.v_peak = st.v_min = x0.v;
  }
  void take(const ProfileState& y) {
    st.v_peak = std::max(st.v_peak, y.v);
    st.v_min = std::min(st.v_min, y.v);
    st.a_abs = std::max(st.a_abs, std::abs(y.a));
  }
  // (Inlined: four calls a ramp_cycle; out of line they cost ~85 instructions a blended cycle.)
  __attribute__((always_inline)) void phase(double dur, double j) {
    if (left <= 0 || !(dur > 0)) return;
    const double t = std::min(dur, left);
    if (j != 0) {  // the speed's extreme inside the phase, where a crosses 0
      const double ts = -st.x.a / j;
      if (ts > 0 && ts < t) take(advance(st.x, j, ts));
    }
    st.x = advance(st.x, j, t);
    st.j_abs = std::max(st.j_abs, std::abs(j));
    left -= t;
    take(st.x);
  }
  void hold_rest(double v, double a) {  // the rest of the cycle at (v, a = 0) exactly
    st.x.v = v;
    st.x.a = a;
    st.x.j = 0;
    if (left > 0) st.x.s += v * left;
    left = 0;
    take(st.x);
  }
};

// The phases of constant jerk of the ramp from x towards speed vt, as ramp_cycle follows it: |x.a|
// first brought within a_max at j_max when it is beyond (phase 0), then plan_ramp's three phases
// from there (|a| clamped to a_max against rounding).
struct RampPhases {
  std::array<double, 4> jerk{}, dur{};
};
// (Inlined: returned through memory, its phases cost ~40 instructions a call more.)
__attribute__((always_inline)) inline RampPhases ramp_phases(const ProfileState& x, double vt, double a_max,
                                                             double j_max) {
  RampPhases ph;
  ProfileState z{0, x.v, x.a, 0};
  if (std::abs(x.a) > a_max) {
    ph.jerk[0] = x.a > 0 ? -j_max : j_max;
    ph.dur[0] = (std::abs(x.a) - a_max) / j_max;
    z = advance(z, ph.jerk[0], ph.dur[0]);
  }
  z.a = std::clamp(z.a, -a_max, a_max);
  const Ramp r = plan_ramp(z.v, z.a, vt, a_max, j_max);
  ph.jerk = {ph.jerk[0], r.dir * r.j, 0, -r.dir * r.j};
  ph.dur = {ph.dur[0], r.t1, r.t2, r.t3};
  return ph;
}

// The ramp to rest from x with limits a, j, as ramp_cycle follows it: |x.a| first brought within a
// at jerk j when it is beyond (phase 0), then plan_ramp's three phases; the distance to rest, the
// largest speed on it, and the largest |a| from each phase on.
struct BrakeRamp {
  static constexpr int kPhases = 4;
  std::array<ProfileState, kPhases> at;  // state at the start of each phase, s from x
  std::array<double, kPhases> jerk, dur;
  // Largest |a| from the start of phase i to rest: filled only when the ramp has a phase 0 (|x.a|
  // above a: the certificate reads it, and a_after, only while phase 0 lasts), else left as it was.
  std::array<double, kPhases + 1> a_from;
  double d_stop, v_up;

  BrakeRamp(const ProfileState& x, double a, double j) { build(x, a, j); }
  // Left unset, to be built before it is read (the certificate's: ~40 instructions a walk less).
  struct Unset {};
  explicit BrakeRamp(Unset) {}
  // Rebuilt in place (the certificate's walk rebuilds it at each lowered limit it must account for).
  void build(const ProfileState& x, double a, double j) {
    const RampPhases ph = ramp_phases(x, 0, a, j);
    ProfileState y{0, x.v, x.a, 0};
    v_up = x.v;
#pragma GCC unroll 4
    for (int i = 0; i < kPhases; ++i) {
      at[i] = y;
      jerk[i] = ph.jerk[i];
      dur[i] = ph.dur[i] > 0 ? ph.dur[i] : 0.0;
      if (dur[i] > 0) {
        // The speed peaks where a falls through 0: v + a²/2|j| (a > 0, jerk < 0).
        if (y.a > 0 && jerk[i] < 0 && -y.a / jerk[i] < dur[i]) v_up = std::max(v_up, y.v - y.a * y.a / (2 * jerk[i]));
        y = advance(y, jerk[i], dur[i]);
      }
      if (i == 0) y.a = std::clamp(y.a, -a, a);  // as ramp_cycle clamps it
      v_up = std::max(v_up, y.v);
    }
    d_stop = y.s;
    if (!(dur[0] > 0)) return;
    a_from[kPhases] = 0;
#pragma GCC unroll 4
    for (int i = kPhases - 1; i >= 0; --i) {
      const double a_end = i + 1 < kPhases ? std::abs(at[i + 1].a) : 0.0;
      a_from[i] = std::max(std::max(a_from[i + 1], a_end), dur[i] > 0 ? std::abs(at[i].a) : 0.0);
    }
  }

  // The largest |a| on the ramp from distance d on (|a| is linear in time within a phase: the
  // larger of its value at d and everything after).
  double a_after(double d) const {
    if (d <= 0) return a_from[0];
    for (int i = 0; i < kPhases; ++i) {
      if (!(dur[i] > 0)) continue;
      const ProfileState end = advance(at[i], jerk[i], dur[i]);
      if (end.s < d) continue;
      double lo = 0, hi = dur[i];  // s(t) = d: s rises with t (v ≥ 0 on a brake)
      for (int it = 0; it < 60 && hi - lo > 1e-15; ++it) {
        const double mid = 0.5 * (lo + hi);
        (advance(at[i], jerk[i], mid).s < d ? lo : hi) = mid;
      }
      const double a_d = std::abs(advance(at[i], jerk[i], lo).a);  // lo: just before d
      return std::max({a_d, std::abs(i + 1 < kPhases ? at[i + 1].a : 0.0), a_from[i + 1]});
    }
    return 0;
  }

// Distance from x where the speed, past its peak, has fallen to `cap` (0 when it never exceeds it):
  // beyond it the speed stays at or below cap.
  double reach_speed(double cap) const {
    if (v_up <= cap) return 0;
#pragma GCC unroll 4
    for (int i = 0; i < kPhases; ++i) {
      const ProfileState& y = at[i];
      const double j = jerk[i], t_end = dur[i];
      if (!(t_end > 0)) continue;
      // The speed falls from t0 on in this phase (a ≤ 0 there); before t0 it rises.
      double t0 = 0;
      if (y.a > 0) {
        if (!(j < 0) || -y.a / j >= t_end) continue;
        t0 = -y.a / j;
      }
      if (advance(y, j, t_end).v > cap) continue;
      const ProfileState y0 = advance(y, j, t0);
      if (y0.v <= cap) return y0.s;
      // v(t) = y0.v + y0.a·t + j·t²/2 = cap on (0, t_end − t0], v falling there: its one root.
      const double c = y0.v - cap, b = y0.a;
      double t;
      if (j == 0) {
        t = -c / b;
      } else {
        const double disc = std::sqrt(std::max(0.0, b * b - 2 * j * c));
        const double q = -0.5 * (b + (b >= 0 ? disc : -disc));  // roots q / (j/2) and c / q
        const double r1 = q / (0.5 * j), r2 = q != 0 ? c / q : r1;
        const double lo = std::min(r1, r2), hi = std::max(r1, r2);
        t = lo >= 0 ? lo : hi;
      }
      t = std::clamp(t, 0.0, t_end - t0);
      return advance(y0, j, t).s;
    }
    return d_stop;
  }
};

// BrakeRamp(x, a, j).d_stop for x.v ≥ 0 and x.a ≥ 0 (a, j > 0, finite) in closed form, up to
// rounding: a few operations where building the ramp's phases costs about 370 instructions. From
// x.a ≥ 0 the ramp runs at jerk −j until a has fallen through 0 (phase 0 and the first phase join):
// the rise to its peak speed w = v + a0²/2j over v·t + a0·t²/3 (t = a0/j), then the ramp to rest
// from (w, 0), symmetric in speed about its middle, so w times half its duration: w·(w/a + a/j)/2
// where it reaches a (w·j ≥ a²), else w·√(w/j).
__attribute__((always_inline)) inline double brake_distance_rising(const ProfileState& x, double a, double j) {
  const double t = x.a / j;
  const double w = x.v + 0.5 * x.a * t;
  const double rise = t * (x.v + x.a * t / 3);
  const double fall = w * j >= a * a ? 0.5 * w * (w / a + a / j) : w * std::sqrt(w / j);
  return rise + fall;
}
// The half-width of the bracket the certificate puts around it, relative: the two roundings differ
// by at most 1.1e-15 of the distance over the jerk benchmarks and test suites (phase 0 included).
inline constexpr double kClosedFormRel = 1e-9;

}  // namespace softmc::motion::guard_detail
