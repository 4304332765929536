// NURBS curves (LinuxCNC G5.2/G5.3 blocks) as rational Bézier segments, by knot insertion.
//
//   C(t) = Σ N_i,p(t) w_i P_i / Σ N_i,p(t) w_i on a clamped knot vector
//   Insert every interior knot until its multiplicity is p (Boehm, in homogeneous coordinates
//   w·P, w): the control polygon then falls apart into rational Bézier pieces of degree p that
//   share their end points, one segment per non-empty knot span (halved further only near cusps).
// G5.2 (LinuxCNC): the current position is the first control point, P is the weight (default 1),
// L the order k = degree + 1 (default 3), and the knot vector is uniform and clamped:
//   k zeros, 1, 2, …, n-k+1, then k times n-k+2   (n + 1 control points).
#pragma once

#include <span>
#include <vector>

#include "motion/geometry/curve_result.hpp"

namespace softmc::motion {

// General clamped NURBS: knots.size() == ctrl.size() + degree + 1; degree 1 … kMaxBezierDegree.
CurveResult nurbs(std::span<const Vec> ctrl, std::span<const double> weights, int degree, std::span<const double> knots);

// LinuxCNC's G5.2 knot vector for n_ctrl points of the given order.
std::vector<double> g5_2_knots(std::size_t n_ctrl, int order);

// A G5.2 … G5.3 block: ctrl[0] is the position before the block.
CurveResult nurbs_g5_2(std::span<const Vec> ctrl, std::span<const double> weights, int order = 3);

}  // namespace softmc::motion
