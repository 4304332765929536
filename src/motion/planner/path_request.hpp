// What the channel asks the planner for: one programmed move (docs/planner.md).
#pragma once

#include <cstdint>

#include "motion/geometry/segment.hpp"
#include "motion/profile/profile.hpp"

namespace softmc::motion {

struct PathRequest {
  Segment geom;
  double feed_mm_s = 0;  // requested path speed; ignored for rapids
  bool rapid = false;
  std::uint32_t tag = 0;        // the instruction index it came from, carried to the setpoints
  std::uint32_t tag_last = 0;   // the last instruction it stands for, when it replaces several
                                // (a smoothed leg over thinned lines); ≤ tag: tag alone
  double tolerance_mm = -1;     // blend tolerance P at the corner this move starts with:
                                // < 0 = the configured default (G64 without P), 0 = exact stop (G61)
  // Speed profile of this move: Scurve (default) keeps the axes' jerk limits; Trapezoid ignores them
  // (acceleration may jump); Sine2 is executed as Scurve on paths (its smooth jerk is a 1-D feature).
  ProfileKind profile = ProfileKind::Scurve;
  // A line that may merge with its neighbouring lines (naive-CAM merge, docs/planner.md). false: a
  // line that must keep its direction, such as a smoothed run's end stub, tangent to its spline
  // (merged, it would meet the spline at a kink, an exact stop under a jerk limit).
  bool mergeable = true;
  // How far this move may already lie from the programmed path (a smoothed run's pieces: up to the
  // smoothing's share of P). A blend at its ends keeps to the rest of P, as one at a merged line
  // keeps to P − Q.
  double offset_mm = 0;
};

}  // namespace softmc::motion
