// Polar coordinates @ (radius) and ^ (angle, degrees): LinuxCNC 2.9's rules for the end point of a
// move (interp_find.cc find_ends) and what a block with them may hold (interp_internal.cc enhance_block).
// The canned cycles' own use of them (convert_cycle_xy) is in canned.cpp.
//
//        Y                          in program coordinates of the current coordinate system, G17 only:
//        │      • end               G90  @r ^t   (r cos t, r sin t)
//        │     /                    G90  @r      radius r along the current angle (not at the origin)
//        │    / r                   G90  ^t      the current radius at angle t
//        │   /                      G91  @dr     current radius + dr along the current angle
//        │  /  t                    G91  ^dt     current angle + dt at the current radius
//   ─────┼──────── X                (G91 with both: the radius first, then the angle; neither at the origin)
//     origin
// The centre is always the origin of the coordinate system, never the current point, also in G91.
#include <cmath>
#include <numbers>

#include "program/iso/exec.hpp"

namespace softmc::program::iso::detail {

double polar_radians(double deg) { return deg * std::numbers::pi / 180.0; }  // LinuxCNC's D2R

void polar_point(double& x, double& y, std::optional<double> r, std::optional<double> t) {
  const double radius = r ? *r : std::hypot(y, x);
  const double theta = t ? *t : std::atan2(y, x);
  x = radius * std::cos(theta);
  y = radius * std::sin(theta);
}

PolarStep polar_increment(double& x, double& y, std::optional<double> dr, std::optional<double> dt_rad) {
  if (dr) {
    if (x == 0 && y == 0) return PolarStep::RadiusAtOrigin;
    polar_point(x, y, std::hypot(y, x) + *dr, std::nullopt);
  }
  if (dt_rad) {
    if (x == 0 && y == 0) return PolarStep::AngleAtOrigin;
    polar_point(x, y, std::nullopt, std::atan2(y, x) + *dt_rad);
  }
  return PolarStep::Ok;
}

std::optional<LineError> Exec::polar_words() {
  if (!b.has_polar()) return std::nullopt;
  const std::uint32_t col = b.first_polar_col();
  // LinuxCNC checks the plane in effect before the block: a G17 in the block itself comes too late.
  // A block that leaves G17 is refused too (rs274 would still move X and Y in the new plane).
  if (st.plane != Plane::XY)
    return error(col, fmt::format("polar coordinates (@ ^) work only in the G17 plane, and {} is in effect{}",
                                  plane_code(st.plane),
                                  b.plane && b.plane->value == Plane::XY ? ": select G17 on an earlier line" : ""));
  if (b.plane && b.plane->value != Plane::XY)
    return error(col, fmt::format("polar coordinates (@ ^) work only in the G17 plane, and this block selects {}",
                                  plane_code(b.plane->value)));
  for (const char l : {'X', 'Y'})
    if (const auto& x = b.word(l))
      return error(x->col, fmt::format("{} word together with polar coordinates (@ ^): they give X and Y, use one or the "
                                       "other", l));
  if (b.g53_col) return error(*b.g53_col, "G53 cannot be used with polar coordinates (@ ^)");
  // G10, G28, G30, G92 and G43.1 take axis words for themselves (LinuxCNC: "Polar coordinates can only be
  // used for motion"); G28.1 and G30.1 take none.
  int setup_code = b.axis_words_code();
  if (!setup_code && b.non_modal && (b.non_modal->value == 281 || b.non_modal->value == 301))
    setup_code = b.non_modal->value;
  if (setup_code != 0)
    return error(col, fmt::format("polar coordinates (@ ^) can only be used for motion, not with {}", g_code_name(setup_code)));
  if (b.nurbs_end) return error(col, "G5.3 takes no polar coordinates (@ ^)");
  // LinuxCNC's G5.2 reads its control points from X and Y only and would ignore @ and ^ silently.
  if ((b.motion ? b.motion->value : st.motion) == Motion::Nurbs)
    return error(col, "polar coordinates (@ ^) cannot give a NURBS control point (G5.2): use X and Y");
  return std::nullopt;
}

std::optional<LineError> Exec::polar_end(double& x, double& y) {
  const auto& r = b.polar_radius;
  const auto& a = b.polar_angle;
  if (st.distance == Distance::Absolute) {
    if (r && !a && x == 0 && y == 0)
      return error(r->col, "polar radius (@) without an angle (^) at the origin: the current angle is undefined there");
    polar_point(x, y, r ? std::optional<double>(r->value * k()) : std::nullopt,
                a ? std::optional<double>(polar_radians(a->value)) : std::nullopt);
    return std::nullopt;
  }
  const std::optional<double> dr = r ? std::optional<double>(r->value * k()) : std::nullopt;
  const std::optional<double> dt = a ? std::optional<double>(polar_radians(a->value)) : std::nullopt;
  switch (polar_increment(x, y, dr, dt)) {
    case PolarStep::Ok: return std::nullopt;
    case PolarStep::RadiusAtOrigin:
      return error(r->col, "incremental polar coordinates (G91 @) at the origin: the current angle is undefined there");
    case PolarStep::AngleAtOrigin:
      return error(a->col, "incremental polar coordinates (G91 ^) at the origin: the current angle is undefined there");
  }
  return std::nullopt;
}

}  // namespace softmc::program::iso::detail
