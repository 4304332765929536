// NURBS (LinuxCNC G5.2/G5.3) as rational Bézier segments: exact conics, agreement with de Boor.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "motion/geometry/bezier.hpp"
#include "motion/geometry/nurbs.hpp"

using namespace softmc;
using namespace softmc::motion;

namespace {
core::Vec xy(double x, double y) {
  core::Vec v;
  v[0] = x;
  v[1] = y;
  return v;
}

// Cox–de Boor basis, straight from the definition: an independent NURBS evaluator.
double basis(const std::vector<double>& u, int i, int p, double t) {
  if (p == 0) {
    const bool last_span = u[i + 1] == u.back() && t == u.back() && u[i] < u[i + 1];
    return (u[i] <= t && t < u[i + 1]) || last_span ? 1 : 0;
  }
  double a = 0, b = 0;
  if (u[i + p] > u[i]) a = (t - u[i]) / (u[i + p] - u[i]) * basis(u, i, p - 1, t);
  if (u[i + p + 1] > u[i + 1]) b = (u[i + p + 1] - t) / (u[i + p + 1] - u[i + 1]) * basis(u, i + 1, p - 1, t);
  return a + b;
}
core::Vec nurbs_point(const std::vector<core::Vec>& c, const std::vector<double>& w, const std::vector<double>& u,
                      int p, double t) {
  core::Vec num;
  double den = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const double b = basis(u, static_cast<int>(i), p, t) * w[i];
    num = num + c[i] * b;
    den += b;
  }
  return num * (1 / den);
}
}  // namespace

TEST(GeometryNurbs, G5_2_QuarterCircleWithWeightsIsExact) {
  // Centre (20, 30), R = 10: control points (30,30), (30,40), (20,40), weights 1, √2/2, 1, order 3.
  const std::vector<core::Vec> c{xy(30, 30), xy(30, 40), xy(20, 40)};
  const std::vector<double> w{1, std::sqrt(0.5), 1};
  const auto r = nurbs_g5_2(c, w, 3);
  ASSERT_TRUE(r.ok()) << to_string(r.error);
  ASSERT_EQ(r.segments.size(), 1u);
  const auto& s = r.segments[0];
  EXPECT_NEAR(s.length / (10 * std::numbers::pi / 2) - 1, 0, 1e-9);
  for (int i = 0; i <= 1000; ++i) {
    const auto p = s.point(s.length * i / 1000.0);
    EXPECT_NEAR(std::hypot(p[0] - 20, p[1] - 30), 10, 1e-9);
    EXPECT_NEAR(core::norm(s.curvature(s.length * i / 1000.0)), 0.1, 1e-9);
  }
  // Arc-length parameter: a step h along a circle has the chord 2R·sin(h / 2R), exactly.
  const double h = 0.05;
  for (double at = 0; at + h <= s.length; at += h)
    EXPECT_NEAR(core::distance(s.point(at), s.point(at + h)), 20 * std::sin(h / 20), 1e-9);
  // Half way along is at 45°.
  const auto mid = s.point(s.length / 2);
  EXPECT_NEAR(mid[0], 20 + 10 * std::sqrt(0.5), 1e-9);
  core::Vec lo, hi;
  s.bounds(lo, hi);
  EXPECT_NEAR(lo[0], 20, 1e-9);
  EXPECT_NEAR(hi[0], 30, 1e-9);
  EXPECT_NEAR(hi[1], 40, 1e-9);
  EXPECT_NEAR(s.distance_to(xy(20, 30)), 10, 1e-9);
}

TEST(GeometryNurbs, FullCircleFromNinePoints) {
  // The classic 9-point circle: degree 2, double interior knots (already Bézier form).
  const double r2 = std::sqrt(0.5);
  const std::vector<core::Vec> c{xy(1, 0), xy(1, 1), xy(0, 1), xy(-1, 1), xy(-1, 0), xy(-1, -1), xy(0, -1), xy(1, -1), xy(1, 0)};
  const std::vector<double> w{1, r2, 1, r2, 1, r2, 1, r2, 1};
  const std::vector<double> u{0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};
  const auto r = nurbs(c, w, 2, u);
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r.segments.size(), 4u);
  double total = 0;
  for (const auto& s : r.segments) {
    total += s.length;
    for (int i = 0; i <= 100; ++i) EXPECT_NEAR(core::norm(s.point(s.length * i / 100.0)), 1, 1e-12);
  }
  EXPECT_NEAR(total / (2 * std::numbers::pi) - 1, 0, 1e-9);
}

// The pieces of a NURBS against de Boor's algorithm: at least one per non-empty knot span (halved
// where a cusp, the length table or a lower speed cap asks for it: append_rational_bezier), chained
// end to start, every interior knot's point a piece's end, and 20 points of every span on a piece.
static void expect_pieces_on_de_boor(const CurveResult& r, const std::vector<core::Vec>& c, const std::vector<double>& w,
                                     const std::vector<double>& knots, int degree) {
  std::vector<double> spans;
  for (std::size_t k = static_cast<std::size_t>(degree); k + static_cast<std::size_t>(degree) < knots.size(); ++k)
    if (spans.empty() || knots[k] > spans.back()) spans.push_back(knots[k]);
  ASSERT_GE(r.segments.size(), spans.size() - 1);
  for (std::size_t k = 0; k + 1 < r.segments.size(); ++k) EXPECT_EQ(r.segments[k].end, r.segments[k + 1].start);
  const auto nearest = [&](const core::Vec& p, bool ends) {
    double d = 1e9;
    for (const auto& g : r.segments) d = std::min(d, ends ? core::distance(g.end, p) : g.distance_to(p));
    return d;
  };
  for (std::size_t j = 0; j + 1 < spans.size(); ++j) {
    if (j > 0) {
      EXPECT_LT(nearest(nurbs_point(c, w, knots, degree, spans[j]), true), 1e-12) << "knot " << spans[j];
    }
    for (int i = 0; i <= 20; ++i)
      EXPECT_LT(nearest(nurbs_point(c, w, knots, degree, spans[j] + i / 20.0 * (spans[j + 1] - spans[j])), false), 1e-12)
          << "span " << j << " at " << i / 20.0;
  }
}

TEST(GeometryNurbs, G5_2_LinuxCncExampleMatchesDeBoor) {
  // G0 X0 Y0 / G5.2 P1 L3 / X0 Y1 P1 / X2 Y2 P1 / X2 Y0 P1 / X0 Y0 P2 / G5.3
  const std::vector<core::Vec> c{xy(0, 0), xy(0, 1), xy(2, 2), xy(2, 0), xy(0, 0)};
  const std::vector<double> w{1, 1, 1, 1, 2};
  const auto knots = g5_2_knots(c.size(), 3);
  EXPECT_EQ(knots, (std::vector<double>{0, 0, 0, 1, 2, 3, 3, 3}));
  const auto r = nurbs_g5_2(c, w, 3);
  ASSERT_TRUE(r.ok());
  expect_pieces_on_de_boor(r, c, w, knots, 2);
  EXPECT_EQ(r.segments.front().start, c.front());
  EXPECT_EQ(r.segments.back().end, c.back());
}

TEST(GeometryNurbs, CubicNurbsWithUnevenKnotsMatchesDeBoor) {
  const std::vector<core::Vec> c{xy(0, 0), xy(1, 3), xy(4, 4), xy(6, 1), xy(9, 2), xy(10, 6), xy(12, 0)};
  const std::vector<double> w{1, 0.5, 2, 1, 3, 0.7, 1};
  const std::vector<double> u{0, 0, 0, 0, 0.1, 0.5, 0.5, 1.3, 1.3, 1.3, 1.3};
  const auto r = nurbs(c, w, 3, u);
  ASSERT_TRUE(r.ok()) << to_string(r.error);
  expect_pieces_on_de_boor(r, c, w, u, 3);
}

TEST(GeometryNurbs, RejectsBadInput) {
  const std::vector<core::Vec> c{xy(0, 0), xy(1, 1), xy(2, 0)};
  EXPECT_EQ(nurbs_g5_2(c, std::vector<double>{1, -1, 1}, 3).error, CurveError::BadWeight);
  EXPECT_EQ(nurbs_g5_2(c, std::vector<double>{1, 1, 1}, 4).error, CurveError::TooFewPoints);
  EXPECT_EQ(nurbs_g5_2(c, std::vector<double>{1, 1, 1}, 9).error, CurveError::BadDegree);
  EXPECT_EQ(nurbs(c, std::vector<double>{1, 1, 1}, 2, std::vector<double>{0, 0, 1, 1, 1, 1}).error, CurveError::BadKnots);
}

// A 100 mm span whose bend is all at its end (a fuzzer's NURBS crawled minutes at the cap of that
// end): halved while one half gets a far lower curvature (split_pays, as the smoothing's pieces),
// so the planner's one cap per piece is that of the bend only where it is.
TEST(GeometryNurbs, ALongPieceBentAtOneEndIsSplit) {
  const std::vector<core::Vec> c{xy(0, 0), xy(60, 0), xy(100, 0), xy(100, 2)};
  const std::vector<double> w{1, 1, 1, 1};
  const auto whole = make_rational_bezier(c, w);
  ASSERT_TRUE(whole.ok());
  const auto r = nurbs(c, w, 3, std::vector<double>{0, 0, 0, 0, 1, 1, 1, 1});
  ASSERT_TRUE(r.ok());
  ASSERT_GT(r.segments.size(), 2u);
  EXPECT_LT(r.segments.front().poly.max_curvature, 0.4 * whole.segment.poly.max_curvature);
  // The bend stays in the last piece (the curvature is sampled: within a percent).
  EXPECT_NEAR(r.segments.back().poly.max_curvature, whole.segment.poly.max_curvature, 0.01 * whole.segment.poly.max_curvature);
  double length = 0;
  for (const auto& g : r.segments) length += g.length;
  EXPECT_NEAR(length, whole.segment.length, 1e-9 * whole.segment.length);
}

// A review's G5.2 of order 4 doubling back on itself twice (weights 1 and 3): its cusp tips, where
// the speed nearly stops, had their length tables halved to a relative 1e-10 down to pieces of
// 1e-14 mm (747 pieces, 662 under a nanometre, 1.3 s to build). A table is now accurate enough
// within 1e-12 mm too, and grading a sharp end counts apart from those halvings: 145 pieces, still
// one after another and the same length.
TEST(GeometryNurbs, T2_ACuspTipIsNotSplitIntoHundredsOfPieces) {
  const std::vector<core::Vec> c{xy(50.092563, 49.847194), xy(50.438131, 49.052842), xy(50.092572, 49.847187),
                                 xy(50.438135, 49.052848), xy(50.092571, 49.847192), xy(50.438128, 49.052847)};
  const std::vector<double> w{1, 1, 3, 3, 1, 1};
  const auto r = nurbs_g5_2(c, w, 4);
  ASSERT_EQ(r.error, CurveError::Ok);
  EXPECT_LT(r.segments.size(), 200u) << r.segments.size();
  double total = 0;
  for (std::size_t i = 0; i < r.segments.size(); ++i) {
    total += r.segments[i].length;
    if (i > 0) {
      EXPECT_LE(core::distance(r.segments[i - 1].end, r.segments[i].start), 1e-9) << i;
    }
  }
  EXPECT_NEAR(total, 1.4223787897, 1e-8);
}
