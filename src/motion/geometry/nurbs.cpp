// NURBS → rational Bézier segments by knot insertion.
#include "motion/geometry/nurbs.hpp"

#include <algorithm>
#include <cmath>

#include "motion/geometry/bezier.hpp"

namespace softmc::motion {

namespace {

struct Homog {
  Vec p;  // w·P
  double w = 1;
};

// Boehm: insert t once into knots `u` (degree p), updating the homogeneous control points.
void insert_knot(std::vector<double>& u, std::vector<Homog>& c, std::size_t p, double t) {
  // k: the last knot index with u[k] <= t, inside the domain.
  std::size_t k = static_cast<std::size_t>(std::upper_bound(u.begin(), u.end(), t) - u.begin()) - 1;
  k = std::min(k, u.size() - p - 2);
  std::vector<Homog> q(c.size() + 1);
  for (std::size_t i = 0; i < q.size(); ++i) {
    if (i + p <= k) {
      q[i] = c[i];
    } else if (i >= k + 1) {
      q[i] = c[i - 1];
    } else {
      const double a = (t - u[i]) / (u[i + p] - u[i]);
      q[i].p = c[i - 1].p * (1 - a) + c[i].p * a;
      q[i].w = c[i - 1].w * (1 - a) + c[i].w * a;
    }
  }
  u.insert(u.begin() + static_cast<std::ptrdiff_t>(k) + 1, t);
  c = std::move(q);
}

}  // namespace

CurveResult nurbs(std::span<const Vec> ctrl, std::span<const double> weights, int degree, std::span<const double> knots) {
  if (degree < 1 || degree > static_cast<int>(kMaxBezierDegree)) return {CurveError::BadDegree, {}};
  const auto p = static_cast<std::size_t>(degree);
  if (ctrl.size() < p + 1) return {CurveError::TooFewPoints, {}};
  if (weights.size() != ctrl.size()) return {CurveError::BadWeight, {}};
  for (double w : weights)
    if (!(std::isfinite(w) && w > 0)) return {CurveError::BadWeight, {}};
  for (const auto& v : ctrl)
    for (std::size_t a = 0; a < core::kMaxAxes; ++a)
      if (!std::isfinite(v[a])) return {CurveError::BadValue, {}};
  // Clamped, non-decreasing, a non-empty domain, interior multiplicity <= p (no breaks).
  if (knots.size() != ctrl.size() + p + 1) return {CurveError::BadKnots, {}};
  for (std::size_t i = 1; i < knots.size(); ++i)
    if (!(knots[i] >= knots[i - 1]) || !std::isfinite(knots[i])) return {CurveError::BadKnots, {}};
  const std::size_t last = knots.size() - 1;
  for (std::size_t i = 1; i <= p; ++i)
    if (knots[i] != knots[0] || knots[last - i] != knots[last]) return {CurveError::BadKnots, {}};
  if (!(knots[p] < knots[last - p])) return {CurveError::BadKnots, {}};

  std::vector<double> u(knots.begin(), knots.end());
  std::vector<Homog> c(ctrl.size());
  for (std::size_t i = 0; i < ctrl.size(); ++i) c[i] = {ctrl[i] * weights[i], weights[i]};
  // Distinct interior knots, each raised to multiplicity p.
  std::vector<double> interior;
  for (std::size_t i = p + 1; i < last - p; ++i) {
    if (!interior.empty() && interior.back() == knots[i]) continue;
    interior.push_back(knots[i]);
  }
  for (double t : interior) {
    const auto mult = static_cast<std::size_t>(std::count(u.begin(), u.end(), t));
    if (mult > p) return {CurveError::BadKnots, {}};
    for (std::size_t m = mult; m < p; ++m) insert_knot(u, c, p, t);
  }
  CurveResult r;
  const std::size_t pieces = interior.size() + 1;
  r.segments.reserve(pieces);
  std::array<Vec, kMaxBezierDegree + 1> pts;
  std::array<double, kMaxBezierDegree + 1> ws;
  for (std::size_t j = 0; j < pieces; ++j) {
    for (std::size_t i = 0; i <= p; ++i) {
      const Homog& h = c[j * p + i];
      pts[i] = h.p * (1.0 / h.w);
      ws[i] = h.w;
    }
    // The first and last control points are interpolated: keep them bit-exact.
    if (j == 0) pts[0] = ctrl.front();
    if (j + 1 == pieces) pts[p] = ctrl.back();
    const CurveError e = append_rational_bezier(r.segments, {pts.data(), p + 1}, {ws.data(), p + 1});
    if (e != CurveError::Ok) return {e, {}};
  }
  return r;
}

std::vector<double> g5_2_knots(std::size_t n_ctrl, int order) {
  std::vector<double> u;
  if (order < 1 || n_ctrl < static_cast<std::size_t>(order)) return u;
  const auto k = static_cast<std::size_t>(order);
  const std::size_t n = n_ctrl - 1;
  for (std::size_t i = 0; i <= n + k; ++i) {
    if (i < k)
      u.push_back(0);
    else if (i <= n)
      u.push_back(static_cast<double>(i - k + 1));
    else
      u.push_back(static_cast<double>(n - k + 2));
  }
  return u;
}

CurveResult nurbs_g5_2(std::span<const Vec> ctrl, std::span<const double> weights, int order) {
  if (order < 2 || order > static_cast<int>(kMaxBezierDegree) + 1) return {CurveError::BadDegree, {}};
  if (ctrl.size() < static_cast<std::size_t>(order)) return {CurveError::TooFewPoints, {}};
  const auto u = g5_2_knots(ctrl.size(), order);
  return nurbs(ctrl, weights, order - 1, u);
}

}  // namespace softmc::motion
