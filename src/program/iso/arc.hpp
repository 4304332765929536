// Arcs and helices in any plane: centre format (I/J/K) and radius format (R), as LinuxCNC checks them.
#pragma once

#include <optional>
#include <string>

#include "core/axes.hpp"
#include "program/ir/program.hpp"
#include "program/iso/modes.hpp"

namespace softmc::program::iso {

// Tolerances mirror LinuxCNC's interpreter (interp_internal.hh, arc_data_ijk), converted to mm.
// A radius below this is a zero-radius arc (LinuxCNC RADIUS_TOLERANCE_INCH = 0.00005 in).
inline constexpr double kArcZeroRadiusMm = 0.00005 * kMmPerInch;
// Allowed |r_end - r_start| where the relative error is above kArcRadiusRelTolerance
// (LinuxCNC CENTER_ARC_RADIUS_TOLERANCE_MM = 0.02·√2 mm, _INCH = 0.002·√2 in, by program units).
inline constexpr double kArcRadiusAbsToleranceMm = 0.02 * 1.4142135623730951;
inline constexpr double kArcRadiusAbsToleranceInchMm = 0.002 * 1.4142135623730951 * kMmPerInch;
inline constexpr double kArcRadiusRelTolerance = 0.001;  // LinuxCNC SPIRAL_RELATIVE_TOLERANCE
inline constexpr double kArcTiny = 1e-12;                // LinuxCNC TINY, for R-format arcs
// How much shorter than half the chord an R-format radius may be (LinuxCNC RADIUS_TOLERANCE_INCH =
// 0.00005 in, RADIUS_TOLERANCE_MM the same in mm, passed to arc_data_r): it then makes a half circle.
inline constexpr double kArcRadiusToleranceMm = 0.00005 * kMmPerInch;

// Largest accepted |r_end - r_start| for radii up to `r_max_mm`. LinuxCNC refuses an arc when the
// difference is above 100 × abs, or above both abs and rel × r_max; so the allowance is
// min(100·abs, max(abs, rel·r_max)): 0.028 mm for small mm arcs, 0.1 % of the radius for large ones.
double arc_radius_allowance_mm(double r_max_mm, Units units);

struct ArcRequest {
  core::Vec start, end;             // mm, machine coordinates
  double center0 = 0, center1 = 0;  // centre in the plane (axis0, axis1), mm, machine coordinates
  PlaneAxes plane{0, 1, 2};
  bool clockwise = false;           // G2; G3 is counter-clockwise
  int turns = 1;                    // P word: 1 = up to one revolution, each more adds a full circle
  Units units = Units::Mm;          // the program's units select LinuxCNC's absolute tolerance
  double feed_mm_s = 0;
};

// Builds the IR arc or says why the arc is impossible (zero radius, end not on the circle).
std::optional<std::string> make_arc(const ArcRequest& rq, Arc& out);

// R format (LinuxCNC arc_data_r): the centre of the arc of radius |r| from start to end in the
// plane; r < 0 asks for the arc of more than half a circle. No full circles. A radius up to
// kArcRadiusToleranceMm short of half the chord makes a half circle.
std::optional<std::string> centre_from_radius(const core::Vec& start, const core::Vec& end, PlaneAxes plane, double r_mm,
                                              bool clockwise, double& c0, double& c1);

// Length of the path of an IR arc starting at `start` (helix included), for inverse-time feed.
double arc_length_mm(const core::Vec& start, const Arc& a);

}  // namespace softmc::program::iso
