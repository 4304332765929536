// cutting_table.md T-2: natural and clamped cubic splines through any number of points.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "motion/geometry/cubic_spline.hpp"

using namespace softmc;
using namespace softmc::motion;

namespace {
core::Vec xyz(double x, double y, double z = 0) {
  core::Vec v;
  v[0] = x;
  v[1] = y;
  v[2] = z;
  return v;
}

std::vector<core::Vec> random_points(unsigned seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-50, 50);
  std::vector<core::Vec> p;
  for (int i = 0; i < count; ++i) p.push_back(xyz(d(rng), d(rng), d(rng) / 10));
  return p;
}
}  // namespace

TEST(CuttingTable, T2_NaturalSplinePassesThroughEveryPoint) {
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const auto pts = random_points(seed, 3 + static_cast<int>(seed) * 3);
    const auto r = cubic_spline(pts);
    ASSERT_TRUE(r.ok()) << to_string(r.error);
    // One segment per interval, unless a near-cusp piece was halved for its length table: walk the
    // chain and find every point, in order, at a joint; the chain is unbroken.
    ASSERT_GE(r.segments.size(), pts.size() - 1);
    std::size_t next = 0;
    for (std::size_t i = 0; i < r.segments.size(); ++i) {
      const auto& s = r.segments[i];
      if (i > 0) {
        ASSERT_EQ(r.segments[i - 1].end, s.start);
      }
      if (next < pts.size() && s.point(0) == pts[next]) ++next;
      EXPECT_LT(s.distance_to(s.start), 1e-12);
    }
    EXPECT_EQ(next, pts.size() - 1);
    EXPECT_EQ(r.segments.back().point(r.segments.back().length), pts.back());
  }
}

TEST(CuttingTable, T2_SplineIsC2AcrossItsJoints) {
  const auto pts = random_points(7, 12);
  const auto r = cubic_spline(pts);
  for (std::size_t i = 0; i + 1 < r.segments.size(); ++i) {
    const auto& a = r.segments[i];
    const auto& b = r.segments[i + 1];
    EXPECT_LT(core::distance(a.tangent(a.length), b.tangent(0)), 1e-9) << "joint " << i;
    EXPECT_LT(core::distance(a.curvature(a.length), b.curvature(0)), 1e-9 * (1 + core::norm(b.curvature(0))))
        << "joint " << i;
  }
  // Natural ends: no curvature at the first and the last point.
  EXPECT_LT(core::norm(r.segments.front().curvature(0)), 1e-12);
  EXPECT_LT(core::norm(r.segments.back().curvature(r.segments.back().length)), 1e-12);
}

TEST(CuttingTable, T2_ClampedSplineHasTheGivenEndDerivatives) {
  const std::vector<core::Vec> pts{xyz(0, 0), xyz(10, 5), xyz(20, -5), xyz(30, 0)};
  const ClampedEnds ends{xyz(0, 1), xyz(1, -1)};
  const auto r = cubic_spline(pts, ends);
  ASSERT_TRUE(r.ok());
  const auto& first = r.segments.front();
  const auto& last = r.segments.back();
  // dP/dt with t the chord length: C'(u) = dP/dt · h, h the chord of the piece.
  const double h0 = core::distance(pts[0], pts[1]), h2 = core::distance(pts[2], pts[3]);
  EXPECT_LT(core::distance(first.poly.derivs(0).d1 * (1 / h0), ends.d0), 1e-12);
  EXPECT_LT(core::distance(last.poly.derivs(1).d1 * (1 / h2), ends.d1), 1e-12);
  EXPECT_NEAR(first.tangent(0)[1], 1, 1e-12);
  EXPECT_NEAR(last.tangent(last.length)[0], std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(last.tangent(last.length)[1], -std::sqrt(0.5), 1e-12);
}

TEST(CuttingTable, T2_TwoPointNaturalSplineIsTheStraightLine) {
  const std::vector<core::Vec> pts{xyz(1, 2, 3), xyz(4, 6, 3)};
  const auto r = cubic_spline(pts);
  ASSERT_EQ(r.segments.size(), 1u);
  EXPECT_NEAR(r.segments[0].length, 5, 1e-12);
  EXPECT_LT(r.segments[0].distance_to(xyz(2.5, 4, 3)), 1e-12);
  EXPECT_LT(core::norm(r.segments[0].curvature(2.5)), 1e-12);
}

TEST(CuttingTable, T2_FunctionSplineOverXReproducesACubic) {
  // A clamped spline y(x) with the right end slopes reproduces any cubic exactly.
  auto f = [](double x) { return 0.01 * x * x * x - 0.3 * x * x + 2 * x - 1; };
  auto df = [](double x) { return 0.03 * x * x - 0.6 * x + 2; };
  std::vector<core::Vec> pts;
  for (double x : {0.0, 3.0, 4.5, 10.0, 17.0, 20.0}) pts.push_back(xyz(x, f(x)));
  const auto r = cubic_spline(pts, ClampedEnds{xyz(1, df(0)), xyz(1, df(20))}, std::uint8_t{0});
  ASSERT_TRUE(r.ok());
  for (const auto& s : r.segments)
    for (int i = 0; i <= 50; ++i) {
      const auto p = s.point(s.length * i / 50.0);
      EXPECT_NEAR(p[1], f(p[0]), 1e-9);
    }
}

TEST(CuttingTable, T2_SplineLengthAndEqualSteps) {
  const auto pts = random_points(3, 6);
  const auto r = cubic_spline(pts);
  for (const auto& s : r.segments) {
    // Reference: Richardson-extrapolated chord lengths from the curve's own C(u).
    auto chords = [&](int n) {
      double len = 0;
      core::Vec prev = s.poly.at(0);
      for (int i = 1; i <= n; ++i) {
        const auto p = s.poly.at(static_cast<double>(i) / n);
        len += core::distance(p, prev);
        prev = p;
      }
      return len;
    };
    const double ref = (4 * chords(1 << 15) - chords(1 << 14)) / 3;
    EXPECT_NEAR(s.length / ref - 1, 0, 1e-9);
    const double h = 1e-3;
    core::Vec prev = s.point(0);
    for (double at = h; at < s.length; at += h) {
      const auto p = s.point(at);
      ASSERT_NEAR(core::distance(p, prev), h, 1e-9);
      prev = p;
    }
  }
}

TEST(CuttingTable, T2_SplineRejectsBadInput) {
  EXPECT_EQ(cubic_spline(std::vector<core::Vec>{xyz(0, 0)}).error, CurveError::TooFewPoints);
  EXPECT_EQ(cubic_spline(std::vector<core::Vec>{xyz(0, 0), xyz(0, 0), xyz(1, 0)}).error, CurveError::RepeatedPoint);
  EXPECT_EQ(cubic_spline(std::vector<core::Vec>{xyz(0, 0), xyz(2, 1), xyz(1, 0)}, NaturalEnds{}, std::uint8_t{0}).error,
            CurveError::NotMonotonic);
}
