// The 3-phase speed ramp: closed-form planning and integration.
#include "motion/profile/jerk_ramp.hpp"

#include <algorithm>
#include <cmath>

namespace softmc::motion {

// rt-safe
Ramp plan_ramp(double v0, double a0, double v1, double a_max, double j_max) {
  Ramp r;
  if (!(j_max > 0) || std::isinf(j_max)) {
    // Jerk-unlimited: a trapezoid's ramp, the initial acceleration plays no part.
    r.dir = v1 >= v0 ? 1 : -1;
    r.a_peak = a_max;
    r.t2 = std::abs(v1 - v0) / a_max;
    return r;
  }
  r.j = j_max;
  r.dir = v1 >= inflection_speed(v0, a0, j_max) ? 1 : -1;
  // In the ramp's own frame the speed must rise by dv, starting with acceleration ac.
  const double ac = r.dir * a0;
  const double dv = r.dir * (v1 - v0);
  // Speed gained by going ac → a_max → 0 with no hold: (2·a_max² − ac²) / 2j.
  const double dv_sat = (2 * a_max * a_max - ac * ac) / (2 * j_max);
  double A;
  if (dv >= dv_sat) {
    A = a_max;
    r.t2 = (dv - dv_sat) / a_max;
  } else {
    A = std::sqrt(std::max(0.0, (2 * j_max * dv + ac * ac) / 2));
  }
  A = std::max({A, ac, 0.0});  // rounding near the inflection speed must not flip a phase's sign
  r.a_peak = A;
  r.t1 = (A - ac) / j_max;
  r.t3 = A / j_max;
  return r;
}

// rt-safe
ProfileState ramp_end(const ProfileState& x0, const Ramp& r) {
  if (r.j == 0) {
    ProfileState x = x0;
    x.a = r.dir * r.a_peak;
    x = advance(x, 0, r.t2);
    x.a = 0;
    return x;
  }
  ProfileState x = advance(x0, r.dir * r.j, r.t1);
  x = advance(x, 0, r.t2);
  x = advance(x, -r.dir * r.j, r.t3);
  x.a = 0;  // exactly zero by construction; drop the rounding
  x.j = 0;
  return x;
}

void push_ramp(JerkPath& path, const Ramp& r) {
  if (r.j == 0) {
    path.push_acc(r.t2, r.dir * r.a_peak);
  } else {
    path.push(r.t1, r.dir * r.j);
    path.push(r.t2, 0);
    path.push(r.t3, -r.dir * r.j);
  }
  path.set_end_acc(0);
}

}  // namespace softmc::motion
