// Trapezoidal profile planning and sampling.
#include "motion/profile/trapezoid.hpp"

#include <algorithm>
#include <cmath>

namespace softmc::motion {

std::optional<Trapezoid> plan_trapezoid(double length, double v0, double v1, double v_max, double acc) {
  if (!(length >= 0) || !(acc > 0) || !(v_max > 0) || v0 < 0 || v1 < 0) return std::nullopt;
  // Reachability of v1 from v0 over the length, with a small relative slack for rounding.
  if (std::abs(v1 * v1 - v0 * v0) > 2 * acc * length * (1 + 1e-9) + 1e-12) return std::nullopt;
  Trapezoid p;
  p.length = length;
  p.v0 = v0;
  p.v1 = v1;
  p.acc = acc;
  // Peak speed where the acceleration and deceleration ramps meet.
  const double v_meet = std::sqrt(std::max(0.0, acc * length + 0.5 * (v0 * v0 + v1 * v1)));
  p.v_peak = std::max({std::min(v_max, v_meet), v0, v1});
  p.t_acc = (p.v_peak - v0) / acc;
  p.t_dec = (p.v_peak - v1) / acc;
  const double s_acc = 0.5 * (v0 + p.v_peak) * p.t_acc;
  const double s_dec = 0.5 * (p.v_peak + v1) * p.t_dec;
  const double s_cruise = length - s_acc - s_dec;
  p.t_cruise = p.v_peak > 0 ? std::max(0.0, s_cruise) / p.v_peak : 0.0;
  return p;
}

// rt-safe
ProfileState Trapezoid::at(double t) const {
  if (t <= 0) return {0, v0, t_acc > 0 ? acc : 0};
  if (t < t_acc) return {v0 * t + 0.5 * acc * t * t, v0 + acc * t, acc};
  const double s_acc = 0.5 * (v0 + v_peak) * t_acc;
  t -= t_acc;
  if (t < t_cruise) return {s_acc + v_peak * t, v_peak, 0};
  const double s_c = s_acc + v_peak * t_cruise;
  t -= t_cruise;
  if (t < t_dec) return {std::min(length, s_c + v_peak * t - 0.5 * acc * t * t), v_peak - acc * t, -acc};
  return {length, v1, 0};
}

}  // namespace softmc::motion
