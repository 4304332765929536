// Curvature-continuous smoothing of CAM polylines, for jerk-limited paths (docs/planner.md).
//
//   P0 ──── P1 ──── P2 ──── P3 ──── P4        programmed: short lines, small turns
//   P0 ─S╮                       ╭E─ P4        smoothed: a cubic B-spline (centripetal knots) with control
//        ╰──── · ──── · ──── · ─╯              points P0 P0 P1 … P4 P4, one cubic piece per line, and two
//                                              line stubs P0→S, E→P4 along the first and last control
//                                              legs (the filtered points' first and last)
//
// Corners of arcs and lines step the curvature, and a curvature step at speed v steps every axis's
// acceleration by v²·Δκ in one cycle: under a jerk limit such a corner can only be crossed slowly
// (v²·Δκ ≤ j·dt). The B-spline is C² (curvature continuous) everywhere, starts and ends with zero
// curvature tangent to its first and last legs (so the stubs join it without a step), and lies
// within the convex hull of each four consecutive control points. The control points are the
// programmed points low-pass filtered (CAM rounding would otherwise become curvature noise, and
// the jerk of v³·dκ/ds); each piece is checked against the
// tolerance P (sampled distance to the programmed lines around it), and a run is split where a piece
// would leave it. Exact stops and sharp corners end a run and are planned as usual.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include "motion/geometry/segment.hpp"

namespace softmc::motion {

struct PolylineSmoothing {
  double tolerance_mm = 0.05;   // the smoothed curve stays within this of the programmed lines
  double max_turn_rad = 0.35;   // a larger turn between two lines ends a run (a corner to blend)
  double min_length_mm = 1e-6;  // shorter lines end a run
  double knot_exponent = 0.5;   // knot intervals |leg|^this: 0 uniform, ½ centripetal, 1 chord length
  int filter_passes = 8;        // low-pass passes over the points before the spline (fewer where P is left)
  double filter_cut = 0.85;     // a point near a piece leaving P keeps this share of its way above the next tier down
  double filter_taper = 0.25;   // a point's filter weight stays within this (in tiers) of its neighbours'
  std::size_t max_run_lines = 1000;  // a longer run is cut there (bounds the work and the splitting depth)
  // A piece is split in halves (exactly, the same curve) where one half bends much less than the
  // whole, so that the planner's per-piece speed cap does not hold along all of it: down to pieces
  // of split_min_length_mm, split_depth halvings at most; depth 0 = never.
  double split_min_length_mm = 0.25;
  int split_depth = 4;
  // Threads smoothing a polyline's stretches (up to sharp turns, max_run_lines) at once: 0 = one a
  // hardware thread. The pieces are the same whatever the count.
  std::size_t threads = 0;
};

// For the polyline pts[0..n] (n lines): `lines[i]` receives the segments that replace line i
// (pts[i] → pts[i + 1]), or stays empty where line i is kept as programmed. Configuration time
// (allocates). Consecutive segments join exactly (the end of one is the start of the next), but for
// an axis that moves less than 1e-9 mm within a Bézier piece, which the piece keeps flat at its
// start: gaps of up to about a nanometre there (the stop-27 review: 1.3e-9 mm at 2.5 % of random
// joints, as before; docs/planner.md "Not yet").
// `range_done(a, b)`, when given, is called as soon as the lines a … b − 1 have their segments (in
// rising order, each line in one range at most; lines no range covers stay empty): a caller may
// take them and free them then, so a long run's pieces (1.3 kB each) are not all held at once.
void smooth_polyline(std::span<const Vec> pts, const PolylineSmoothing& cfg, std::vector<std::vector<Segment>>& lines,
                     const std::function<void(std::size_t, std::size_t)>& range_done = {});

// Tiny collinear lines of a polyline, for smoothing: `kept` receives the indices of the points that
// stay (always the first and the last), in order. A point is dropped where it lies within eps_mm of
// the chord between the kept points around it, the points from one kept point to the next advance
// along that chord (no reversal is dropped), and that chord is at most max_leg_mm long; at most
// max_dropped in a row (bounds the work: O(n · max_dropped)). 1 µm CAM lines along a line become
// legs of max_leg_mm for the spline, instead of thousands of pieces the planner cannot merge; lines
// longer than max_leg_mm are never touched (a long leg next to short ones would bend the spline
// where they meet). Configuration time (allocates).
void thin_polyline(std::span<const Vec> pts, double eps_mm, double max_leg_mm, std::size_t max_dropped,
                   std::vector<std::size_t>& kept);

}  // namespace softmc::motion
