// Bézier segments: polynomial and rational, and LinuxCNC's G5 (cubic) and G5.1 (quadratic) splines.
//
//   G5   X Y I J P Q: P0 = start, P1 = start + (I, J), P2 = end + (P, Q), P3 = end
//   G5.1 X Y I J:     P0 = start, P1 = start + (I, J), P2 = end
// (LinuxCNC g-code reference; a G5 without I J continues with I J = -(previous P Q): that is the
// interpreter's bookkeeping, not geometry's.) Axes other than the plane's move linearly in u
// (LinuxCNC forbids them; here a start ≠ end in such an axis is simply carried along).
#pragma once

#include <array>
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

// The curvature-continuous blend between any two curves (the planner's at corners and curvature
// steps involving arcs): a quintic Bézier from p0 to p1 that leaves p0 along unit tangent t0 with
// curvature vector k0 and joins p1 along t1 with curvature k1 (position, tangent and curvature
// continuous at both ends: no step of any axis's acceleration). x0 and x1 are its control legs,
// the distances from p0 and p1 to the corner its tangent lines make (make_corner_blend's d), and
// (α, β) its shape as there:
//   P1 = p0 + (1−α)·x0·t0, P2 = p0 + (1−β)·x0·t0 + 1.25·(1−α)²·x0²·k0⊥  (k⊥: the part normal to t)
// and the mirror image at p1. With k0 = k1 = 0 and x0 = x1 = d it is make_corner_blend.
// rt-safe.
SegmentResult make_g2_blend(const Vec& p0, const Vec& t0, const Vec& k0, double x0, const Vec& p1, const Vec& t1,
                            const Vec& k1, double x1, double alpha, double beta);
// Its control points alone (evaluated by bezier_point before the curve is built).
std::array<Vec, 6> g2_blend_points(const Vec& p0, const Vec& t0, const Vec& k0, double x0, const Vec& p1,
                                   const Vec& t1, const Vec& k1, double x1, double alpha, double beta);
// Point of the polynomial Bézier with these control points at u ∈ [0, 1] (de Casteljau). rt-safe.
Vec bezier_point(std::span<const Vec> ctrl, double u);
// The same curve in the power basis, for evaluating it at many u (Horner: n multiply-adds per
// axis instead of de Casteljau's n(n+1)/2 interpolations). rt-safe.
struct BezierPower {
  std::array<Vec, kMaxBezierDegree + 1> a{};  // C(u) = Σ a_j u^j
  std::size_t n = 0;                          // degree
  explicit BezierPower(std::span<const Vec> ctrl);
  Vec at(double u) const {
    Vec p = a[n];
    for (std::size_t j = n; j-- > 0;) p = p * u + a[j];
    return p;
  }
};

// Whether splitting `whole` into `left` and `right` pays: the planner gives each piece one speed
// cap, from its largest curvature κ and jerk term |dκ/ds|, so a long piece whose bend is all at one
// end would crawl along its whole length at the cap of that end. It pays when one half has under a
// quarter of the whole's |dκ/ds| or under 0.4 of its κ (a cap at least 1.6 times higher, whatever
// the machine).
bool split_pays(const Segment& whole, const Segment& left, const Segment& right);

// Configuration time: appends the rational Bézier as one segment, or as consecutive pieces (de
// Casteljau, recursively): split at a cusp; halved while a piece's length table is not accurate to
// kTableTolerance (near-cusps); halved while that pays (split_pays), down to pieces of 0.25 mm, at
// most four times. Splines and NURBS build their segments with it.
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
