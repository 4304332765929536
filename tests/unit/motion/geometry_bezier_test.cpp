// Bézier segments, G5 and G5.1: exact end points, arc-length parameterisation, tangents, curvature.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

#include "motion/geometry/bezier.hpp"
#include "nearest_reference.hpp"

using namespace softmc;
using namespace softmc::motion;

namespace {
core::Vec xy(double x, double y, double z = 0) {
  core::Vec v;
  v[0] = x;
  v[1] = y;
  v[2] = z;
  return v;
}

// Composite Simpson with 2^18 panels: an independent reference for a length integral.
double simpson(const std::function<double(double)>& f, double a, double b) {
  constexpr int n = 1 << 18;
  const double h = (b - a) / n;
  double sum = f(a) + f(b);
  for (int i = 1; i < n; ++i) sum += f(a + i * h) * (i % 2 ? 4 : 2);
  return sum * h / 3;
}

// Speed of a 2-D cubic Bézier written out from the Bernstein derivative, not from the library.
double cubic_speed(const core::Vec (&p)[4], double u) {
  const double v = 1 - u;
  double sx = 0, sy = 0;
  for (int a = 0; a < 2; ++a) {
    const double d = 3 * (v * v * (p[1][a] - p[0][a]) + 2 * u * v * (p[2][a] - p[1][a]) + u * u * (p[3][a] - p[2][a]));
    (a == 0 ? sx : sy) = d;
  }
  return std::hypot(sx, sy);
}
}  // namespace

TEST(GeometryBezier, T2_CubicLengthMatchesNumericIntegration) {
  const core::Vec p[4] = {xy(0, 0), xy(30, 80), xy(90, -60), xy(100, 20)};
  const auto s = make_cubic_bezier(p[0], p[1], p[2], p[3]);
  ASSERT_EQ(s.kind, SegmentKind::Poly);
  const double ref = simpson([&](double u) { return cubic_speed(p, u); }, 0, 1);
  EXPECT_NEAR(s.length / ref - 1, 0, 1e-9) << s.length << " vs " << ref;
  EXPECT_EQ(s.point(0), p[0]);
  EXPECT_EQ(s.point(s.length), p[3]);
}

TEST(GeometryBezier, T2_EqualArcLengthStepsGiveEqualChords) {
  // Steps of 1 µm along the whole curve: each chord equals the step (the chord/arc difference
  // κ²h³/24 is below 1e-12 here), which holds only if point(s) is truly parameterised by length.
  const auto s = make_cubic_bezier(xy(0, 0), xy(30, 80), xy(90, -60), xy(100, 20, 5));
  const double h = 1e-3;
  core::Vec prev = s.point(0);
  double worst = 0;
  for (double at = h; at <= s.length; at += h) {
    const core::Vec p = s.point(at);
    worst = std::max(worst, std::abs(core::distance(p, prev) - h));
    prev = p;
  }
  EXPECT_LT(worst, 1e-9);
}

TEST(GeometryBezier, T2_TangentIsUnitAndMatchesFiniteDifferences) {
  const auto s = make_cubic_bezier(xy(0, 0), xy(30, 80), xy(90, -60), xy(100, 20, 5));
  for (int i = 1; i < 200; ++i) {
    const double at = s.length * i / 200.0, e = 1e-5;
    const auto t = s.tangent(at);
    EXPECT_NEAR(core::norm(t), 1, 1e-12);
    const auto fd = (s.point(at + e) - s.point(at - e)) * (1 / (2 * e));
    EXPECT_LT(core::distance(fd, t), 1e-6);
    const auto kfd = (s.tangent(at + e) - s.tangent(at - e)) * (1 / (2 * e));
    EXPECT_LT(core::distance(kfd, s.curvature(at)), 1e-5 * std::max(1.0, core::norm(kfd)));
    const auto f = s.frame(at);
    EXPECT_LT(core::distance(f.point, s.point(at)), 1e-12);
    EXPECT_LT(core::distance(f.tangent, t), 1e-12);
  }
}

TEST(GeometryBezier, G5_CurvyNEndsAndTangents) {
  // LinuxCNC's example: G0 X0 Y0 / G5 I0 J3 P0 Q-3 X1 Y1, then G5 P0 Q-3 X2 Y2 (I J = -previous P Q).
  const auto a = g5_cubic_spline(xy(0, 0), xy(1, 1), 0, 3, 0, -3);
  const auto b = g5_cubic_spline(xy(1, 1), xy(2, 2), 0, 3, 0, -3);
  EXPECT_EQ(a.point(0), xy(0, 0));
  EXPECT_EQ(a.point(a.length), xy(1, 1));
  EXPECT_NEAR(a.tangent(0)[1], 1, 1e-12);          // leaves along +Y (towards start + (I, J))
  EXPECT_NEAR(a.tangent(a.length)[1], 1, 1e-12);   // arrives along +Y (from end + (P, Q))
  EXPECT_LT(core::distance(a.tangent(a.length), b.tangent(0)), 1e-12);  // joins smoothly
  // The "N": y(u) = 9u(1-u)² - 6u²(1-u) + u³ rises to 1 at u = ¼, falls to 0 at u = ¾.
  EXPECT_NEAR(a.poly.at(0.25)[1], 1, 1e-12);
  EXPECT_NEAR(a.poly.at(0.75)[1], 0, 1e-12);
  EXPECT_GT(a.poly.at(0.25)[1], a.poly.at(0.5)[1] + 0.4);
  core::Vec lo, hi;
  a.bounds(lo, hi);
  EXPECT_NEAR(lo[1], 0, 1e-9);
  EXPECT_NEAR(hi[1], 1, 1e-9);
  EXPECT_EQ(lo[2], 0);
  EXPECT_EQ(hi[2], 0);
}

TEST(GeometryBezier, G5_BoundsContainTheCurveTightly) {
  const auto a = g5_cubic_spline(xy(0, 0), xy(1, 1), 0, 3, 0, -3);
  core::Vec lo, hi;
  a.bounds(lo, hi);
  double ymin = 1e9, ymax = -1e9;
  for (int i = 0; i <= 100000; ++i) {
    const auto p = a.poly.at(i / 100000.0);
    ymin = std::min(ymin, p[1]);
    ymax = std::max(ymax, p[1]);
    ASSERT_GE(p[0], lo[0]);
    ASSERT_LE(p[0], hi[0]);
  }
  EXPECT_LE(lo[1], ymin);
  EXPECT_GE(hi[1], ymax);
  EXPECT_LT(ymin - lo[1], 1e-8);
  EXPECT_LT(hi[1] - ymax, 1e-8);
  EXPECT_NEAR(hi[1] + lo[1], 1.0, 1e-9);  // the N is point-symmetric about (0.5, 0.5)
}

TEST(GeometryBezier, G5_1_ParabolaLiesOnYEqualsXSquared) {
  // LinuxCNC's example: G0 X-2 Y4 / G5.1 X2 I2 J-8 is the parabola y = x² through the origin.
  const auto s = g5_1_quadratic(xy(-2, 4), xy(2, 4), 2, -8);
  ASSERT_EQ(s.poly.degree, 2);
  const double exact_len = 2 * std::sqrt(17.0) + std::asinh(4.0) / 2;  // ∫ √(1 + 4x²) dx over [-2, 2]
  EXPECT_NEAR(s.length / exact_len - 1, 0, 1e-12);
  for (int i = 0; i <= 400; ++i) {
    const double at = s.length * i / 400.0;
    const auto p = s.point(at);
    EXPECT_NEAR(p[1], p[0] * p[0], 1e-12);
    // Curvature of y = x²: 2 / (1 + 4x²)^1.5, pointing to the concave side (+Y component).
    const auto k = s.curvature(at);
    EXPECT_NEAR(core::norm(k), 2 / std::pow(1 + 4 * p[0] * p[0], 1.5), 1e-9);
    EXPECT_GT(k[1], 0);
    EXPECT_NEAR(core::dot(k, s.tangent(at)), 0, 1e-9);
  }
  // Arc length from x = -2 to x: the closed form F(x) - F(-2) with F = x√(1+4x²)/2 + asinh(2x)/4.
  auto F = [](double x) { return x * std::sqrt(1 + 4 * x * x) / 2 + std::asinh(2 * x) / 4; };
  for (double x : {-1.5, -0.3, 0.0, 0.7, 1.9}) {
    const auto p = s.point(F(x) - F(-2));
    EXPECT_NEAR(p[0], x, 1e-9);
  }
  EXPECT_NEAR(s.distance_to(xy(0, 0)), 0, 1e-12);
  EXPECT_NEAR(s.distance_to(xy(0, -1)), 1, 1e-9);
  EXPECT_NEAR(s.max_curvature(), 2, 1e-9);  // at the vertex
}

TEST(GeometryBezier, RationalBezierRejectsBadWeightsAndDegrees) {
  const core::Vec c[3] = {xy(0, 0), xy(1, 1), xy(2, 0)};
  const double bad[3] = {1, 0, 1};
  EXPECT_EQ(make_rational_bezier(c, bad).error, CurveError::BadWeight);
  const core::Vec seven[7] = {};
  EXPECT_EQ(make_bezier(seven).error, CurveError::BadDegree);
  EXPECT_EQ(make_bezier(std::span<const core::Vec>(c, 1)).error, CurveError::TooFewPoints);
}

TEST(GeometryBezier, DegenerateStartTangentFollowsTheCurve) {
  // G5 with I = J = 0: C'(0) = 0; the tangent there is the limit direction, towards P2.
  const auto s = g5_cubic_spline(xy(0, 0), xy(10, 0), 0, 0, 0, 5);
  const auto t = s.tangent(0);
  EXPECT_NEAR(core::norm(t), 1, 1e-12);
  EXPECT_NEAR(t[0], 10 / std::hypot(10.0, 5.0), 1e-12);
  const double h = 1e-3;
  EXPECT_NEAR(core::distance(s.point(h), s.point(0)), h, 1e-9);
}

TEST(GeometryBezier, T2_CuspIsHalvedAndStillMeasuredExactly) {
  // (0,0) (10,10) (0,10) (10,0) has C'(½) = 0, a true cusp where |C'| has a kink. Its part over
  // u in [0, 0.7] puts the cusp at u = 5/7, between two length-table breakpoints: one table would
  // miss 1e-9 there, so the curve comes back as halves.
  const core::Vec q[4] = {xy(0, 0), xy(10, 10), xy(0, 10), xy(10, 0)};
  auto lerp = [](const core::Vec& a, const core::Vec& b, double t) { return a * (1 - t) + b * t; };
  const double t = 0.7;
  const core::Vec a1 = lerp(q[0], q[1], t), b1 = lerp(q[1], q[2], t), c1 = lerp(q[2], q[3], t);
  const core::Vec a2 = lerp(a1, b1, t), b2 = lerp(b1, c1, t), a3 = lerp(a2, b2, t);
  const core::Vec p[4] = {q[0], a1, a2, a3};
  std::vector<Segment> out;
  const double ones[4] = {1, 1, 1, 1};
  ASSERT_EQ(append_rational_bezier(out, p, ones), CurveError::Ok);
  EXPECT_GE(out.size(), 2u);
  double total = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    total += out[i].length;
    // Pieces graded down to a nanometre next to the cusp have an axis flat within a nanometre,
    // collapsed onto its start (build): the next piece starts within that of this one's end.
    if (i > 0) {
      EXPECT_LE(core::distance(out[i - 1].end, out[i].start), 1e-9) << i;
    }
  }
  const double ref = simpson([&](double u) { return cubic_speed(p, u); }, 0, 5.0 / 7) +
                     simpson([&](double u) { return cubic_speed(p, u); }, 5.0 / 7, 1);
  EXPECT_NEAR(total / ref - 1, 0, 1e-9) << total << " vs " << ref;
  // A single segment (make_cubic_bezier never splits) is less accurate across the kink: this is why.
  const auto one = make_cubic_bezier(p[0], p[1], p[2], p[3]);
  EXPECT_GT(std::abs(one.length / ref - 1), 1e-9);
}

// The planner's curvature-continuous corner blend (jerk mode): from V − d·t1 to V + d·t2, leaving
// and joining each line along it with zero curvature, its midpoint corner_blend_dev from V, and no
// point of it farther than that from the two lines, for gentle to sharp corners in 3-D.
TEST(GeometryBezier, CornerBlendLeavesAndJoinsTheLinesWithZeroCurvature) {
  for (const double delta : {0.1, 0.5, 1.0, std::numbers::pi / 2, 2.2, 2.8}) {
    const core::Vec corner = xy(3, -2, 1);
    core::Vec t1 = xy(1, 0, 0.2), t2 = xy(std::cos(delta), std::sin(delta), 0.2 * std::cos(delta) - 0.3);
    t1 = t1 * (1 / core::norm(t1));
    t2 = t2 * (1 / core::norm(t2));
    const double d = 0.4, alpha = 0.6, beta = 0.25;
    const auto r = make_corner_blend(corner, t1, t2, d, alpha, beta);
    ASSERT_TRUE(r.ok());
    const Segment& s = r.segment;
    EXPECT_EQ(s.start, corner - t1 * d);
    EXPECT_EQ(s.end, corner + t2 * d);
    EXPECT_LT(core::norm(s.tangent(0) - t1), 1e-12) << delta;
    EXPECT_LT(core::norm(s.tangent(s.length) - t2), 1e-12) << delta;
    EXPECT_LT(core::norm(s.curvature(0)), 1e-9) << delta;  // no acceleration step onto or off the lines
    EXPECT_LT(core::norm(s.curvature(s.length)), 1e-9) << delta;
    EXPECT_GT(core::norm(s.curvature(s.length / 2)), 0.1) << delta;
    const double dev = corner_blend_dev(core::norm(t2 - t1), d, alpha, beta);
    EXPECT_NEAR(core::distance(s.point(s.length / 2), corner), dev, 1e-12) << delta;
    const Segment in = make_line(corner - t1 * 10, corner), out = make_line(corner, corner + t2 * 10);
    double far = 0;
    for (int k = 0; k <= 1000; ++k) {
      const core::Vec p = s.point(s.length * k / 1000);
      far = std::max(far, std::min(in.distance_to(p), out.distance_to(p)));
    }
    EXPECT_LE(far, dev + 1e-12) << delta;
    EXPECT_GT(far, 0.5 * dev * std::cos(delta / 2)) << delta;  // it does cut the corner
  }
}

// s → u integrates its partial table interval with the 8-point rule where construction found it
// agrees with the 16-point one on every interval (PolyCurve::gl8_ok): tame cubics and quintics
// qualify, a curve with a near-cusp does not, and either rule gives the same parameter to 1e-12.
TEST(GeometryBezier, T2_ArcLengthInversionIsTheSameWithEitherRule) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  int fast = 0;
  for (int n = 0; n < 40; ++n) {
    std::vector<core::Vec> ctrl;
    const std::size_t deg = n % 2 ? 5 : 3;
    for (std::size_t i = 0; i <= deg; ++i) ctrl.push_back(xy(3.0 * i + 0.8 * u(rng), 0.8 * u(rng), 0.3 * u(rng)));
    const auto r = make_bezier(ctrl);
    ASSERT_TRUE(r.ok());
    fast += r.segment.poly.gl8_ok;
    PolyCurve slow = r.segment.poly;
    slow.gl8_ok = false;
    for (int k = 1; k < 200; ++k) {
      const double s = r.segment.length * k / 200;
      EXPECT_NEAR(r.segment.poly.param_at(s), slow.param_at(s), 1e-12) << n << " " << k;
    }
  }
  EXPECT_GE(fast, 36);
  // The cusp of (0,0) (10,10) (0,10) (10,0) at u = 5/7 of its part over [0, 0.7] (as below): |C'|
  // has a kink inside a table interval.
  const core::Vec q[4] = {xy(0, 0), xy(10, 10), xy(0, 10), xy(10, 0)};
  const auto lerp = [](const core::Vec& a, const core::Vec& b, double t) { return a * (1 - t) + b * t; };
  const core::Vec a1 = lerp(q[0], q[1], 0.7), b1 = lerp(q[1], q[2], 0.7), c1 = lerp(q[2], q[3], 0.7);
  const core::Vec a2 = lerp(a1, b1, 0.7), b2 = lerp(b1, c1, 0.7);
  const auto c = make_bezier(std::vector<core::Vec>{q[0], a1, a2, lerp(a2, b2, 0.7)});
  ASSERT_TRUE(c.ok());
  EXPECT_FALSE(c.segment.poly.gl8_ok);
}

// The planner's blend where a line meets an arc (or two arcs meet): the quintic continues each
// curve with its position, unit tangent and curvature vector, so no axis's acceleration steps.
TEST(GeometryBezier, G2BlendContinuesEachCurveWithItsTangentAndCurvature) {
  const Segment in = make_line(xy(-5, 0, 0), xy(0, 0, 0));
  for (const int turns : {1, -1}) {
    // A helix leaving the corner at 90° (centre (0, ±3)), rising along z.
    const Segment out = make_arc(xy(0, 0, 0), xy(3 * turns, 3, 1), 0, 1, 3 * turns, 0, -turns);
    const double sa = in.length - 0.4, sb = 0.5;
    const core::Vec p0 = in.point(sa), p1 = out.point(sb);
    const core::Vec t0 = in.tangent(sa), t1 = out.tangent(sb) * (1 / core::norm(out.tangent(sb)));
    const auto r = make_g2_blend(p0, t0, in.curvature(sa), 0.5, p1, t1, out.curvature(sb), 0.45, 0.6, 0.2);
    ASSERT_TRUE(r.ok());
    const Segment& s = r.segment;
    EXPECT_EQ(s.start, p0);
    EXPECT_EQ(s.end, p1);
    EXPECT_LT(core::norm(s.tangent(0) - t0), 1e-12) << turns;
    EXPECT_LT(core::norm(s.tangent(s.length) - t1), 1e-12) << turns;
    EXPECT_LT(core::norm(s.curvature(0)), 1e-9) << turns;  // the line's
    const core::Vec k1 = out.curvature(sb);
    EXPECT_GT(core::norm(k1), 0.1);
    EXPECT_LT(core::norm(s.curvature(s.length) - k1), 1e-9 * core::norm(k1)) << turns;  // the helix's
    for (int k = 0; k <= 10; ++k)  // bezier_point is the same curve the segment samples
      EXPECT_LT(core::distance(bezier_point(g2_blend_points(p0, t0, in.curvature(sa), 0.5, p1, t1, out.curvature(sb),
                                                            0.45, 0.6, 0.2),
                                            s.poly.param_at(s.length * k / 10)),
                               s.point(s.length * k / 10)),
                1e-12);
  }
}

// The power-basis form the planner evaluates candidate blends with is the same curve as de Casteljau's.
TEST(GeometryBezier, PowerBasisIsTheSameCurve) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-10, 10);
  for (std::size_t n = 1; n <= 5; ++n) {
    std::vector<core::Vec> c(n + 1);
    for (auto& p : c) p = xy(u(rng), u(rng), u(rng));
    const BezierPower b(c);
    for (int k = 0; k <= 20; ++k) {
      const double t = k / 20.0;
      EXPECT_LT(core::distance(b.at(t), bezier_point(c, t)), 1e-11) << n << " " << t;
    }
    EXPECT_EQ(b.at(0), c.front());
  }
}

// The planner's jerk speed term v³·|dκ/ds| (κ the curvature vector) comes from the sampled
// PolyCurve::max_dcurvature. A secant over 1/256 of u is the mean over its interval: on a
// near-cusp cubic it was half the true peak, below even κ², which the curvature vector's derivative
// always holds (its tangential part is −κ²). The intervals beside the largest secant are sampled
// 32 times finer: at least a 40 000-step reference, and at least κ².
TEST(GeometryBezier, MaxDcurvatureFindsASharpPeak) {
  Vec p0{}, p1{}, p2{}, p3{};
  p1[0] = -4.9, p1[1] = 4.1;
  p2[0] = 7.6, p2[1] = -5.5;
  p3[0] = -3.8, p3[1] = -6.6;
  const Segment g = make_cubic_bezier(p0, p1, p2, p3);
  constexpr int kSteps = 40000;
  const double h = g.length / kSteps;
  double fine = 0;
  for (int i = 0; i < kSteps; ++i) fine = std::max(fine, core::norm(g.curvature((i + 1) * h) - g.curvature(i * h)) / h);
  // (The reference steps evenly in s, which the cusp's sharp end covers in few steps: the finer u
  // samples there find a higher peak still. Before: 1.27e6 against this reference's 4.6e6.)
  EXPECT_GT(g.poly.max_dcurvature, 0.99 * fine) << g.poly.max_dcurvature << " vs " << fine;
  EXPECT_LT(g.poly.max_dcurvature, 2 * fine);
  EXPECT_GE(g.poly.max_dcurvature, g.poly.max_curvature * g.poly.max_curvature);
}

// The arc-length integrals of a polynomial Bézier evaluate |C'(u)| from one stored polynomial of
// |C'|² (PolyCurve::speed2, degree 2(n − 1)). On random curves of every degree in four axes, and
// on equal weights ≠ 1 (still polynomial), the length over random parameter intervals of one table
// step agrees with Simpson's rule over the norm of the de Casteljau derivative to 1e-10 of the
// curve's length; a rational curve keeps the quotient form and agrees as well.
TEST(GeometryBezier, StoredSpeedPolynomialMatchesTheDerivative) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-50, 50), t(0, 1);
  for (int trial = 0; trial < 40; ++trial) {
    const std::size_t degree = 1 + static_cast<std::size_t>(trial) % kMaxBezierDegree;
    std::vector<core::Vec> ctrl(degree + 1);
    for (auto& p : ctrl)
      for (std::size_t a : {0, 1, 2, 4}) p[a] = u(rng);
    std::vector<double> w(degree + 1, trial % 3 == 1 ? 2.5 : 1.0);
    if (trial % 3 == 2)
      for (auto& x : w) x = 0.5 + t(rng);
    const auto r = make_rational_bezier(ctrl, w);
    ASSERT_TRUE(r.ok()) << trial;
    ASSERT_EQ(r.segment.kind, SegmentKind::Poly) << trial;
    const PolyCurve& c = r.segment.poly;
    EXPECT_EQ(c.has_speed2, trial % 3 != 2) << trial;
    for (int k = 0; k < 3; ++k) {  // intervals of a table step, where 16 Gauss points are exact
      const double a = t(rng) * (1 - 1.0 / kArcTableIntervals), b = a + 1.0 / kArcTableIntervals;
      const double ref = simpson([&](double x) { return core::norm(c.derivs(x).d1); }, a, b);
      EXPECT_NEAR(c.arc(a, b), ref, 1e-10 * std::max(1.0, c.length())) << trial << " " << a << " " << b;
    }
  }
}

// A cubic in XY at a height (and a 4th axis) it keeps: the axes it does not move stay exactly where
// they are at every arc length (PolyCurve::moving), not within a rounding of the Bernstein sum,
// and the tangent and curvature there are 0. Its moving axes are X and Y alone.
TEST(GeometryBezier, AxesTheCurveDoesNotMoveStayExactlyPut) {
  core::Vec p[4] = {xy(0, 0, 0.1), xy(3.3, 1.7, 0.1), xy(6.1, -2.9, 0.1), xy(9.7, 0.3, 0.1)};
  for (auto& q : p) q[6] = 0.7;
  const Segment s = make_cubic_bezier(p[0], p[1], p[2], p[3]);
  ASSERT_EQ(s.poly.n_moving, 2u);
  EXPECT_EQ(s.poly.moving[0], 0u);
  EXPECT_EQ(s.poly.moving[1], 1u);
  int off = 0;
  for (int i = 0; i <= 1000; ++i) {
    const double at = s.length * i / 1000;
    const CurveFrame f = s.frame(at);
    off += f.point[2] != 0.1 || f.point[6] != 0.7;
    EXPECT_EQ(f.tangent[2], 0.0);
    EXPECT_EQ(f.curvature[6], 0.0);
    EXPECT_NEAR(std::hypot(f.tangent[0], f.tangent[1]), 1.0, 1e-12);
  }
  EXPECT_EQ(off, 0) << "samples off the height the curve keeps";
}

// Polynomial pieces of degree 1, 2, 4 and 5 are evaluated on the axes their control points move
// (PolyCurve::poly_axes, listed by finalize) instead of comparing every axis's points at every
// evaluation: the same derivatives to the bit as the comparisons give (kAxesUnknown: the reference),
// on random pieces with some axes held, some moved by a single control point.
TEST(GeometryBezier, ListedAxesGiveTheSameDerivativesAsTheReference) {
  std::mt19937_64 rng(20261203);
  std::uniform_real_distribution<double> coord(-50, 50);
  std::uniform_int_distribution<int> pick(0, 3);
  int compared = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const std::size_t n = std::array<std::size_t, 4>{1, 2, 4, 5}[static_cast<std::size_t>(trial % 4)];
    std::vector<core::Vec> ctrl(n + 1);
    for (std::size_t a = 0; a < core::kMaxAxes; ++a) {
      const int kind = pick(rng);  // 0: held, 1: one point moved, else: all random
      const double base = coord(rng);
      for (std::size_t i = 0; i <= n; ++i) ctrl[i][a] = kind == 0 ? base : kind == 1 ? (i == n / 2 + 1 ? coord(rng) : base) : coord(rng);
    }
    const SegmentResult r = make_bezier(ctrl);
    ASSERT_TRUE(r.ok()) << trial;
    const Segment& s = r.segment;
    ASSERT_NE(s.poly.n_poly_axes, PolyCurve::kAxesUnknown);
    PolyCurve ref = s.poly;
    ref.n_poly_axes = PolyCurve::kAxesUnknown;
    for (int i = 0; i <= 64; ++i) {
      const double u = i / 64.0 + (i % 3) * 1e-3 * (i < 64);
      const CurveDerivs d = s.poly.derivs(u), e = ref.derivs(u);
      for (std::size_t a = 0; a < core::kMaxAxes; ++a) {
        ASSERT_EQ(d.c[a], e.c[a]) << trial << " u " << u << " axis " << a;
        ASSERT_EQ(d.d1[a], e.d1[a]) << trial << " u " << u << " axis " << a;
        ASSERT_EQ(d.d2[a], e.d2[a]) << trial << " u " << u << " axis " << a;
      }
      ++compared;
    }
  }
  EXPECT_EQ(compared, 400 * 65);
}

// s → u of a polynomial piece evaluates its stored |C'|² unrolled for its degree (PolyCurve::param_at):
// the same parameter to the bit as the general speed evaluation (param_at_reference), for degrees
// 1 to 5, at arc lengths across each piece, its ends and beyond.
TEST(GeometryBezier, ArcLengthInversionIsTheSameAsTheReference) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coord(-20, 20);
  int compared = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t n = static_cast<std::size_t>(trial % 5) + 1;
    std::vector<core::Vec> ctrl(n + 1);
    for (auto& p : ctrl)
      for (std::size_t a : {0u, 1u, 2u, 6u}) p[a] = coord(rng);
    const SegmentResult r = make_bezier(ctrl);
    ASSERT_TRUE(r.ok()) << trial;
    const PolyCurve& c = r.segment.poly;
    ASSERT_TRUE(c.has_speed2);
    for (int i = -1; i <= 301; ++i) {
      const double s = c.length() * i / 300.0 * (1 + 1e-7 * (i % 7));
      ASSERT_EQ(c.param_at(s), c.param_at_reference(s)) << trial << " s " << s;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 200 * 303);
}

// A fuzzer's G5 (G5 I1.175 J1.132 P-0.416 Q1.183 from X34.4985 Y81.5772 to X33.6178 Y79.3326)
// nearly stops at u = 0.195 (|C'| 0.0029, under a thousandth of its length) without a cusp: the
// split there collapsed the pieces' end legs as at a true cusp, 2e-4 mm of control point: the
// pieces lay up to 3.5e-4 mm off the programmed cubic, and a run's setpoints 1.6e-6 mm off it
// (setpoints on the programmed curve within 1e-6 mm). Legs are collapsed only where that moves the
// curve by less than 1e-9 mm: every point of the pieces lies on the programmed cubic.
TEST(GeometryBezier, T2_ANearCuspIsSplitWithoutMovingTheCurve) {
  const core::Vec p0 = xy(34.4985, 81.5772), p3 = xy(33.6178, 79.3326);
  const core::Vec p[4] = {p0, p0 + xy(1.175, 1.132), p3 + xy(-0.416, 1.183), p3};
  const auto cubic = [&](double u) {
    const double v = 1 - u;
    return p[0] * (v * v * v) + p[1] * (3 * v * v * u) + p[2] * (3 * v * u * u) + p[3] * (u * u * u);
  };
  std::vector<Segment> out;
  const double ones[4] = {1, 1, 1, 1};
  ASSERT_EQ(append_rational_bezier(out, p, ones), CurveError::Ok);
  ASSERT_GE(out.size(), 2u);  // split at the near cusp
  constexpr int kRef = 20000;
  std::vector<core::Vec> ref(kRef + 1);
  for (int i = 0; i <= kRef; ++i) ref[i] = cubic(static_cast<double>(i) / kRef);
  double worst = 0;
  for (const auto& seg : out) {
    for (int k = 0; k <= 48; ++k) {  // (the near cusp is graded into 25 pieces: 48 points each)
      const core::Vec q = seg.point(seg.length * k / 48);
      int best = 0;
      for (int i = 1; i <= kRef; ++i)
        if (core::distance(ref[i], q) < core::distance(ref[best], q)) best = i;
      double lo = std::max(0, best - 1) / static_cast<double>(kRef), hi = std::min(kRef, best + 1) / static_cast<double>(kRef);
      for (int it = 0; it < 200; ++it) {  // the nearest point between the neighbouring samples
        const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
        const bool nearer_m1 = core::distance(cubic(m1), q) < core::distance(cubic(m2), q);
        (nearer_m1 ? hi : lo) = nearer_m1 ? m2 : m1;
      }
      worst = std::max(worst, core::distance(cubic(0.5 * (lo + hi)), q));
    }
  }
  EXPECT_LT(worst, 1e-9) << "the pieces leave the programmed cubic";
}

// Next to the near cusp above the curvature climbs to 2.4·10⁶/mm within a micrometre, and the
// planner gives each piece one cap from its largest κ: the two 0.1 mm pieces ending there crawled
// at that cap (125 s for the 3.4 mm curve at F1200 on the built-in table). A piece whose curvature
// is all at one end is now split where κ falls to a quarter of the end's, again and again
// (grade_param), so the pieces' caps rise away from the sharp end. Measured as the time the caps
// give at one acceleration, Σ L·√κ_max against ∫ √κ ds (a = v²κ): 175× before, now under 2×.
TEST(GeometryBezier, T2_APieceSharpAtOneEndIsGradedTowardsIt) {
  const core::Vec p0 = xy(34.4985, 81.5772), p3 = xy(33.6178, 79.3326);
  const core::Vec p[4] = {p0, p0 + xy(1.175, 1.132), p3 + xy(-0.416, 1.183), p3};
  std::vector<Segment> out;
  const double ones[4] = {1, 1, 1, 1};
  ASSERT_EQ(append_rational_bezier(out, p, ones), CurveError::Ok);
  double pieces = 0, ideal = 0, length = 0;
  for (const auto& seg : out) {
    pieces += seg.length * std::sqrt(seg.poly.max_curvature);
    constexpr int kN = 4000;
    for (int k = 0; k < kN; ++k)
      ideal += seg.length / kN * std::sqrt(core::norm(seg.frame(seg.length * (k + 0.5) / kN).curvature));
    length += seg.length;
  }
  EXPECT_LT(pieces, 2 * ideal) << out.size() << " pieces";
  EXPECT_NEAR(length, 3.38309026259, 1e-9);
  // A curve of even curvature is left whole: a quarter circle as a cubic.
  const double k = 0.5522847498;
  const core::Vec q[4] = {xy(10, 0), xy(10, 10 * k), xy(10 * k, 10), xy(0, 10)};
  std::vector<Segment> arc;
  ASSERT_EQ(append_rational_bezier(arc, q, ones), CurveError::Ok);
  EXPECT_EQ(arc.size(), 1u);
}

// A G5 whose control polygon nearly doubles back twice (a review's): two near cusps 0.06 mm apart,
// |C'| down to 3.3e-8 there. Grading on κ alone left 0.1 mm pieces whose |dκ/ds| peaked at their
// ends (3.3·10⁷/mm²): at 10 000 mm/s³ those pieces' jerk caps (j/|dκ/ds|)^⅓ made the curve 3.3 s
// long (Σ length / cap). Graded on the sharpness √|dκ/ds| as well: 0.07 s. The
// pieces meet within a nanometre (an axis flat within that beside moving ones is collapsed onto its
// start by build; a piece flat on every axis is the straight piece between its ends), and their
// lengths add up to the curve's within 3e-9 (2.2e-8 before; the reference: mpmath at 50 digits,
// split at the two speed minima).
TEST(GeometryBezier, T2_APieceIsGradedOnItsJerkTermToo) {
  const core::Vec p0 = xy(100.04448776445652, 100.07219332582257), p3 = xy(99.950378222369238, 99.906515631366091);
  const core::Vec p[4] = {p0, p0 + xy(-0.13175071874582045, -0.23194520248019046),
                          p3 + xy(0.13175335892219664, 0.23194877223906474), p3};
  std::vector<Segment> out;
  const double ones[4] = {1, 1, 1, 1};
  ASSERT_EQ(append_rational_bezier(out, p, ones), CurveError::Ok);
  double length = 0, at_caps = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    length += out[i].length;
    at_caps += out[i].length * std::cbrt(out[i].poly.jerk_speed_term() / 10000);
    if (i > 0) {
      EXPECT_LE(core::distance(out[i - 1].end, out[i].start), 1e-9) << i;
    }
  }
  EXPECT_EQ(out.front().start, p0);
  EXPECT_EQ(out.back().end, p3);
  EXPECT_NEAR(length / 0.24443152118297081 - 1, 0, 3e-9);
  EXPECT_LT(at_caps, 0.2) << out.size() << " pieces";
}

// An axis whose control points lie within a nanometre of each other counts as not moving (build):
// beside axes that move, it is collapsed onto its start value, so it gives no direction and no
// curvature where the moving axes stand still (a review's G5.2 along X with Y moving 9e-10: 3.28 s;
// kept at its end values, its nanometre of shape made 286 s of it); the piece ends within that
// nanometre of its last control point. A piece flat on every axis is the straight piece between its
// own ends (collapsed onto its start, it left a gap to the next piece).
TEST(GeometryBezier, AnAxisFlatWithinANanometreGivesNoDirection) {
  const core::Vec c[4] = {xy(0, 0, 1), xy(0, 1, 1 + 3e-10), xy(0, 1, 1 - 2e-10), xy(2, 1, 1 + 6e-10)};
  const Segment s = make_bezier(c).segment;
  EXPECT_EQ(s.start, c[0]);
  EXPECT_LE(core::distance(s.end, c[3]), 1e-9);
  EXPECT_EQ(s.tangent(0)[2], 0.0);
  EXPECT_EQ(s.tangent(s.length)[2], 0.0);
  EXPECT_EQ(s.curvature(s.length / 2)[2], 0.0);
  // Within a nanometre on every axis: the straight piece between its ends.
  const core::Vec t[4] = {xy(0, 0), xy(4e-10, 7e-10), xy(-3e-10, 2e-10), xy(6e-10, 3e-10)};
  const Segment tip = make_bezier(t).segment;
  EXPECT_EQ(tip.end, t[3]);
  EXPECT_NEAR(tip.length, core::norm(t[3]), 1e-24);
  EXPECT_LT(tip.poly.max_curvature, 1e-12);
}

// The distance to a Bézier piece against a dense sampling refined by golden sections: exact with
// no `enough`; with one, a caller that only asks whether it is within `enough` (a fillet's check
// of the arc it replaces, 17 points each) gets a point's distance at or below it as soon as a
// coarse-to-fine sample finds one, and the exact distance when there is none.
TEST(GeometryBezier, DistanceToAPieceIsTheNearestPointOrOneWithinEnough) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(0, 1);
  int within = 0, beyond = 0;
  for (int t = 0; t < 60; ++t) {
    std::array<core::Vec, 6> c{};
    for (auto& q : c) q = xy(10 * u(rng), 10 * u(rng), 2 * u(rng));
    const Segment s = make_bezier(c).segment;
    for (int k = 0; k < 5; ++k) {
      core::Vec p = s.point(s.length * u(rng));
      for (int i = 0; i < 3; ++i) p[i] += 0.5 * (2 * u(rng) - 1);
      const double brute = test::brute_distance(s, p, 4000);
      const double exact = s.distance_to(p);
      EXPECT_NEAR(exact, brute, 1e-9) << t << " " << k;
      const double enough = 0.3;
      const double quick = s.distance_to(p, enough);
      EXPECT_GE(quick, exact - 1e-12);
      if (exact < enough - 1e-9) {
        EXPECT_LE(quick, enough);
        ++within;
      } else if (exact > enough + 1e-9) {
        EXPECT_EQ(quick, exact);
        ++beyond;
      }
    }
  }
  EXPECT_GT(within, 50);
  EXPECT_GT(beyond, 50);
}

// A curve that starts standing still (its first control point doubled, as a G5.2 starting where the
// machine is: C'(0) = 0): Newton cannot start at u = 0, and the distance of a point of the curve a
// few micrometres along was the distance to the start itself: a review's G61 run reported 2.5e-6 mm
// off its NURBS where every setpoint lay on it. A golden-section search takes over there.
TEST(GeometryBezier, DistanceToIsExactWhereTheCurveStartsStandingStill) {
  const core::Vec c[4] = {xy(50, 50), xy(50, 50), xy(50.4, 49.2), xy(50.1, 49.8)};
  const Segment s = make_bezier(c).segment;
  for (const double at : {1e-7, 2.7e-6, 1e-4, 1e-3}) {
    const core::Vec p = s.point(at);
    EXPECT_LT(s.distance_to(p), 1e-12) << at;
    // A point beside it: against the nearest of 20 000 points over the first 0.2 µm past it.
    const core::Vec q = p + xy(0, 1e-5);
    double brute = 1e300;
    for (int k = 0; k <= 20000; ++k) brute = std::min(brute, core::distance(q, s.point((at + 2e-4) * k / 20000)));
    EXPECT_NEAR(s.distance_to(q), brute, 1e-10) << at;
  }
}
