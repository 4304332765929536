// Bézier segments: polynomial and rational, and LinuxCNC's G5 (cubic) and G5.1 (quadratic) splines.
//
//   G5   X Y I J P Q: P0 = start, P1 = start + (I, J), P2 = end + (P, Q), P3 = end
//   G5.1 X Y I J:     P0 = start, P1 = start + (I, J), P2 = end
// (LinuxCNC g-code reference; a G5 without I J continues with I J = -(previous P Q): that is the
// interpreter's bookkeeping, not geometry's.) Axes other than the plane's move linearly in u
// (LinuxCNC forbids them; here a start ≠ end in such an axis is simply carried along).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "motion/geometry/curve_result.hpp"
#include "motion/geometry/segment.hpp"

namespace softmc::motion {

// Polynomial Bézier of degree ctrl.size() - 1 (1 … kMaxBezierDegree).
SegmentResult make_bezier(std::span<const Vec> ctrl);
Segment make_cubic_bezier(const Vec& p0, const Vec& p1, const Vec& p2, const Vec& p3);
// Rational Bézier: C(u) = Σ B_i w_i P_i / Σ B_i w_i, every weight finite and > 0.
SegmentResult make_rational_bezier(std::span<const Vec> ctrl, std::span<const double> weights);

// The curvature-continuous corner blend (the planner's in jerk mode): a quintic Bézier from
// V − d·t1 to V + d·t2 (V the corner, t1, t2 unit directions in and out, 0 ≤ β < α < 1) whose
// first three control points lie on the incoming line and last three on the outgoing one, so it
// leaves and joins each line along it with zero curvature: no acceleration step at either end.
//   P0 = V − d·t1, P1 = V − α·d·t1, P2 = V − β·d·t1, P3 = V + β·d·t2, P4 = V + α·d·t2, P5 = V + d·t2
// rt-safe (bounded work, no allocation). Its midpoint lies corner_blend_dev(...) from V.
SegmentResult make_corner_blend(const Vec& corner, const Vec& t1, const Vec& t2, double d, double alpha, double beta);
// Distance of that blend's midpoint C(½) = V + (d/32)(1 + 5α + 10β)(t2 − t1) from V, the farthest
// any point of it lies from the two lines (symmetric and convex, it is nearest V there).
inline double corner_blend_dev(double chord, double d, double alpha, double beta) {
  return d / 32 * (1 + 5 * alpha + 10 * beta) * chord;  // chord = |t2 − t1|
}

// Configuration time: appends the rational Bézier as one segment, or as consecutive halves (de
// Casteljau at u = ½, recursively) while a piece's length table is not accurate to
// kTableTolerance (near-cusps). Splines and NURBS build their segments with it.
CurveError append_rational_bezier(std::vector<Segment>& out, std::span<const Vec> ctrl, std::span<const double> weights,
                                  int depth = 0);

// G5 in the plane (axis0, axis1): (i, j) offsets the first control point from start, (p, q) the
// second from end.
Segment g5_cubic_spline(const Vec& start, const Vec& end, double i, double j, double p, double q,
                        std::uint8_t axis0 = 0, std::uint8_t axis1 = 1);
// G5.1 in the plane (axis0, axis1): (i, j) offsets the single control point from start.
Segment g5_1_quadratic(const Vec& start, const Vec& end, double i, double j, std::uint8_t axis0 = 0,
                       std::uint8_t axis1 = 1);

}  // namespace softmc::motion
