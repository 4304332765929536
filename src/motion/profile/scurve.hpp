// Jerk-limited S-curve speed profile over a length (7 phases), from v0 to v1 with zero acceleration at both ends.
//
//   v ^        _________               phases: jerk +j, hold +a, jerk −j  (ramp up to v_peak)
//     |      /           \                     cruise at v_peak
//  v0 |____/               \____ v1            jerk −j, hold −a, jerk +j  (ramp down to v1)
//     +------------------------------> t
// Time-optimal: v_peak is the highest speed ≤ v_max whose two ramps fit in the length (found by bisection
// on the monotone distance-of-ramps function; the leftover length becomes the cruise).
#pragma once

#include <optional>

#include "motion/profile/jerk_path.hpp"
#include "motion/profile/jerk_ramp.hpp"
#include "motion/profile/profile_state.hpp"

namespace softmc::motion {

struct Scurve {
  double length = 0;  // mm
  double v0 = 0, v_peak = 0, v1 = 0;  // mm/s
  double a_max = 0, j_max = 0;        // mm/s², mm/s³ (j_max = 0: jerk-unlimited, i.e. a trapezoid)
  Ramp up, down;
  double t_cruise = 0;  // s
  JerkPath path;

  double duration() const { return path.duration(); }
  // rt-safe: closed form; t is clamped to [0, duration].
  ProfileState at(double t) const { return path.at(t); }
};

// Time-optimal S-curve over `length` from v0 to v1 (zero acceleration at both ends), cruise speed at most
// max(v_max, v0, v1), |a| ≤ a_max, |jerk| ≤ j_max (0 = no jerk limit). Nothing when the input is invalid or
// v1 cannot be reached from v0 within the length. Bounded work (≤ 80 bisection steps); no allocation.
std::optional<Scurve> plan_scurve(double length, double v0, double v1, double v_max, double a_max, double j_max);

}  // namespace softmc::motion
