// Centre-format (I/J) arcs in the XY plane: centre, signed turns, and the end-on-circle check.
#include "program/iso/arc.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace softmc::program::iso {

double arc_radius_allowance_mm(double r_max_mm, Units units) {
  const double abs_mm = units == Units::Inch ? kArcRadiusAbsToleranceInchMm : kArcRadiusAbsToleranceMm;
  return std::min(100.0 * abs_mm, std::max(abs_mm, kArcRadiusRelTolerance * r_max_mm));
}

std::optional<std::string> make_arc(const ArcRequest& rq, Arc& out) {
  const double r_start = std::hypot(rq.start[0] - rq.center0, rq.start[1] - rq.center1);
  const double r_end = std::hypot(rq.end[0] - rq.center0, rq.end[1] - rq.center1);
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
  out.axis0 = static_cast<std::uint8_t>(core::index(core::Axis::X));
  out.axis1 = static_cast<std::uint8_t>(core::index(core::Axis::Y));
  out.normal = static_cast<std::uint8_t>(core::index(core::Axis::Z));
  out.turns = rq.clockwise ? -rq.turns : rq.turns;
  out.feed_mm_s = rq.feed_mm_s;
  return std::nullopt;
}

}  // namespace softmc::program::iso
