// Lines and arcs: points, tangents, curvature, lengths, bounds, distances.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <tuple>

#include "motion/geometry/segment.hpp"

using namespace softmc;
using motion::make_arc;
using motion::make_line;

namespace {
core::Vec xy(double x, double y, double z = 0) {
  core::Vec v;
  v[0] = x;
  v[1] = y;
  v[2] = z;
  return v;
}
}  // namespace

TEST(Geometry, LinePointTangentLength) {
  const auto s = make_line(xy(0, 0), xy(3, 4));
  EXPECT_DOUBLE_EQ(s.length, 5.0);
  EXPECT_EQ(s.point(0), xy(0, 0));
  EXPECT_EQ(s.point(5), xy(3, 4));
  EXPECT_NEAR(s.point(2.5)[0], 1.5, 1e-12);
  EXPECT_NEAR(s.tangent(1)[1], 0.8, 1e-12);
  EXPECT_DOUBLE_EQ(core::norm(s.curvature(1)), 0.0);
}

TEST(Geometry, T2_ArcPointsLieOnTheCircle) {
  // Rounded rectangle's first arc: centre (40,20), from (40,10) sweeping +90° to (50,20).
  const auto a = make_arc(xy(40, 10), xy(50, 20), 0, 1, 40, 20, 1);
  EXPECT_NEAR(a.radius, 10, 1e-12);
  EXPECT_NEAR(a.sweep, std::numbers::pi / 2, 1e-12);
  EXPECT_NEAR(a.length, 10 * std::numbers::pi / 2, 1e-12);
  for (int i = 0; i <= 1000; ++i) {
    const auto p = a.point(a.length * i / 1000.0);
    EXPECT_NEAR(std::hypot(p[0] - 40, p[1] - 20), 10.0, 1e-9);
    EXPECT_LE(p[0], 50 + 1e-12);
    EXPECT_GE(p[0], 40 - 1e-12);
  }
  EXPECT_EQ(a.point(a.length), xy(50, 20));
  // Tangent at the start points +X (counter-clockwise from the bottom of the circle).
  EXPECT_NEAR(a.tangent(0)[0], 1, 1e-12);
  // Curvature points to the centre with magnitude 1/R.
  const auto k = a.curvature(0);
  EXPECT_NEAR(k[1], 0.1, 1e-12);
  EXPECT_NEAR(core::norm(k), 0.1, 1e-12);
}

TEST(Geometry, ClockwiseArcAndFullCircle) {
  const auto cw = make_arc(xy(10, 0), xy(0, 10), 0, 1, 0, 0, -1);  // the long way round, 270°
  EXPECT_NEAR(cw.sweep, -1.5 * std::numbers::pi, 1e-12);
  const auto full = make_arc(xy(10, 0), xy(10, 0), 0, 1, 0, 0, 1);
  EXPECT_NEAR(full.sweep, 2 * std::numbers::pi, 1e-12);
  const auto two = make_arc(xy(10, 0), xy(10, 0), 0, 1, 0, 0, -2);
  EXPECT_NEAR(two.sweep, -4 * std::numbers::pi, 1e-12);
}

TEST(Geometry, HelixMovesTheNormalAxisLinearly) {
  const auto h = make_arc(xy(10, 0, 0), xy(10, 0, 5), 0, 1, 0, 0, 1);
  const double arc = 2 * std::numbers::pi * 10;
  EXPECT_NEAR(h.length, std::hypot(arc, 5.0), 1e-9);
  const auto mid = h.point(h.length / 2);
  EXPECT_NEAR(mid[2], 2.5, 1e-12);
  EXPECT_NEAR(mid[0], -10, 1e-9);
  EXPECT_NEAR(core::norm(h.tangent(1.0)), 1.0, 1e-12);
}

TEST(Geometry, BoundsIncludeArcExtremes) {
  const auto a = make_arc(xy(10, 0), xy(-10, 0), 0, 1, 0, 0, 1);  // upper half circle
  core::Vec lo, hi;
  a.bounds(lo, hi);
  EXPECT_NEAR(hi[1], 10, 1e-12);
  EXPECT_NEAR(lo[1], 0, 1e-12);
  EXPECT_NEAR(lo[0], -10, 1e-12);
}

TEST(Geometry, DistanceToCurve) {
  const auto a = make_arc(xy(10, 0), xy(0, 10), 0, 1, 0, 0, 1);
  EXPECT_NEAR(a.distance_to(xy(0, 10.5)), 0.5, 1e-9);
  EXPECT_NEAR(a.distance_to(xy(7.0710678118654755 * 0.9, 7.0710678118654755 * 0.9)), 1.0, 1e-9);
  EXPECT_NEAR(a.distance_to(xy(0, -10)), std::hypot(10.0, 10.0), 1e-9);  // the missing quadrant is far
  const auto l = make_line(xy(0, 0), xy(10, 0));
  EXPECT_NEAR(l.distance_to(xy(5, 2)), 2, 1e-12);
  EXPECT_NEAR(l.distance_to(xy(13, 4)), 5, 1e-12);
}

TEST(Geometry, MaxTangentAndCurvatureForThePlanner) {
  const auto l = make_line(xy(0, 0), xy(3, -4));
  EXPECT_NEAR(l.max_abs_tangent()[0], 0.6, 1e-12);
  EXPECT_NEAR(l.max_abs_tangent()[1], 0.8, 1e-12);
  EXPECT_EQ(l.max_curvature(), 0);
  // Arc from 20° to 60° on R = 10: the tangent (-sin θ, cos θ) peaks at |sin 60°| and |cos 20°|.
  const double d = std::numbers::pi / 180;
  const auto a = make_arc(xy(10 * std::cos(20 * d), 10 * std::sin(20 * d)), xy(10 * std::cos(60 * d), 10 * std::sin(60 * d)),
                          0, 1, 0, 0, 1);
  EXPECT_NEAR(a.max_abs_tangent()[0], std::sin(60 * d), 1e-12);
  EXPECT_NEAR(a.max_abs_tangent()[1], std::cos(20 * d), 1e-12);
  EXPECT_NEAR(a.max_curvature(), 0.1, 1e-12);
  // Passing through 90°, |sin| reaches 1.
  const auto b = make_arc(xy(10 * std::cos(80 * d), 10 * std::sin(80 * d)), xy(-10, 0), 0, 1, 0, 0, 1);
  EXPECT_NEAR(b.max_abs_tangent()[0], 1, 1e-12);
  EXPECT_NEAR(b.max_abs_tangent()[1], 1, 1e-12);  // and |cos| at 180°
  // A helix: the in-plane share shrinks by the pitch.
  const auto h = make_arc(xy(10, 0, 0), xy(10, 0, 5), 0, 1, 0, 0, 1);
  EXPECT_NEAR(h.max_abs_tangent()[0], 2 * std::numbers::pi * 10 / h.length, 1e-12);
  EXPECT_NEAR(h.max_abs_tangent()[2], 5 / h.length, 1e-12);
}

// An arc whose programmed end lies off the start circle (the interpreter allows a small difference,
// as LinuxCNC does) is a slight spiral: it ends exactly on the programmed point with no jump, its
// length is the spiral's to 1e-9, s is its arc length (|tangent| = 1) and tangent/curvature are the
// derivatives of point().
TEST(Geometry, SpiralArcReachesAnEndOffTheCircleWithoutAJump) {
  // plasma.ngc's notch: the end radius is 0.54 µm longer than the start radius.
  const auto a = make_arc({31.62, 18.835}, {38.54, 14.839}, 0, 1, 35, 16.699, -1);
  EXPECT_GT(std::abs(a.dradius), 5e-4);
  EXPECT_LT(core::distance(a.point(a.length * (1 - 1e-12)), a.end), 1e-10);
  // Length: the sum of many small chords converges to it.
  double chords = 0;
  const int n = 200000;
  for (int k = 0; k < n; ++k) chords += core::distance(a.point(a.length * k / n), a.point(a.length * (k + 1) / n));
  EXPECT_NEAR(chords / a.length, 1, 1e-9);
  const double h = 1e-4;
  for (double f : {0.1, 0.5, 0.9}) {
    const double s = f * a.length;
    const core::Vec d1 = (a.point(s + h) - a.point(s - h)) * (0.5 / h);
    const core::Vec d2 = (a.point(s + h) - a.point(s) * 2 + a.point(s - h)) * (1 / (h * h));
    EXPECT_LT(core::distance(d1, a.tangent(s)), 1e-8);
    EXPECT_LT(core::distance(d2, a.curvature(s)), 1e-4);
    EXPECT_LE(std::abs(a.tangent(s)[0]), a.max_abs_tangent()[0] + 1e-12);
    EXPECT_LE(core::norm(a.curvature(s)), a.max_curvature() + 1e-12);
    EXPECT_NEAR(core::norm(a.tangent(s)), 1, 1e-14);
    EXPECT_NEAR(core::dot(a.tangent(s), a.curvature(s)), 0, 1e-14);
  }
}

// Arcs are parameterised by arc length, spirals too (the issue: "exact segments parameterised by arc
// length"): strong spirals (the end radius 0.05 to 3 times the start's, over sweeps up to 3 turns,
// with and without a rise) have |tangent| = 1 everywhere, lie on r = r0 + dr·φ/|sweep| (the same
// curve as the program's arc: the radius runs linearly with the angle), give the length of their
// chords to 1e-9, and their tangent, curvature and bounds are those of point(). Before, the angle
// ran linearly with s and |dp/ds| reached 1.38 on a tiny arc within the interpreter's allowance.
TEST(Geometry, StrongSpiralsAreParameterisedByArcLength) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  for (int t = 0; t < 60; ++t) {
    const double r0 = 0.01 + 5 * u(rng), r1 = r0 * (0.05 + 2.95 * u(rng)), th0 = 6.283 * u(rng);
    const double sweep = (u(rng) * 2 - 1) * 18, rise = t % 2 ? 0.0 : 3 * r0 * (u(rng) * 2 - 1);
    const int turns = (sweep < 0 ? -1 : 1) * (static_cast<int>(std::abs(sweep) / 6.283185307179586) + 1);
    const auto g = make_arc(xy(r0 * std::cos(th0), r0 * std::sin(th0), 1),
                            xy(r1 * std::cos(th0 + sweep), r1 * std::sin(th0 + sweep), 1 + rise), 0, 1, 0, 0, turns);
    ASSERT_NE(g.dradius, 0) << t;
    const auto ab = g.arc_bounds();
    const core::Vec tmax = g.max_abs_tangent(), nmax = g.max_abs_normal();
    const auto chords = [&](int n) {
      double sum = 0;
      core::Vec prev = g.point(0);
      for (int k = 1; k <= n; ++k) {
        const core::Vec p = g.point(g.length * k / n);
        sum += core::distance(prev, p);
        prev = p;
      }
      return sum;
    };
    // The chords fall short by about Δ²κ²/24 of the length: Richardson's extrapolation removes that.
    const double c1 = chords(10000), c2 = chords(20000);
    EXPECT_NEAR((4 * c2 - c1) / 3 / g.length, 1, 1e-9) << t;
    for (int k = 0; k <= 200; ++k) {
      const double s = g.length * k / 200;
      const motion::CurveFrame fr = g.frame(s);
      EXPECT_NEAR(core::norm(fr.tangent), 1, 1e-12) << t << " s " << s;
      EXPECT_LT(core::distance(fr.point, g.point(s)), 1e-12) << t;
      EXPECT_LT(core::norm(fr.tangent - g.tangent(s)), 1e-12) << t;
      EXPECT_LT(core::norm(fr.curvature - g.curvature(s)), 1e-9 * core::norm(fr.curvature)) << t;
      // On the program's curve: the radius is linear in the angle turned.
      const double r = std::hypot(fr.point[0], fr.point[1]);
      double turned = std::atan2(fr.point[1], fr.point[0]) - g.theta0;
      const double expect_frac = (r - g.radius) / g.dradius;  // the angle's fraction of the sweep
      turned -= 6.283185307179586 * std::round((turned - expect_frac * g.sweep) / 6.283185307179586);
      EXPECT_NEAR(turned / g.sweep, expect_frac, 1e-9 * std::max(1.0, g.radius / std::abs(g.dradius))) << t;
      EXPECT_NEAR(fr.point[2], 1 + rise * s / g.length, 1e-12) << t;
      // Bounds the planner's limits rest on.
      for (int i : {0, 1}) {
        EXPECT_LE(std::abs(fr.tangent[i]), tmax[i] + 1e-12) << t;
        const core::Vec nrm = fr.curvature * (1 / std::max(1e-300, core::norm(fr.curvature)));
        EXPECT_LE(std::abs(nrm[i]), nmax[i] + 1e-9) << t;
      }
      EXPECT_LE(std::hypot(fr.tangent[0], fr.tangent[1]), ab.inplane + 1e-12) << t;
      EXPECT_LE(core::norm(fr.curvature), ab.kappa * (1 + 1e-12)) << t;
      if (k > 0 && k < 200) {  // derivatives of point()
        const double h = 1e-5 * g.length, h3 = 2e-3 * g.length;
        const core::Vec d1 = (g.point(s + h) - g.point(s - h)) * (0.5 / h);
        const core::Vec d2 = (g.point(s + h) - g.point(s) * 2 + g.point(s - h)) * (1 / (h * h));
        const core::Vec d3 = (g.point(s + 2 * h3) - g.point(s + h3) * 2 + g.point(s - h3) * 2 - g.point(s - 2 * h3)) * (0.5 / (h3 * h3 * h3));
        EXPECT_LT(core::distance(d1, fr.tangent), 1e-6) << t;
        EXPECT_LT(core::distance(d2, fr.curvature), 1e-4 * std::max(1.0, core::norm(fr.curvature))) << t;
        EXPECT_LE(std::hypot(d3[0], d3[1]), ab.k_speed * 1.01 + 1e-3) << t;
      }
    }
  }
  // The interpreter's extremes: radii of 1.3 µm (its zero radius) to 29 µm (its allowance) either
  // way, and fifty turns: finite, unit tangent, exact ends.
  for (const auto& [r0, r1, turns] : {std::tuple{0.00128, 0.0295, 1}, {0.0295, 0.00128, -1}, {0.00128, 0.0295, 50},
                                      {5.0, 5.0 + 1e-12, 1}, {5.0, 5.0 - 1e-12, -50}}) {
    const auto g = make_arc(xy(r0, 0), xy(0, r1), 0, 1, 0, 0, turns);
    ASSERT_TRUE(std::isfinite(g.length) && g.length > 0);
    for (int k = 0; k <= 1000; ++k) {
      const motion::CurveFrame fr = g.frame(g.length * k / 1000);
      EXPECT_NEAR(core::norm(fr.tangent), 1, 1e-12) << r0 << " " << r1 << " " << turns << " k " << k;
      EXPECT_TRUE(std::isfinite(core::norm(fr.curvature)));
    }
    EXPECT_EQ(g.point(g.length), g.end);
    EXPECT_LT(core::distance(g.point(g.length * (1 - 1e-13)), g.end), 1e-9);
  }
}

// The angle at s, in each of the three ways segment.cpp finds it (a circle's linear angle; the
// quadratic root for G-code's slight spirals, dr/dφ within 1e-4 and the opening within 1e-3 of the
// radius; Newton on the closed-form length for the rest): the in-plane length up to the point's own
// angle, integrated here by Simpson's rule in long double, is s's in-plane share to 1e-13.
TEST(Geometry, SpiralPointsLieAtTheirArcLengthToRounding) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int t = 0; t < 300; ++t) {
    const double r0 = 0.05 + 20 * u(rng), sweep = (u(rng) * 2 - 1) * 7, th0 = 6.283 * u(rng);
    const double open = std::pow(10.0, -8 + 8 * u(rng)) * (u(rng) < 0.5 ? -0.9 : 1);  // dr / r0
    const double r1 = r0 * (1 + open), rise = t % 3 ? 0.0 : r0 * (u(rng) * 2 - 1);
    const int turns = (sweep < 0 ? -1 : 1) * (static_cast<int>(std::abs(sweep) / 6.283185307179586) + 1);
    const auto g = make_arc(xy(r0 * std::cos(th0), r0 * std::sin(th0), 0),
                            xy(r1 * std::cos(th0 + sweep), r1 * std::sin(th0 + sweep), rise), 0, 1, 0, 0, turns);
    const long double b = static_cast<long double>(g.dradius) / std::abs(g.sweep), rr0 = g.radius;
    const auto plane_len = [&](long double phi) {  // ∫0^φ √(r² + b²), Simpson, 2000 intervals
      const int n = 2000;
      const long double h = phi / n;
      long double sum = 0;
      for (int k = 0; k <= n; ++k) {
        const long double r = rr0 + b * h * k, f = std::sqrt(r * r + b * b);
        sum += f * (k == 0 || k == n ? 1 : k % 2 ? 4 : 2);
      }
      return sum * h / 3;
    };
    const long double total = plane_len(std::abs(g.sweep));
    EXPECT_NEAR(static_cast<double>(total / (g.plane_rate * g.length)), 1, 1e-14) << t;
    for (int k = 1; k < 8; ++k) {
      const double s = g.length * k / 8;
      const core::Vec p = g.point(s);
      const double sg = g.sweep > 0 ? 1 : -1, expect = std::abs(g.sweep) * k / 8;
      double phi = sg * (std::atan2(p[1], p[0]) - g.theta0);
      phi += 6.283185307179586 * std::round((expect - phi) / 6.283185307179586);
      EXPECT_NEAR(static_cast<double>(plane_len(phi) / total), g.plane_rate * s / static_cast<double>(total), 1e-13)
          << "case " << t << " open " << open << " s " << s;
    }
  }
}

// The planner cuts an arc back where it blends its end: the piece must be the same curve, point
// for point, tangent and curvature included (a spiral helix: radius, angle and height all move).
TEST(Geometry, TrimmedArcIsTheSameCurveBetweenItsCuts) {
  const auto g = make_arc(xy(10, 0, 0), xy(-0.3, 9.7, 4), 0, 1, 0, 0, 1);  // R 10 → ~10.0046, z 0 → 4
  ASSERT_NE(g.dradius, 0);
  const double s0 = 0.3 * g.length, s1 = 0.8 * g.length;
  const auto t = motion::trimmed(g, s0, s1);
  EXPECT_DOUBLE_EQ(t.length, s1 - s0);
  EXPECT_EQ(t.start, g.point(s0));
  EXPECT_EQ(t.end, g.point(s1));
  for (int k = 0; k <= 50; ++k) {
    const double s = t.length * k / 50;
    EXPECT_LT(core::distance(t.point(s), g.point(s0 + s)), 1e-12) << s;
    EXPECT_LT(core::norm(t.tangent(s) - g.tangent(s0 + s)), 1e-12) << s;
    EXPECT_LT(core::norm(t.curvature(s) - g.curvature(s0 + s)), 1e-12) << s;
  }
  const auto l = motion::trimmed(make_line(xy(0, 0), xy(3, 4)), 1, 4);
  EXPECT_DOUBLE_EQ(l.length, 3.0);
  EXPECT_NEAR(core::distance(l.start, xy(0.6, 0.8)), 0, 1e-15);
}
