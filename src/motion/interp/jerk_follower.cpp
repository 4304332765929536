// Jerk-limited online path speed: brake distances and one-cycle ramps.
#include "motion/interp/jerk_follower.hpp"

#include <algorithm>
#include <cmath>

#include "motion/profile/jerk_ramp.hpp"
#include "motion/profile/otg1.hpp"

namespace softmc::motion {

namespace {
// Distance of the full ramp from (v, a) down to (u, a = 0).
double ramp_distance(double v, double a, double u, double a_max, double j_max) {
  const double a0 = std::clamp(a, -a_max, a_max);
  return ramp_end({0, v, a0, 0}, plan_ramp(v, a0, u, a_max, j_max)).s;
}
}  // namespace

// rt-safe
double brake_distance(double v, double a, double u, double a_max, double j_max, double a_end_max) {
  a = std::max(a, -a_max);  // above +a_max the brake's first phase simply starts higher
  const double infl = inflection_speed(v, a, j_max);
  if (v <= u && infl <= u) return 0;
  // Hardest brake: jerk −j until a = −a_max, then hold. Time at which the falling speed reaches u:
  // v + a·t − j·t²/2 = u (the root after the peak), else in the hold phase.
  const double t1 = (a + a_max) / j_max;
  double t = (a + std::sqrt(std::max(0.0, a * a + 2 * j_max * (v - u)))) / j_max;
  double dist, a_cross;
  if (t <= t1) {
    dist = t * (v + t * (0.5 * a - t * j_max / 6.0));
    a_cross = a - j_max * t;
  } else {
    const double v1 = v + a * t1 - 0.5 * j_max * t1 * t1;
    const double s1 = t1 * (v + t1 * (0.5 * a - t1 * j_max / 6.0));
    const double tau = (v1 - u) / a_max;
    dist = s1 + tau * (v1 - 0.5 * a_max * tau);
    a_cross = -a_max;
  }
  // Crossing u while braking that hard must leave room to bring a back to 0 before the speed would
  // reverse (u ≥ a²/2j); otherwise the limit is the full ramp to (u, a = 0).
  if (a_cross * a_cross > 2 * j_max * u || -a_cross > a_end_max) return ramp_distance(v, a, u, a_max, j_max);
  return dist;
}

// rt-safe
ProfileState brake_step(const ProfileState& x, double a_max, double j_max, double dt) {
  JerkPath p;
  ProfileState s0 = x;
  s0.s = 0;
  p.reset(s0);
  if (s0.a < -a_max) p.push((-a_max - s0.a) / j_max, j_max);  // back within the (lowered) limit
  else p.push((s0.a + a_max) / j_max, -j_max);
  p.push(dt + 1, 0);
  return p.at(dt);
}

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
