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
ProfileState StopPlan::step(const ProfileState& x, double target, double v_max, double a_max, double j_max,
                            double dt) {
  asked_ = true;
  const OtgLimits lim{std::max(v_max, 1e-9), a_max, j_max};
  if (kept_ && lim.v_max_mm_s == v_max_ && a_max == a_max_ && j_max == j_max_) {
    const ProfileState here = otg_.at(t_);
    // The same state (taken from this plan) and the same point, to the rounding of the distances.
    if (here.v == x.v && here.a == x.a && std::abs(target - (target_ - here.s)) <= 1e-12 * std::max(1.0, target)) {
      ProfileState y = otg_.at(t_ + dt);
      y.s -= here.s;
      t0_ = t_;
      s0_ = here.s;
      solved_ = true;
      t_next_ = t_ + dt;
      ++reuses_;
      return y;
    }
  }
  kept_ = false;
  otg_.reset({0, x.v, x.a, 0});  // Otg1 first brings |a| within a_max at full jerk
  t0_ = s0_ = 0;
  solved_ = otg_.update(target, lim) != OtgResult::ErrorInvalidInput;
  if (!solved_) {
    x0_ = x;
    a0_ = a_max;
    j0_ = j_max;
    return ramp_step(x, 0, a_max, j_max, dt);
  }
  ++solves_;
  kept_ = true;
  v_max_ = lim.v_max_mm_s;
  a_max_ = a_max;
  j_max_ = j_max;
  target_ = target;
  t_ = 0;
  t_next_ = dt;
  return otg_.at(dt);
}

// rt-safe
ProfileState StopPlan::last_at(double t) const {
  if (!solved_) return ramp_step(x0_, 0, a0_, j0_, t);
  ProfileState y = otg_.at(t0_ + t);
  y.s -= s0_;
  return y;
}

// rt-safe
void StopPlan::taken(bool yes) {
  if (yes && asked_ && kept_) {
    t_ = t_next_;
  } else {
    kept_ = false;
  }
  asked_ = false;
}

}  // namespace softmc::motion
