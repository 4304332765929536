// Trapezoidal velocity profile along one coordinate (path length s): accelerate, cruise, decelerate.
//
//   v ^    ____________
//     |   /            \   .
//  v0 |  /              \  v1
//     |_/________________\___> t
//       t_acc   t_cruise  t_dec
#pragma once

#include <optional>

#include "motion/profile/profile_state.hpp"

namespace softmc::motion {

struct Trapezoid {
  double length = 0;
  double v0 = 0, v_peak = 0, v1 = 0;
  double acc = 0;  // mm/s², > 0
  double t_acc = 0, t_cruise = 0, t_dec = 0;

  double duration() const { return t_acc + t_cruise + t_dec; }
  // rt-safe: closed form; t is clamped to [0, duration].
  ProfileState at(double t) const;
};

// Time-optimal trapezoid over `length` from speed v0 to v1 with cruise speed at most v_max and
// acceleration at most acc. Nothing when v1 cannot be reached from v0 within the length.
std::optional<Trapezoid> plan_trapezoid(double length, double v0, double v1, double v_max, double acc);

}  // namespace softmc::motion
