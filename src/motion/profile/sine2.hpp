// Sine-squared speed profile over a length (SPC G02, spc200.md S-2): the acceleration of each ramp is a sin² bump.
//
//   a ^   .-.                      a(τ) = a_p · sin²(π τ / T)  over a ramp of T seconds:
//     |  /   \                     smooth (a and jerk continuous), speed change a_p·T/2,
//     |_/     \______     ___      peak jerk a_p·π/T at τ = T/4.
//     |                \_/
//     +--------------------------> t
// Peak acceleration a_p ≤ a_max; with j_max > 0 also a_p·π/T ≤ j_max. Time-optimal within the family: the
// highest peak speed ≤ v_max whose two ramps fit in the length (bisection); the rest is cruise.
#pragma once

#include <optional>

#include "motion/profile/profile_state.hpp"

namespace softmc::motion {

struct Sine2Ramp {
  double a_peak = 0;  // mm/s², signed: > 0 speeds up
  double t = 0;       // s

  double jerk_peak() const;  // mm/s³, magnitude: |a_peak|·π/t
};

struct Sine2 {
  double length = 0;  // mm
  double v0 = 0, v_peak = 0, v1 = 0;  // mm/s
  Sine2Ramp up, down;
  double t_cruise = 0;  // s

  double duration() const { return up.t + t_cruise + down.t; }
  // The largest |jerk| of the profile: the figure a G02 move imposes on the mechanics.
  double jerk_peak() const;
  // rt-safe: closed form; t is clamped to [0, duration].
  ProfileState at(double t) const;
};

// The sin² ramp changing the speed from v_from to v_to, as fast as a_max (and j_max > 0, if given) allow.
Sine2Ramp plan_sine2_ramp(double v_from, double v_to, double a_max, double j_max);

// Time-optimal sine-squared profile over `length` from v0 to v1, cruise speed at most max(v_max, v0, v1),
// peak acceleration ≤ a_max, and peak jerk ≤ j_max when j_max > 0 (0: jerk follows from a_max and the speed
// change, see Sine2::jerk_peak). Nothing when the input is invalid or v1 is unreachable within the length.
std::optional<Sine2> plan_sin2(double length, double v0, double v1, double v_max, double a_max, double j_max = 0);

}  // namespace softmc::motion
