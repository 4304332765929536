// Jerk-limited path speed, decided online every cycle: accelerate towards the cruise speed while every
// speed limit ahead can still be met with a jerk-limited brake, otherwise brake (docs/planner.md, "Jerk").
//
//   v ^         u1 (junction)      u2        0 (end of the window)
//     |   ____   :                  :         :      candidate: one cycle of the ramp towards the
//     |  /    \__:__           ___ :         :      cruise speed; kept when, from the state it
//     | /        :  \_________/   \:___      :      reaches, every limit u_k at distance d_k ahead
//     |/         :                 :    \____:      can still be met: brake_distance(v, a → u_k)
//     +---------------------------------------> s   ≤ d_k; else the brake towards the binding one
//
// A brake that must end at rest (an exact stop, the end of the window) is planned in position mode,
// so the path stops exactly on the point instead of creeping up to it.
#pragma once

#include "motion/profile/jerk_path.hpp"
#include "motion/profile/profile_state.hpp"

namespace softmc::motion {

// rt-safe. Distance the path needs from speed v, acceleration a, braking as hard as the limits allow
// (|a| ≤ a_max, |jerk| ≤ j_max), until its speed has fallen to u — still braking, when that leaves
// room to end the brake without reversing, else with a = 0. 0 when the speed never exceeds u.
// `a_end_max` bounds the deceleration at the point (the next block's own limit): beyond it, the ramp
// must end with a = 0.
double brake_distance(double v, double a, double u, double a_max, double j_max, double a_end_max);

// rt-safe. The hardest brake (jerk −j until a = −a_max, then hold) for dt from x (x.s as origin).
ProfileState brake_step(const ProfileState& x, double a_max, double j_max, double dt);

// rt-safe. The velocity-mode ramp from x towards speed vt (first bringing |a| within a_max), held
// there; returns the state dt later, with x.s as the origin of s.
ProfileState ramp_step(const ProfileState& x, double vt, double a_max, double j_max, double dt);

// rt-safe. The time-optimal jerk-limited motion from x to rest at s = target (x.s as origin), no faster
// than v_max; returns the state dt later. Exact at the target once reached.
ProfileState stop_step(const ProfileState& x, double target, double v_max, double a_max, double j_max, double dt);

}  // namespace softmc::motion
