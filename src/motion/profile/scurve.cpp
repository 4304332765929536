// S-curve planning: bisection on the peak speed, then the 7 phases laid out on a JerkPath.
#include "motion/profile/scurve.hpp"

#include <algorithm>
#include <cmath>

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
  if (!std::isfinite(length) || !std::isfinite(v0) || !std::isfinite(v1) || !std::isfinite(a_max)) return std::nullopt;
  if (!(length >= 0) || !(v_max > 0) || !(a_max > 0) || v0 < 0 || v1 < 0 || std::isnan(j_max) || j_max < 0)
    return std::nullopt;
  if (std::isinf(j_max)) j_max = 0;
  const double tol = 1e-9 * length + 1e-12;  // rounding slack on reachability

  double lo = std::max(v0, v1);
  if (ramps_length(v0, lo, v1, a_max, j_max) > length + tol) return std::nullopt;  // v1 unreachable
  double hi = std::max(lo, std::isinf(v_max) ? lo : v_max);
  double vp = hi;
  if (ramps_length(v0, hi, v1, a_max, j_max) > length) {
    // Invariant: ramps_length(lo) ≤ length (up to tol) < ramps_length(hi).
    for (int i = 0; i < 80 && hi - lo > 1e-15 * hi; ++i) {
      const double mid = 0.5 * (lo + hi);
      (ramps_length(v0, mid, v1, a_max, j_max) <= length ? lo : hi) = mid;
    }
    vp = lo;
  }

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
