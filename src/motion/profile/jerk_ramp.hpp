// The fastest change of speed from (v0, a0) to (v1, a = 0) under acceleration and jerk limits: the 3-phase ramp
// that S-curves and the online trajectory generator are built from.
//
//   a ^      _______             jerk +dir·j for t1 (a: a0 → dir·a_peak), hold for t2,
//     |     /       \            jerk −dir·j for t3 (a: dir·a_peak → 0).
//  a0 |____/         \           dir = +1 raises the speed, −1 lowers it; a0 may point either way
//     +---------------\----> t   (it must satisfy |a0| ≤ a_max).
//
// j_max = 0 means no jerk limit: the acceleration jumps to dir·a_max, holds for t2, jumps back to 0.
#pragma once

#include "motion/profile/jerk_path.hpp"
#include "motion/profile/profile_state.hpp"

namespace softmc::motion {

struct Ramp {
  double dir = 1;     // +1: speed rises; −1: speed falls
  double a_peak = 0;  // mm/s², magnitude of the held acceleration, ≤ a_max
  double j = 0;       // mm/s³, jerk magnitude used (0 = jerk-unlimited)
  double t1 = 0, t2 = 0, t3 = 0;  // s

  double duration() const { return t1 + t2 + t3; }
};

// rt-safe. Plans the time-optimal ramp; a_max > 0, j_max ≥ 0, |a0| ≤ a_max when j_max > 0.
Ramp plan_ramp(double v0, double a0, double v1, double a_max, double j_max);

// rt-safe. The state at the end of `r` started from `x` (exact in closed form up to rounding).
ProfileState ramp_end(const ProfileState& x, const Ramp& r);

// Appends the ramp's phases to a path (the path's end state must be the ramp's start).
void push_ramp(JerkPath& path, const Ramp& r);

// The speed reached when a jerk-limited axis brings its acceleration a0 to zero as fast as it can.
inline double inflection_speed(double v0, double a0, double j_max) {
  return j_max > 0 ? v0 + a0 * (a0 < 0 ? -a0 : a0) / (2 * j_max) : v0;
}

}  // namespace softmc::motion
