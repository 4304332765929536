// Profile: dispatch to the kind held (by index, so nothing on the sampling path can throw).
#include "motion/profile/profile.hpp"

namespace softmc::motion {

static_assert(std::variant_size_v<std::variant<Trapezoid, Scurve, Sine2>> == 3);

const char* to_string(ProfileKind k) {
  switch (k) {
    case ProfileKind::Trapezoid: return "trapezoid";
    case ProfileKind::Scurve: return "scurve";
    case ProfileKind::Sine2: return "sine2";
  }
  return "?";
}

// rt-safe
double Profile::duration() const {
  if (auto* p = std::get_if<Trapezoid>(&p_)) return p->duration();
  if (auto* p = std::get_if<Scurve>(&p_)) return p->duration();
  if (auto* p = std::get_if<Sine2>(&p_)) return p->duration();
  return 0;
}

// rt-safe
ProfileState Profile::at(double t) const {
  if (auto* p = std::get_if<Trapezoid>(&p_)) return p->at(t);
  if (auto* p = std::get_if<Scurve>(&p_)) return p->at(t);
  if (auto* p = std::get_if<Sine2>(&p_)) return p->at(t);
  return {};
}

double Profile::length() const {
  if (auto* p = std::get_if<Trapezoid>(&p_)) return p->length;
  if (auto* p = std::get_if<Scurve>(&p_)) return p->length;
  if (auto* p = std::get_if<Sine2>(&p_)) return p->length;
  return 0;
}

std::optional<Profile> plan_profile(ProfileKind kind, double length, double v0, double v1, double v_max, double a_max,
                                    double j_max) {
  switch (kind) {
    case ProfileKind::Trapezoid:
      if (auto p = plan_trapezoid(length, v0, v1, v_max, a_max)) return Profile(*p);
      return std::nullopt;
    case ProfileKind::Scurve:
      if (auto p = plan_scurve(length, v0, v1, v_max, a_max, j_max)) return Profile(*p);
      return std::nullopt;
    case ProfileKind::Sine2:
      if (auto p = plan_sin2(length, v0, v1, v_max, a_max, j_max)) return Profile(*p);
      return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace softmc::motion
