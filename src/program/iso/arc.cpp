// Arcs and helices in any plane: centre format (I/J/K) and radius format (R), as LinuxCNC checks them.
#include "program/iso/arc.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

namespace softmc::program::iso {

double arc_radius_allowance_mm(double r_max_mm, Units units) {
  const double abs_mm = units == Units::Inch ? kArcRadiusAbsToleranceInchMm : kArcRadiusAbsToleranceMm;
  return std::min(100.0 * abs_mm, std::max(abs_mm, kArcRadiusRelTolerance * r_max_mm));
}

std::optional<std::string> make_arc(const ArcRequest& rq, Arc& out) {
  const auto a0 = rq.plane.a0, a1 = rq.plane.a1;
  const double r_start = std::hypot(rq.start[a0] - rq.center0, rq.start[a1] - rq.center1);
  const double r_end = std::hypot(rq.end[a0] - rq.center0, rq.end[a1] - rq.center1);
  if (r_start < kArcZeroRadiusMm || r_end < kArcZeroRadiusMm)
    return fmt::format("zero-radius arc: centre ({:.4f}, {:.4f}) is on the start or end point", rq.center0, rq.center1);
  const double diff = std::fabs(r_end - r_start);
  const double allowed = arc_radius_allowance_mm(std::max(r_start, r_end), rq.units);
  if (diff > allowed)
    return fmt::format(
        "arc end point is not on the circle: radius {:.4f} mm at the start, {:.4f} mm at the end "
        "(they differ by {:.4g} mm, at most {:.4g} mm allowed)",
        r_start, r_end, diff, allowed);
  out = Arc{};
  out.end = rq.end;
  out.center0 = rq.center0;
  out.center1 = rq.center1;
  out.axis0 = a0;
  out.axis1 = a1;
  out.normal = rq.plane.n;
  out.turns = rq.clockwise ? -rq.turns : rq.turns;
  out.feed_mm_s = rq.feed_mm_s;
  return std::nullopt;
}

std::optional<std::string> centre_from_radius(const core::Vec& start, const core::Vec& end, PlaneAxes plane, double r,
                                              bool clockwise, double& c0, double& c1) {
  const double s0 = start[plane.a0], s1 = start[plane.a1], e0 = end[plane.a0], e1 = end[plane.a1];
  if (s0 == e0 && s1 == e1)
    return std::string("R-format arc with the end point equal to the start point: a full circle needs I/J/K");
  const double abs_r = std::fabs(r);
  const double m0 = (s0 + e0) / 2, m1 = (s1 + e1) / 2;
  double half = std::hypot(m0 - e0, m1 - e1);
  // LinuxCNC 2.9 arc_data_r: a radius short of half the chord by up to RADIUS_TOLERANCE (0.00005 in,
  // 0.00127 mm) makes a half circle; shorter is refused.
  if (abs_r == 0 || half - abs_r > kArcRadiusToleranceMm)
    return fmt::format("arc radius {:.4f} mm is too small to reach the end point ({:.4f} mm away)", abs_r, 2 * half);
  if (half / abs_r > 1 - kArcTiny) half = abs_r;  // a semicircle, give or take rounding
  // The centre lies on the perpendicular bisector: to the right of start→end for a short G2 (or a
  // long G3), to the left otherwise.
  const double theta = std::atan2(e1 - s1, e0 - s0) + ((clockwise == (r > 0)) ? -std::numbers::pi / 2 : std::numbers::pi / 2);
  const double turn2 = std::asin(half / abs_r);
  const double offset = abs_r * std::cos(turn2);
  c0 = m0 + offset * std::cos(theta);
  c1 = m1 + offset * std::sin(theta);
  return std::nullopt;
}

double arc_length_mm(const core::Vec& start, const Arc& a) {
  const double r = std::hypot(start[a.axis0] - a.center0, start[a.axis1] - a.center1);
  const double t0 = std::atan2(start[a.axis1] - a.center1, start[a.axis0] - a.center0);
  const double t1 = std::atan2(a.end[a.axis1] - a.center1, a.end[a.axis0] - a.center0);
  double sweep = a.turns > 0 ? t1 - t0 : t0 - t1;
  constexpr double kTwoPi = 2 * std::numbers::pi;
  while (sweep <= 1e-12) sweep += kTwoPi;
  sweep += kTwoPi * (std::abs(a.turns) - 1);
  double other = 0;  // the helix and every other axis, linearly
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    if (i == a.axis0 || i == a.axis1 || (i >= 3 && i <= 5)) continue;
    other += (a.end[i] - start[i]) * (a.end[i] - start[i]);
  }
  return std::hypot(sweep * r, std::sqrt(other));
}

}  // namespace softmc::program::iso
