// Ramp–cruise–ramp speed plans over the rest of a block.
#include "motion/interp/velocity_ramp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace softmc::motion {

// rt-safe
VelocityRamp plan_ramp(double dist, double v0, double vc, double v1_want, double v1_max, double acc) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  VelocityRamp r;
  dist = std::max(0.0, dist);
  v0 = std::max(0.0, v0);
  vc = std::max(0.0, vc);
  r.s0 = 0;
  r.dist = dist;
  r.v0 = v0;
  // The planner's passes and this plan reach the same speeds by different roundings, so v0 may lie
  // a hair of v² above what `acc` brakes to the wanted exit over `dist`. The square root below would
  // turn that hair into a speed step where the block ends (1e-13 of v² at 4 mm/s: a reversal left
  // at 1.4e-6 mm/s, 1e-6 over the axis's acceleration in the next cycle). A deceleration higher by
  // at most kBrakeSlack of itself takes up the hair instead.
  constexpr double kBrakeSlack = 1e-9;
  const double v1_target = std::max(0.0, std::min(v1_want, v1_max));
  const double over = v0 * v0 - 2 * acc * dist - v1_target * v1_target;
  const double acc_exact = dist > 0 ? (v0 * v0 - v1_target * v1_target) / (2 * dist) : 0.0;
  const bool hair = dist > 0 && over > 0 && acc_exact <= acc * (1 + kBrakeSlack);
  if (hair) acc = acc_exact;
  // The exit speeds the distance allows from v0, then the wanted one clamped into them.
  const double lo = hair ? v1_target : std::sqrt(std::max(0.0, v0 * v0 - 2 * acc * dist));
  const double hi = std::sqrt(v0 * v0 + 2 * acc * dist);
  double v1 = std::clamp(v1_target, lo, hi);
  v1 = std::min(v1, std::max(vc, lo));  // never speed up past the cruise speed to leave a block
  if (v0 <= vc && v1 <= vc) {
    // Accelerate to the peak (vc, or where the two ramps meet), cruise, brake to v1.
    const double vp = std::clamp(std::sqrt(acc * dist + 0.5 * (v0 * v0 + v1 * v1)), std::max(v0, v1), vc);
    r.a1 = acc;
    r.t1 = (vp - v0) / acc;
    r.vc = vp;
    r.a3 = -acc;
    r.t3 = (vp - v1) / acc;
  } else if (v1 > vc) {
    // Above the cruise speed and unable to reach it within the block: brake all the way, with the
    // deceleration that ends exactly at the block's end (≤ acc, since v1 ≥ lo).
    v1 = lo;
    if (dist > 0 && v0 > v1) {
      r.a1 = -(v0 * v0 - v1 * v1) / (2 * dist);
      r.t1 = 2 * dist / (v0 + v1);
    }
    r.vc = v1;
  } else {
    // Brake to vc, cruise, brake to v1.
    r.a1 = -acc;
    r.t1 = (v0 - vc) / acc;
    r.vc = vc;
    r.a3 = -acc;
    r.t3 = (vc - v1) / acc;
  }
  r.d1 = r.v0 * r.t1 + 0.5 * r.a1 * r.t1 * r.t1;
  const double d3 = r.vc * r.t3 + 0.5 * r.a3 * r.t3 * r.t3;
  r.dc = std::max(0.0, dist - r.d1 - d3);
  if (r.vc > 0) {
    r.tc = r.dc / r.vc;
  } else if (r.dc > 1e-12) {
    r.tc = kInf;  // cruise at rest: held on the path until an input changes
    r.t3 = 0;
  } else {
    r.tc = 0;
  }
  r.v1 = v1;
  return r;
}

// rt-safe
ProfileState VelocityRamp::at(double t) const {
  if (t <= 0) return {s0, v0, a1};
  if (t < t1) return {s0 + std::min(dist, v0 * t + 0.5 * a1 * t * t), v0 + a1 * t, a1};
  t -= t1;
  if (t < tc) return {s0 + std::min(dist, d1 + vc * t), vc, 0};
  t -= tc;
  if (t < t3) return {s0 + std::min(dist, d1 + dc + vc * t + 0.5 * a3 * t * t), vc + a3 * t, a3};
  return {s0 + dist, v1, 0};
}

}  // namespace softmc::motion
