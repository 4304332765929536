// A look-ahead block: one piece of path (program line/arc, or a corner blend) with its speed limits.
//
//   programmed:  A ───────────●─────────── B        ● = corner, P = blend tolerance
//   planned:     A ──────╮  (P)                     the corner is cut by a circular arc tangent to
//                        ╰───────────── B           both lines; A and B are shortened by d each
//
// The interpolator samples a Block through point/tangent/curvature at arc length s, whatever its kind.
#pragma once

#include <cstdint>

#include "core/axes.hpp"
#include "motion/geometry/segment.hpp"
#include "motion/planner/tangent_law.hpp"

namespace softmc::motion {

// A circular arc in any plane of axis space (a corner blend between two lines in 3-D need not lie
// in a coordinate plane): p(φ) = centre + R·(cos φ·u + sin φ·w), φ ∈ [0, sweep], u ⟂ w unit vectors.
struct BlendArc {
  Vec centre, u, w;
  Vec start;  // p(0)
  double radius = 0, sweep = 0;

  // rt-safe
  Vec point(double s) const;
  Vec tangent(double s) const;
  Vec curvature(double s) const;
  CurveFrame frame(double s) const;  // all three with one sincos
};

// Builds the arc tangent to unit direction t1 at `p1`, turning by `sweep` (radians) towards unit
// direction t2, with radius r. t1 and t2 must not be (anti)parallel.
BlendArc make_blend_arc(const Vec& p1, const Vec& t1, const Vec& t2, double r, double sweep);

// The speed limits come first, together: the jerk guard walks them over every block within the
// braking distance each cycle, and packed into the block's first cache line (alignas) a walk touches
// one line per block instead of three spread over its 1.9 kB.
struct alignas(64) Block {
  double length = 0;          // mm
  double a_mm_s2 = 0;         // path acceleration every axis allows along the whole block at any speed
                              // up to v_split_mm_s (the jerk follower's limit)
  double j_mm_s3 = 0;         // path jerk every axis allows (infinite: no jerk limit, trapezoid)
  double v_cap_mm_s = 0;      // path speed every axis allows (hard: never exceeded, whatever the override)
  double v_split_mm_s = 0;    // the speed up to which a_mm_s2 holds (= v_cap_mm_s on jerk blocks)
  double feed_mm_s = 0;       // programmed feed (infinite for rapids): the override scales it
  double v2_junction = 0;     // (mm/s)²: entry speed the junction with the previous block allows
  bool is_blend = false;
  bool rapid = false;
  std::uint32_t tag = 0;  // instruction index carried to the setpoints
  double v2_kink = 0;         // (mm/s)²: speed a non-tangent, unblended corner at its start allows
  double v2_entry_max = 0;    // (mm/s)²: backward pass — entry speed from which every later limit,
                              // and the stop at the end of what is planned, can still be met
  std::uint32_t tag_last = 0;  // a merged line: the last instruction it stands for (else = tag)
  double merge_q_mm = 0;      // a merged line: largest distance of the programmed corners it replaces
  // A line after a line whose corner was left unblended within a tolerance: how far from the
  // corner the path may pass (P less what merges took) where the corner is a stop, so that this
  // line may begin while the one before still brakes (jerk mode: Interpolator, "corner overlap").
  // 0: none (G61, curves, blends).
  double overlap_mm = 0;
  // A Poly block's limits as segment_limits derived them (before junction shares lowered them), for
  // the speed it was asked for (relimit_v, ∞: none) and the jerk bound it took (relimit_norm): a
  // stop derives them again for the speed the path has then (Planner::limit_for_stop). 0: none kept.
  double base_a = 0, base_j = 0, relimit_v = 0;
  bool relimit_norm = true;
  double stop_a0 = 0, stop_j0 = 0;  // its a_mm_s2 and j_mm_s3 before the first limit_for_stop
  double stop_v0 = 0;               // its v_cap_mm_s then (a hold's end restores the three)
  TangentLaw law;             // tangential acceleration allowed at each speed (backward pass and the
                              // trapezoid interpolator); on jerk blocks the constant a_mm_s2
  Segment seg;            // the geometry when !is_blend (line or arc/helix)
  BlendArc blend;         // the geometry when is_blend

  // rt-safe geometry at arc length s ∈ [0, length].
  Vec start() const { return is_blend ? blend.point(0) : seg.start; }
  Vec end() const { return is_blend ? blend.point(length) : seg.end; }
  Vec point(double s) const { return is_blend ? blend.point(s) : seg.point(s); }
  Vec tangent(double s) const { return is_blend ? blend.tangent(s) : seg.tangent(s); }
  Vec curvature(double s) const { return is_blend ? blend.curvature(s) : seg.curvature(s); }
  // All three at s: a Poly curve maps s to its parameter once, a blend takes one sincos.
  CurveFrame frame(double s) const {
    return is_blend ? blend.frame(s) : seg.frame(s);
  }
};

}  // namespace softmc::motion
