// Jerk-limited online path speed: brake distances and one-cycle ramps.
#include "motion/interp/jerk_follower.hpp"

#include <algorithm>
#include <cmath>

#include "motion/profile/jerk_ramp.hpp"
#include "motion/profile/otg1.hpp"

namespace softmc::motion {

// rt-safe
ProfileState ramp_step(const ProfileState& x, double vt, double a_max, double j_max, double dt) {
  JerkPath p;
  ProfileState s0 = x;
  s0.s = 0;
  p.reset(s0);
  if (std::abs(s0.a) > a_max) p.push((std::abs(s0.a) - a_max) / j_max, s0.a > 0 ? -j_max : j_max);
  ProfileState b = p.end();
  b.a = std::clamp(b.a, -a_max, a_max);
  push_ramp(p, plan_ramp(b.v, b.a, vt, a_max, j_max));
  ProfileState e = p.end();
  e.v = vt;  // exactly the target once there
  p.snap_end(e);
  ProfileState r = p.at(dt);
  if (dt > p.duration()) r.s = e.s + vt * (dt - p.duration());
  return r;
}

// rt-safe
ProfileState stop_step(const ProfileState& x, double target, double v_max, double a_max, double j_max, double dt) {
  Otg1 otg;
  otg.reset({0, x.v, x.a, 0});  // Otg1 first brings |a| within a_max at full jerk
  OtgLimits lim{std::max(v_max, 1e-9), a_max, j_max};
  if (otg.update(target, lim) == OtgResult::ErrorInvalidInput) return ramp_step(x, 0, a_max, j_max, dt);
  return otg.at(dt);
}

}  // namespace softmc::motion
