// Bézier, rational Bézier, G5 and G5.1 constructors.
#include "motion/geometry/bezier.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "motion/geometry/golden.hpp"

namespace softmc::motion {

const char* to_string(CurveError e) {
  switch (e) {
    case CurveError::Ok: return "ok";
    case CurveError::TooFewPoints: return "too few points for the curve";
    case CurveError::TooManyPoints: return "too many points for one segment";
    case CurveError::RepeatedPoint: return "two consecutive points coincide";
    case CurveError::NotMonotonic: return "nodes must be strictly monotonic in the independent axis";
    case CurveError::BadDegree: return "curve degree out of range";
    case CurveError::BadWeight: return "weights must be finite and positive";
    case CurveError::BadKnots: return "bad knot vector";
    case CurveError::BadValue: return "a coordinate is not finite";
  }
  return "?";
}

namespace {
bool finite(const Vec& v) {
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}
}  // namespace

namespace {
// Spread of an axis's control points below which it is taken as not moving (rounding; a thousandth
// of the micrometre the interpolation keeps to).
constexpr double kFlatAxis_mm = 1e-9;
// The segment and (estimate) the estimated error of its length table.
SegmentResult build(std::span<const Vec> ctrl, std::span<const double> weights, double& table_error,
                    bool estimate) {
  SegmentResult r;
  if (ctrl.size() < 2) return {CurveError::TooFewPoints, {}};
  if (ctrl.size() > kMaxBezierDegree + 1) return {CurveError::BadDegree, {}};
  if (weights.size() != ctrl.size()) return {CurveError::BadWeight, {}};
  for (std::size_t i = 0; i < ctrl.size(); ++i) {
    if (!(std::isfinite(weights[i]) && weights[i] > 0)) return {CurveError::BadWeight, {}};
    if (!finite(ctrl[i])) return {CurveError::BadValue, {}};
  }
  // An axis whose control points differ by rounding only (a piece split off a curve that keeps
  // that axis constant: de Casteljau in homogeneous coordinates, and the collapse at a cusp, leave
  // 1e-14 to 1e-10 mm) does not move: its points are made exactly equal. Counted as moving, near a
  // stationary point of the curve (|C'| → 0 at a cusp) that rounding turned the tangent and gave
  // curvatures of 1e26/mm, speed caps of 1e-16 mm/s, and a fuzzer's G5.2 doubling back along X
  // crept there for ever.
  std::array<Vec, kMaxBezierDegree + 1> p{};
  for (std::size_t i = 0; i < ctrl.size(); ++i) p[i] = ctrl[i];
  std::array<bool, core::kMaxAxes> flat{};
  bool all_flat = true;
  for (std::size_t a = 0; a < core::kMaxAxes; ++a) {
    flat[a] = true;
    for (std::size_t i = 1; flat[a] && i < ctrl.size(); ++i)
      flat[a] = std::abs(p[i][a] - p[0][a]) <= kFlatAxis_mm;
    all_flat = all_flat && flat[a];
  }
  // A piece within kFlatAxis_mm on every axis (the tip of a cusp, graded down to a nanometre) is
  // the straight piece between its own ends instead: collapsed onto its start, it left a gap of up
  // to kFlatAxis_mm to the next piece. (An axis flat beside moving ones is still collapsed: kept at
  // its end values, its nanometre of shape made tangents and curvatures of 10¹³/mm² next to a cusp,
  // and a review's G5.2 ran 286 s instead of 3.28.)
  const std::size_t n = ctrl.size() - 1;
  for (std::size_t a = 0; a < core::kMaxAxes; ++a) {
    if (!flat[a]) continue;
    if (all_flat)  // the ends kept, the inner points evenly between them
      for (std::size_t i = 1; i < n; ++i) p[i][a] = p[0][a] + (p[n][a] - p[0][a]) * (static_cast<double>(i) / static_cast<double>(n));
    else
      for (std::size_t i = 1; i <= n; ++i) p[i][a] = p[0][a];
  }
  Segment& s = r.segment;
  s.kind = SegmentKind::Poly;
  s.poly.basis = PolyBasis::Bezier;
  s.poly.degree = static_cast<std::uint8_t>(ctrl.size() - 1);
  for (std::size_t i = 0; i < ctrl.size(); ++i) {
    s.poly.bez.hctrl[i] = p[i] * weights[i];
    s.poly.bez.w[i] = weights[i];
  }
  table_error = s.poly.finalize(estimate);
  s.start = p[0];  // the end points are interpolated exactly
  s.end = p[ctrl.size() - 1];
  s.length = s.poly.length();
  return r;
}

constexpr int kMaxSplitDepth = 10;
}  // namespace

SegmentResult make_rational_bezier(std::span<const Vec> ctrl, std::span<const double> weights) {
  double err = 0;
  return build(ctrl, weights, err, false);  // not split: its table's error estimate is not needed
}

namespace {
// Where the curve's tangent reverses inside (0, 1) at a cusp (the control points double back along
// a line: C'(u) passes through 0): found as a turn of more than a right angle within 1/64 of u, the
// u at which it turns by bisection on the sign of C'(u)·C'(u₀), where |C'| is below 1e-3 of the
// length; −1 where there is none. Curvature is 0 on a line that doubles back (C' ∥ C''), so the planner's sampled limits
// cannot see such a cusp; split there, the two pieces meet as a reversal (Planner::kink_speed: a
// stop, or a crossing within one cycle's share of every axis's acceleration and jerk).
double cusp_param(const PolyCurve& c) {
  constexpr int kSamples = 64;
  Vec d0 = c.derivs(0).d1;
  for (int k = 1; k <= kSamples; ++k) {
    const double u1 = static_cast<double>(k) / kSamples;
    const Vec d1 = c.derivs(u1).d1;
    if (core::dot(d0, d1) < 0) {
      double lo = static_cast<double>(k - 1) / kSamples, hi = u1;
      for (int it = 0; it < 60 && hi - lo > 1e-15; ++it) {
        const double mid = 0.5 * (lo + hi);
        (core::dot(c.derivs(mid).d1, d0) >= 0 ? lo : hi) = mid;
      }
      const double u = 0.5 * (lo + hi);
      // A cusp only where the curve (nearly) stops there: a tight loop that keeps its speed has a
      // finite curvature, which the sampled limits see.
      if (!(core::norm(c.derivs(u).d1) <= 1e-3 * c.length())) return -1.0;
      return u > 1e-9 && u < 1 - 1e-9 ? u : -1.0;
    }
    if (core::norm(d1) > 0) d0 = d1;
  }
  return -1.0;
}

// How sharp c is at u (1/mm), as the planner's caps see it: the larger of κ (the centripetal
// acceleration v²κ) and √|dκ⃗/ds| (the speed term of the path jerk, v³·|dκ⃗/ds|), the latter as the
// secant of the curvature vector over 1/8192 of u towards the inside of [0, 1].
double sharpness_at(const PolyCurve& c, double u) {
  constexpr double kH = 1.0 / 8192;
  const double u0 = std::min(u, 1 - kH), u1 = u0 + kH;
  const CurveDerivs d0 = c.derivs(u0), d1 = c.derivs(u1);
  const Vec k0 = curvature_vector(d0), k1 = curvature_vector(d1);
  const double ds = c.arc(u0, u1);
  const double dk = ds > 1e-300 ? core::norm(k1 - k0) / ds : 0.0;
  return std::max(core::norm(u == u0 ? k0 : k1), std::sqrt(dk));
}

// Where to split a piece whose sharpness is all at one end (next to a near cusp, where C' nearly
// stops: κ there 10⁶/mm on a 0.1 mm piece of a fuzzer's G5): the planner gives a piece one cap, from
// its largest κ and |dκ/ds|, so the whole piece crawled at that end's cap (125 s for 3.4 mm at
// F1200). Split at the u where the sharpness (sharpness_at) has fallen to a quarter of the end's,
// the end piece short and the rest graded again: each piece's cap then rises away from the sharp
// end, and the path takes each at about its own curvature. Only where the end is far sharper than
// the piece's middle (16×) and than half its length (a radius under twice the length).
//
// Else, where the sharpness peaks inside the piece, far above both ends (16×) and above half its
// length (a near cusp that cusp_param leaves whole: |C'| above a thousandth of the length): at the
// sharpest of 63 samples, refined by golden sections between its neighbours. Split there, the
// sharp point is an end of both halves, which are then graded towards it: a fuzzed G5 going out
// 9.5 mm and back through a turn of 0.05 mm ran all its 19.3 mm at that turn's cap (0.87 mm/s,
// 21.6 s at F300). −1 where neither applies.
double grade_param(const PolyCurve& c, double length) {
  const double k0 = sharpness_at(c, 0), k1 = sharpness_at(c, 1), km = sharpness_at(c, 0.5);
  const double ke = std::max(k0, k1);
  if (ke > 16 * km && ke * length > 2) {
    double lo = k0 >= k1 ? 0.0 : 1.0, hi = 0.5;  // sharpness(lo) ≥ ke/4 > sharpness(hi)
    for (int it = 0; it < 60 && std::abs(hi - lo) > 1e-15; ++it) {
      const double mid = 0.5 * (lo + hi);
      (sharpness_at(c, mid) >= 0.25 * ke ? lo : hi) = mid;
    }
    const double u = 0.5 * (lo + hi);
    if (u > 1e-12 && u < 1 - 1e-12) return u;
  }
  constexpr int kSamples = 64;
  double best = 0, u_best = -1;
  for (int k = 1; k < kSamples; ++k) {
    const double u = static_cast<double>(k) / kSamples, g = sharpness_at(c, u);
    if (g > best) best = g, u_best = u;
  }
  if (!(best > 16 * ke && best * length > 2)) return -1.0;
  const double u = golden_max([&](double v) { return sharpness_at(c, v); }, u_best - 1.0 / kSamples,
                              u_best + 1.0 / kSamples, 40).u;
  return u > 1e-9 && u < 1 - 1e-9 ? u : -1.0;
}

// de Casteljau at t in homogeneous coordinates: the left piece takes the first point of every
// level, the right piece the last; both share the point at t exactly.
void split_bezier(std::span<const Vec> ctrl, std::span<const double> weights, double t,
                  std::array<Vec, kMaxBezierDegree + 1>& lp, std::array<double, kMaxBezierDegree + 1>& lw,
                  std::array<Vec, kMaxBezierDegree + 1>& rp, std::array<double, kMaxBezierDegree + 1>& rw) {
  const std::size_t n = ctrl.size() - 1;
  std::array<Vec, kMaxBezierDegree + 1> hp;
  std::array<double, kMaxBezierDegree + 1> w = {};
  for (std::size_t i = 0; i <= n; ++i) {
    hp[i] = ctrl[i] * weights[i];
    w[i] = weights[i];
  }
  for (std::size_t lvl = 0; lvl <= n; ++lvl) {
    lp[lvl] = hp[0];
    lw[lvl] = w[0];
    rp[n - lvl] = hp[n - lvl];
    rw[n - lvl] = w[n - lvl];
    for (std::size_t i = 0; i + lvl < n; ++i) {
      hp[i] = hp[i] * (1 - t) + hp[i + 1] * t;
      w[i] = (1 - t) * w[i] + t * w[i + 1];
    }
  }
  for (std::size_t i = 0; i <= n; ++i) {
    lp[i] = lp[i] * (1.0 / lw[i]);
    rp[i] = rp[i] * (1.0 / rw[i]);
  }
  lp[0] = ctrl.front();
  rp[n] = ctrl.back();
  rp[0] = lp[n];
}
}  // namespace

bool split_pays(const Segment& whole, const Segment& left, const Segment& right) {
  const auto k3 = [](const Segment& g) { return g.poly.jerk_speed_term(); };
  const double k3_low = std::min(k3(left), k3(right)), k_low = std::min(left.poly.max_curvature, right.poly.max_curvature);
  return k3_low < 0.25 * k3(whole) || k_low < 0.4 * whole.poly.max_curvature;
}

namespace {
CurveError append_piece(std::vector<Segment>& out, std::span<const Vec> ctrl, std::span<const double> weights,
                        int depth, int grades) {
  constexpr int kPaySplitDepth = 4;          // halvings for a lower cap at most (split_pays) ...
  constexpr double kPaySplitMin_mm = 0.25;   // ... down to pieces twice this long
  constexpr int kMaxGrades = 40;             // splits of a sharp end at most (grade_param), counted
                                             // apart from `depth` (the cusp and table splits') ...
  constexpr double kGradeMin_mm = 1e-9;      // ... of pieces longer than this (at a stationary end
                                             // |dκ/ds| grows like 1/√s: 1e-6 left a 38 nm piece
                                             // there crawling for 15 s)
  // A length table is accurate enough within kTableTolerance of the length or within this (a
  // thousandth of a nanometre, near the rounding of coordinates of a few hundred mm): the tip of a
  // near cusp, whose speed nearly stops, was halved down to pieces of 1e-14 mm for a relative
  // accuracy nothing can measure (a review's G5.2: 747 pieces, 662 under a nanometre).
  constexpr double kTableFloor_mm = 1e-12;
  double err = 0;
  SegmentResult r = build(ctrl, weights, err, true);
  if (!r.ok()) return r.error;
  // Split at a cusp (cusp_param) first; else halve while the length table is not accurate enough,
  // or while that lowers the cap of one half enough (split_pays).
  const double cusp = depth < kMaxSplitDepth ? cusp_param(r.segment.poly) : -1.0;
  const std::size_t n = ctrl.size() - 1;
  std::array<Vec, kMaxBezierDegree + 1> lp, rp;
  std::array<double, kMaxBezierDegree + 1> lw, rw;
  int next_depth = depth + 1, next_grades = grades;
  if (cusp < 0 && (!(err > std::max(kTableTolerance * r.segment.length, kTableFloor_mm)) || depth >= kMaxSplitDepth)) {
    bool halve = depth < kPaySplitDepth && r.segment.length > 2 * kPaySplitMin_mm;
    if (halve) {
      split_bezier(ctrl, weights, 0.5, lp, lw, rp, rw);
      double e = 0;
      const SegmentResult left = build({lp.data(), n + 1}, {lw.data(), n + 1}, e, false);
      const SegmentResult right = build({rp.data(), n + 1}, {rw.data(), n + 1}, e, false);
      halve = left.ok() && right.ok() && split_pays(r.segment, left.segment, right.segment);
    }
    if (!halve) {
      const double g = grades < kMaxGrades && r.segment.length > kGradeMin_mm
                           ? grade_param(r.segment.poly, r.segment.length) : -1.0;
      if (g < 0) {
        out.push_back(r.segment);
        return CurveError::Ok;
      }
      split_bezier(ctrl, weights, g, lp, lw, rp, rw);
      next_depth = depth;  // a grading split: counted apart from the cusp and table splits
      ++next_grades;
    }
  } else {
    split_bezier(ctrl, weights, cusp < 0 ? 0.5 : cusp, lp, lw, rp, rw);
  }
  if (cusp >= 0 && n >= 2) {
    // The pieces stop exactly at the cusp (C' = 0 there: their end legs collapsed): their tangents
    // there are then the limits of C'/|C'| (Segment::tangent), arriving one way and leaving the
    // other. Moving a control point moves no point of the curve farther than it moves (the
    // Bernstein weights are at most 1), so only legs within kCollapse_mm are collapsed: at a true
    // cusp they are the bisection's 1e-15 of u long; near one (|C'| a thousandth of the length, a
    // fuzzer's G5) they were 2e-4 mm, the pieces lay up to 3.5e-4 mm off the programmed curve and a
    // run's setpoints 1.6e-6 mm off it. Such a near cusp is split there all the same (two pieces
    // tangent to each other) and run at its curvature.
    constexpr double kCollapse_mm = 1e-9;
    if (core::norm(lp[n] - lp[n - 1]) <= kCollapse_mm && core::norm(rp[1] - rp[0]) <= kCollapse_mm) {
      lp[n - 1] = lp[n];
      rp[1] = rp[0];
    }
  }
  const CurveError e = append_piece(out, {lp.data(), n + 1}, {lw.data(), n + 1}, next_depth, next_grades);
  if (e != CurveError::Ok) return e;
  return append_piece(out, {rp.data(), n + 1}, {rw.data(), n + 1}, next_depth, next_grades);
}
}  // namespace

CurveError append_rational_bezier(std::vector<Segment>& out, std::span<const Vec> ctrl, std::span<const double> weights,
                                  int depth) {
  return append_piece(out, ctrl, weights, depth, 0);
}

SegmentResult make_bezier(std::span<const Vec> ctrl) {
  const std::array<double, kMaxBezierDegree + 1> ones{1, 1, 1, 1, 1, 1};
  return make_rational_bezier(ctrl, {ones.data(), std::min(ctrl.size(), ones.size())});
}

Segment make_cubic_bezier(const Vec& p0, const Vec& p1, const Vec& p2, const Vec& p3) {
  const std::array<Vec, 4> c{p0, p1, p2, p3};
  return make_bezier(c).segment;
}

SegmentResult make_corner_blend(const Vec& corner, const Vec& t1, const Vec& t2, double d, double alpha, double beta) {
  return make_g2_blend(corner - t1 * d, t1, Vec{}, d, corner + t2 * d, t2, Vec{}, d, alpha, beta);
}

std::array<Vec, 6> g2_blend_points(const Vec& p0, const Vec& t0, const Vec& k0, double x0, const Vec& p1,
                                   const Vec& t1, const Vec& k1, double x1, double alpha, double beta) {
  // C'(0) = 5(P1 − P0) = λ·t0 with λ = 5(1−α)·x0, and C''(0) = 20(P2 − 2P1 + P0) = λ²·k0 + μ·t0 for
  // any μ: the curvature vector at 0 is then k0 (its part normal to t0). The same at the end.
  const auto normal = [](const Vec& k, const Vec& t) { return k - t * core::dot(k, t); };
  const double c0 = 1.25 * (1 - alpha) * (1 - alpha) * x0 * x0, c1 = 1.25 * (1 - alpha) * (1 - alpha) * x1 * x1;
  return {p0,
          p0 + t0 * ((1 - alpha) * x0),
          p0 + t0 * ((1 - beta) * x0) + normal(k0, t0) * c0,
          p1 - t1 * ((1 - beta) * x1) + normal(k1, t1) * c1,
          p1 - t1 * ((1 - alpha) * x1),
          p1};
}

SegmentResult make_g2_blend(const Vec& p0, const Vec& t0, const Vec& k0, double x0, const Vec& p1, const Vec& t1,
                            const Vec& k1, double x1, double alpha, double beta) {
  const auto c = g2_blend_points(p0, t0, k0, x0, p1, t1, k1, x1, alpha, beta);
  return make_bezier(c);
}

// rt-safe
Vec bezier_point(std::span<const Vec> ctrl, double u) {
  std::array<Vec, kMaxBezierDegree + 1> q{};
  const std::size_t n = std::min(ctrl.size(), q.size());
  for (std::size_t i = 0; i < n; ++i) q[i] = ctrl[i];
  for (std::size_t lvl = 1; lvl < n; ++lvl)
    for (std::size_t i = 0; i + lvl < n; ++i) q[i] = q[i] + (q[i + 1] - q[i]) * u;
  return q[0];
}

BezierPower::BezierPower(std::span<const Vec> ctrl) {
  // a_j = C(n, j) · Σ_{i ≤ j} (−1)^(j−i) C(j, i) P_i: the j-th forward difference, scaled.
  n = std::min(ctrl.size(), a.size()) - 1;
  double cn = 1;  // C(n, j)
  for (std::size_t j = 0; j <= n; ++j) {
    Vec d{};
    double cj = 1;  // C(j, i)
    for (std::size_t i = 0; i <= j; ++i) {
      d = d + ctrl[i] * (((j - i) % 2 ? -1.0 : 1.0) * cj);
      cj = cj * static_cast<double>(j - i) / static_cast<double>(i + 1);
    }
    a[j] = d * cn;
    cn = cn * static_cast<double>(n - j) / static_cast<double>(j + 1);
  }
}

Segment g5_cubic_spline(const Vec& start, const Vec& end, double i, double j, double p, double q,
                        std::uint8_t axis0, std::uint8_t axis1) {
  // Off-plane axes: at 1/3 and 2/3 of the way, which makes them linear in u.
  Vec c1 = start + (end - start) * (1.0 / 3), c2 = start + (end - start) * (2.0 / 3);
  c1[axis0] = start[axis0] + i;
  c1[axis1] = start[axis1] + j;
  c2[axis0] = end[axis0] + p;
  c2[axis1] = end[axis1] + q;
  return make_cubic_bezier(start, c1, c2, end);
}

Segment g5_1_quadratic(const Vec& start, const Vec& end, double i, double j, std::uint8_t axis0,
                       std::uint8_t axis1) {
  Vec c = (start + end) * 0.5;
  c[axis0] = start[axis0] + i;
  c[axis1] = start[axis1] + j;
  const std::array<Vec, 3> ctrl{start, c, end};
  return make_bezier(ctrl).segment;
}

}  // namespace softmc::motion
