// S-curve planning: bisection on the peak speed, then the 7 phases laid out on a JerkPath.
#include "motion/profile/scurve.hpp"

#include <algorithm>
#include <cmath>

#include "motion/profile/peak_speed.hpp"

namespace softmc::motion {

namespace {

// Length used by the two ramps v0 → vp → v1 with no cruise. Each ramp starts and ends with a = 0, so it is
// point-symmetric and its length is the mean speed times its duration. Increasing in vp ≥ max(v0, v1).
double ramps_length(double v0, double vp, double v1, double a_max, double j_max) {
  const Ramp up = plan_ramp(v0, 0, vp, a_max, j_max);
  const Ramp down = plan_ramp(vp, 0, v1, a_max, j_max);
  return 0.5 * (v0 + vp) * up.duration() + 0.5 * (vp + v1) * down.duration();
}

}  // namespace

std::optional<Scurve> plan_scurve(double length, double v0, double v1, double v_max, double a_max, double j_max) {
  const auto j = profile_detail::move_jerk(length, v0, v1, v_max, a_max, j_max);
  if (!j) return std::nullopt;
  j_max = *j;
  const auto peak = profile_detail::peak_speed(
      length, v0, v1, v_max, [&](double vp) { return ramps_length(v0, vp, v1, a_max, j_max); });
  if (!peak) return std::nullopt;  // v1 unreachable
  const double vp = *peak;

  Scurve p;
  p.length = length;
  p.v0 = v0;
  p.v1 = v1;
  p.v_peak = vp;
  p.a_max = a_max;
  p.j_max = j_max;
  p.up = plan_ramp(v0, 0, vp, a_max, j_max);
  p.down = plan_ramp(vp, 0, v1, a_max, j_max);
  const double rest = length - (0.5 * (v0 + vp) * p.up.duration() + 0.5 * (vp + v1) * p.down.duration());
  p.t_cruise = vp > 0 ? std::max(0.0, rest) / vp : 0.0;
  p.path.reset({0, v0, 0, 0});
  push_ramp(p.path, p.up);
  p.path.push(p.t_cruise, 0);
  push_ramp(p.path, p.down);
  p.path.snap_end({length, v1, 0, 0});
  return p;
}

}  // namespace softmc::motion
