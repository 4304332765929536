// cutting_table.md T-2: the Newton interpolating polynomial by divided differences.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "motion/geometry/newton_polynomial.hpp"

using namespace softmc;
using namespace softmc::motion;

namespace {
// Lagrange form: an independent evaluation of the interpolating polynomial.
double lagrange(const std::vector<Node2>& n, double x) {
  double sum = 0;
  for (std::size_t i = 0; i < n.size(); ++i) {
    double l = 1;
    for (std::size_t j = 0; j < n.size(); ++j)
      if (j != i) l *= (x - n[j].x) / (n[i].x - n[j].x);
    sum += n[i].y * l;
  }
  return sum;
}

// Length of the graph by chords, Richardson-extrapolated (error ~ 1/N⁴): independent of the library.
double graph_length(const std::vector<Node2>& n) {
  auto chords = [&](int count) {
    const double a = n.front().x, b = n.back().x;
    double len = 0, px = a, py = lagrange(n, a);
    for (int i = 1; i <= count; ++i) {
      const double x = a + (b - a) * i / count, y = lagrange(n, x);
      len += std::hypot(x - px, y - py);
      px = x;
      py = y;
    }
    return len;
  };
  const double l1 = chords(1 << 15), l2 = chords(1 << 16);
  return (4 * l2 - l1) / 3;
}

const std::vector<Node2> kThesis{{10, 11}, {40, 22}, {60, 20}, {90, 5}};
}  // namespace

TEST(CuttingTable, T2_NewtonPolynomialThesisExampleIsExactAtEveryNode) {
  const auto r = newton_polynomial(kThesis);
  ASSERT_TRUE(r.ok()) << to_string(r.error);
  ASSERT_EQ(r.segments.size(), 1u);  // a gentle cubic needs no splitting
  const auto& s = r.segments[0];
  // The thesis's forward differences gave ≈ 11 at x = 90; divided differences give the node.
  EXPECT_NEAR(newton_value(s.poly, 90), 5, 1e-9);
  EXPECT_NEAR(newton_value(s.poly, 10), 11, 1e-9);
  EXPECT_NEAR(newton_value(s.poly, 40), 22, 1e-9);
  EXPECT_NEAR(newton_value(s.poly, 60), 20, 1e-9);
  EXPECT_NEAR(s.start[0], 10, 1e-12);
  EXPECT_NEAR(s.start[1], 11, 1e-9);
  EXPECT_NEAR(s.end[0], 90, 1e-12);
  EXPECT_NEAR(s.end[1], 5, 1e-9);
  // The segment as a path passes through every node.
  for (const auto& n : kThesis) {
    core::Vec p;
    p[0] = n.x;
    p[1] = n.y;
    EXPECT_LT(s.distance_to(p), 1e-9);
  }
}

TEST(CuttingTable, T2_NewtonPolynomialLengthAndArcLengthParameter) {
  const auto r = newton_polynomial(kThesis);
  const auto& s = r.segments.at(0);
  const double ref = graph_length(kThesis);
  EXPECT_NEAR(s.length / ref - 1, 0, 1e-9) << s.length << " vs " << ref;
  // Every interpolated point is on y = p(x), and equal s steps give equal chords.
  const double h = 1e-3;
  core::Vec prev = s.point(0);
  for (double at = h; at < s.length; at += h) {
    const auto p = s.point(at);
    ASSERT_NEAR(p[1], lagrange(kThesis, p[0]), 1e-9);
    ASSERT_NEAR(core::distance(p, prev), h, 1e-9);
    prev = p;
  }
}

TEST(CuttingTable, T2_NewtonPolynomialBoundsContainTheBulge) {
  const auto s = newton_polynomial(kThesis).segments.at(0);
  core::Vec lo, hi;
  s.bounds(lo, hi);
  double ymax = -1e9, ymin = 1e9;
  for (int i = 0; i <= 100000; ++i) {
    const double y = lagrange(kThesis, 10 + 80 * i / 100000.0);
    ymax = std::max(ymax, y);
    ymin = std::min(ymin, y);
  }
  EXPECT_GT(ymax, 22);  // the curve rises above its highest node between 40 and 60
  EXPECT_GE(hi[1], ymax);
  EXPECT_LT(hi[1] - ymax, 1e-8);
  EXPECT_LE(lo[1], ymin);
  EXPECT_LT(ymin - lo[1], 1e-8);
  EXPECT_EQ(lo[0], 10);
  EXPECT_EQ(hi[0], 90);
  EXPECT_EQ(lo[2], 0);
  EXPECT_EQ(hi[2], 0);
}

TEST(CuttingTable, T2_NewtonPolynomialRandomSpacingAndDirection) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> gap(0.5, 12), val(-20, 20);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Node2> n;
    const int count = 2 + trial % 7;  // 2 … 8 nodes
    const bool down = trial % 2;
    double x = 100;
    for (int i = 0; i < count; ++i) {
      n.push_back({x, val(rng)});
      x += down ? -gap(rng) : gap(rng);
    }
    core::Vec base;
    base[2] = 3;  // Z stays put
    const auto r = newton_polynomial(n, base, 0, 1);
    ASSERT_TRUE(r.ok());
    const auto& first = r.segments.front().poly;
    for (const auto& node : n) EXPECT_NEAR(newton_value(first, node.x), node.y, 1e-9 * (1 + std::abs(node.y)));
    // Steep polynomials come in several pieces: consecutive, joined exactly, lengths adding up.
    double total = 0;
    for (std::size_t i = 0; i < r.segments.size(); ++i) {
      const auto& s = r.segments[i];
      total += s.length;
      if (i > 0) {
        EXPECT_EQ(r.segments[i - 1].end, s.start);
      }
      EXPECT_EQ(s.point(s.length / 3)[2], 3);
      for (int k = 0; k <= 20; ++k) {
        const auto p = s.point(s.length * k / 20);
        EXPECT_NEAR(p[1], lagrange(n, p[0]), 1e-9 * (1 + std::abs(p[1])));
      }
    }
    EXPECT_NEAR(r.segments.front().start[0], n.front().x, 0);
    EXPECT_NEAR(r.segments.back().end[0], n.back().x, 0);
    EXPECT_NEAR(total / graph_length(n) - 1, 0, 1e-9);
  }
}

TEST(CuttingTable, T2_NewtonPolynomialRejectsBadNodes) {
  EXPECT_EQ(newton_polynomial(std::vector<Node2>{{1, 1}}).error, CurveError::TooFewPoints);
  EXPECT_EQ(newton_polynomial(std::vector<Node2>{{1, 1}, {1, 2}}).error, CurveError::RepeatedPoint);
  EXPECT_EQ(newton_polynomial(std::vector<Node2>{{1, 1}, {3, 2}, {2, 0}}).error, CurveError::NotMonotonic);
  std::vector<Node2> many;
  for (int i = 0; i < 17; ++i) many.push_back({double(i), 0});
  EXPECT_EQ(newton_polynomial(many).error, CurveError::TooManyPoints);
}
