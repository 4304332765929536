// Cubic interpolating splines through any number of points (the method cutting_table.md T-2 says
// the thesis wished for), in any axes, as C²-continuous cubic Bézier segments.
//
//   parameter t: cumulative chord length |P_i+1 - P_i| (default), or one axis's coordinate
//   (a function spline y(x); that axis must be strictly monotonic)
//   slopes D_i = dP/dt from the tridiagonal C² system, ends natural (P'' = 0) or clamped (D = given)
//   piece i: P_i, P_i + D_i·h_i/3, P_i+1 - D_i+1·h_i/3, P_i+1
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <variant>

#include "motion/geometry/curve_result.hpp"

namespace softmc::motion {

struct NaturalEnds {};
// dP/dt at the first and the last point (with the chord-length parameter a unit vector means
// "this direction at the natural speed").
struct ClampedEnds {
  Vec d0, d1;
};
using SplineEnds = std::variant<NaturalEnds, ClampedEnds>;

// One segment per interval (more only if a piece is near a cusp and gets halved, see
// append_rational_bezier); the segments pass exactly through every point.
CurveResult cubic_spline(std::span<const Vec> points, const SplineEnds& ends = NaturalEnds{},
                         std::optional<std::uint8_t> param_axis = std::nullopt);

}  // namespace softmc::motion
