// Newton interpolating polynomial by divided differences.
#include "motion/geometry/newton_polynomial.hpp"

#include <cmath>
#include <memory>
#include <vector>

namespace softmc::motion {

namespace {

constexpr int kMaxSplitDepth = 10;

// One segment over [xa, xb] of the polynomial, halved in x while its length table is not accurate
// enough (steep graphs make |C'| = |dx|·√(1 + p'²) nearly kinked where p' changes sign).
void append_piece(const PolyCurve& proto, double xa, double xb, int depth, std::vector<Segment>& out) {
  Segment s;
  s.kind = SegmentKind::Poly;
  s.poly = proto;
  s.poly.newton.x_begin = xa;
  s.poly.newton.x_end = xb;
  const double err = s.poly.finalize();
  if (err > kTableTolerance * s.poly.length() && depth < kMaxSplitDepth) {
    const double xm = 0.5 * (xa + xb);
    append_piece(proto, xa, xm, depth + 1, out);
    append_piece(proto, xm, xb, depth + 1, out);
    return;
  }
  s.start = s.poly.at(0);
  s.end = s.poly.at(1);
  s.length = s.poly.length();
  out.push_back(s);
}

}  // namespace

CurveResult newton_polynomial(std::span<const Node2> nodes, const Vec& base, std::uint8_t x_axis,
                              std::uint8_t y_axis) {
  if (nodes.size() < 2) return {CurveError::TooFewPoints, {}};
  if (nodes.size() > kMaxNewtonDegree + 1) return {CurveError::TooManyPoints, {}};
  if (x_axis == y_axis || x_axis >= core::kMaxAxes || y_axis >= core::kMaxAxes) return {CurveError::BadValue, {}};
  for (const auto& n : nodes)
    if (!std::isfinite(n.x) || !std::isfinite(n.y)) return {CurveError::BadValue, {}};
  const bool up = nodes[1].x > nodes[0].x;
  for (std::size_t i = 1; i < nodes.size(); ++i) {
    if (nodes[i].x == nodes[i - 1].x) return {CurveError::RepeatedPoint, {}};
    if ((nodes[i].x > nodes[i - 1].x) != up) return {CurveError::NotMonotonic, {}};
  }
  PolyCurve c;
  c.basis = PolyBasis::NewtonGraph;
  std::construct_at(&c.newton);  // switch the union's active member
  const std::size_t n = nodes.size() - 1;
  c.degree = static_cast<std::uint8_t>(n);
  auto& nd = c.newton;
  for (std::size_t i = 0; i <= n; ++i) {
    nd.node_x[i] = nodes[i].x;
    nd.coef[i] = nodes[i].y;
  }
  // Divided differences in place: after pass j, coef[i] = f[x_{i-j} .. x_i] for i >= j.
  for (std::size_t j = 1; j <= n; ++j)
    for (std::size_t i = n; i >= j; --i) nd.coef[i] = (nd.coef[i] - nd.coef[i - 1]) / (nd.node_x[i] - nd.node_x[i - j]);
  nd.base = base;
  nd.x_axis = x_axis;
  nd.y_axis = y_axis;
  CurveResult r;
  append_piece(c, nodes.front().x, nodes.back().x, 0, r.segments);
  return r;
}

// rt-safe
double newton_value(const PolyCurve& curve, double x) {
  const auto& nd = curve.newton;
  double p = nd.coef[curve.degree];
  for (std::size_t k = curve.degree; k-- > 0;) p = p * (x - nd.node_x[k]) + nd.coef[k];
  return p;
}

}  // namespace softmc::motion
