// The cutting table's curve through points (cutting_table.md T-2): the Newton interpolating
// polynomial y = p(x) by divided differences, for nodes at any spacing, exact at every node.
//
//   p(x) = f[x0] + f[x0,x1](x-x0) + f[x0,x1,x2](x-x0)(x-x1) + …
//   f[xi..xj] = (f[xi+1..xj] - f[xi..xj-1]) / (xj - xi)
// The thesis used forward differences, which assume equal spacing: its own example (x = 10, 40,
// 60, 90) missed the last node by about 6. Divided differences need no spacing at all.
#pragma once

#include <cstdint>
#include <span>

#include "motion/geometry/curve_result.hpp"

namespace softmc::motion {

struct Node2 {
  double x = 0, y = 0;
};

// The graph of p from the first node's x to the last node's x, in the plane (x_axis, y_axis); the
// other axes stay at `base`. 2 … kMaxNewtonDegree + 1 nodes, x strictly monotonic. Usually one
// segment; a steep polynomial is cut into consecutive x ranges so each keeps its length table
// accurate (every piece evaluates the same polynomial, so the joints are exact).
CurveResult newton_polynomial(std::span<const Node2> nodes, const Vec& base = {}, std::uint8_t x_axis = 0,
                                std::uint8_t y_axis = 1);

// p(x) of a NewtonGraph curve (rt-safe).
double newton_value(const PolyCurve& curve, double x);

}  // namespace softmc::motion
