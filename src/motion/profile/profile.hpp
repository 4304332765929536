// One 1-D speed profile of a selectable kind (trapezoid, jerk-limited S-curve, sine-squared): a value type that
// the planner and SPC moves store per move and sample with at(t). No allocation: a std::variant of plain values.
#pragma once

#include <cstdint>
#include <optional>
#include <variant>

#include "motion/profile/profile_state.hpp"
#include "motion/profile/scurve.hpp"
#include "motion/profile/sine2.hpp"
#include "motion/profile/trapezoid.hpp"

namespace softmc::motion {

// Scurve is the default for ISO moves; Sine2 is SPC's G02 (spc200.md S-2); Trapezoid is SPC's G01/G00.
enum class ProfileKind : std::uint8_t { Trapezoid, Scurve, Sine2 };
const char* to_string(ProfileKind k);

class Profile {
 public:
  Profile() = default;  // an empty trapezoid: duration 0, at rest at 0
  explicit Profile(const Trapezoid& p) : p_(p) {}
  explicit Profile(const Scurve& p) : p_(p) {}
  explicit Profile(const Sine2& p) : p_(p) {}

  ProfileKind kind() const { return static_cast<ProfileKind>(p_.index()); }
  // rt-safe
  double duration() const;
  // rt-safe: closed form; t is clamped to [0, duration].
  ProfileState at(double t) const;
  double length() const;

  // The held profile, or nullptr when it is of another kind.
  const Trapezoid* trapezoid() const { return std::get_if<Trapezoid>(&p_); }
  const Scurve* scurve() const { return std::get_if<Scurve>(&p_); }
  const Sine2* sine2() const { return std::get_if<Sine2>(&p_); }

 private:
  std::variant<Trapezoid, Scurve, Sine2> p_;  // order = ProfileKind
};

// Plans a profile of the given kind (see plan_trapezoid / plan_scurve / plan_sin2): j_max is ignored by the
// trapezoid; j_max = 0 makes the S-curve a trapezoid and leaves the sine-squared jerk to follow from a_max.
std::optional<Profile> plan_profile(ProfileKind kind, double length, double v0, double v1, double v_max, double a_max,
                                    double j_max);

}  // namespace softmc::motion
