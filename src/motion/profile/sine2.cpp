// Sine-squared profile: planning (bisection on the peak speed) and closed-form sampling.
#include "motion/profile/sine2.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "motion/profile/peak_speed.hpp"

namespace softmc::motion {

namespace {

constexpr double kPi = std::numbers::pi;

// The ramp starts and ends with a = 0 and is point-symmetric: its length is mean speed × duration.
double ramps_length(double v0, double vp, double v1, double a_max, double j_max) {
  return 0.5 * (v0 + vp) * plan_sine2_ramp(v0, vp, a_max, j_max).t +
         0.5 * (vp + v1) * plan_sine2_ramp(vp, v1, a_max, j_max).t;
}

// State after τ seconds of ramp r started at (s0, v0).
ProfileState ramp_at(const Sine2Ramp& r, double s0, double v0, double tau) {
  if (!(r.t > 0)) return {s0, v0, 0, 0};
  const double w = kPi / r.t;
  const double sn = std::sin(w * tau);
  const double s2 = std::sin(2 * w * tau), c2 = std::cos(2 * w * tau);
  const double A = r.a_peak;
  return {s0 + v0 * tau + A * (0.25 * tau * tau + (c2 - 1) / (8 * w * w)),
          v0 + A * (0.5 * tau - s2 / (4 * w)), A * sn * sn, A * w * s2};
}

}  // namespace

double Sine2Ramp::jerk_peak() const { return t > 0 ? std::abs(a_peak) * kPi / t : 0.0; }

double Sine2::jerk_peak() const { return std::max(up.jerk_peak(), down.jerk_peak()); }

Sine2Ramp plan_sine2_ramp(double v_from, double v_to, double a_max, double j_max) {
  const double dv = std::abs(v_to - v_from);
  if (dv == 0) return {};
  // Speed change dv = a_p·T/2, peak jerk a_p·π/T = a_p²·π/(2·dv): the jerk bound caps a_p at √(2·dv·j/π).
  double ap = a_max;
  if (j_max > 0) ap = std::min(ap, std::sqrt(2 * dv * j_max / kPi));
  return {v_to > v_from ? ap : -ap, 2 * dv / ap};
}

std::optional<Sine2> plan_sin2(double length, double v0, double v1, double v_max, double a_max, double j_max) {
  const auto j = profile_detail::move_jerk(length, v0, v1, v_max, a_max, j_max);
  if (!j) return std::nullopt;
  j_max = *j;
  const auto peak = profile_detail::peak_speed(
      length, v0, v1, v_max, [&](double vp) { return ramps_length(v0, vp, v1, a_max, j_max); });
  if (!peak) return std::nullopt;
  const double vp = *peak;
  Sine2 p;
  p.length = length;
  p.v0 = v0;
  p.v1 = v1;
  p.v_peak = vp;
  p.up = plan_sine2_ramp(v0, vp, a_max, j_max);
  p.down = plan_sine2_ramp(vp, v1, a_max, j_max);
  const double rest = length - ramps_length(v0, vp, v1, a_max, j_max);
  p.t_cruise = vp > 0 ? std::max(0.0, rest) / vp : 0.0;
  return p;
}

// rt-safe
ProfileState Sine2::at(double t) const {
  if (t <= 0) return {0, v0, 0, 0};
  if (t >= duration()) return {length, v1, 0, 0};  // before the subtractions below round it into the ramp
  if (t < up.t) return ramp_at(up, 0, v0, t);
  const double s_up = 0.5 * (v0 + v_peak) * up.t;
  t -= up.t;
  if (t < t_cruise) return {s_up + v_peak * t, v_peak, 0, 0};
  t -= t_cruise;
  if (t < down.t) {
    ProfileState x = ramp_at(down, s_up + v_peak * t_cruise, v_peak, t);
    x.s = std::min(x.s, length);
    return x;
  }
  return {length, v1, 0, 0};
}

}  // namespace softmc::motion
