// One-cycle moves of the jerk-limited path speed: the velocity ramp and the position-mode stop
// (docs/planner.md, "Jerk"; which one runs is decided by interp/jerk_guard).
//
// A brake that must end at rest (an exact stop, the end of the window) is planned in position mode,
// so the path stops exactly on the point instead of creeping up to it.
#pragma once

#include "motion/profile/jerk_path.hpp"
#include "motion/profile/profile_state.hpp"

namespace softmc::motion {

// rt-safe. The velocity-mode ramp from x towards speed vt (first bringing |a| within a_max), held
// there; returns the state dt later, with x.s as the origin of s.
ProfileState ramp_step(const ProfileState& x, double vt, double a_max, double j_max, double dt);

// rt-safe. The time-optimal jerk-limited motion from x to rest at s = target (x.s as origin), no faster
// than v_max; returns the state dt later. Exact at the target once reached.
ProfileState stop_step(const ProfileState& x, double target, double v_max, double a_max, double j_max, double dt);

}  // namespace softmc::motion
