// The compact segment store: every kind of piece the Channel keeps comes back bit for bit, in a
// third of a Segment's bytes, and reading one back never allocates.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "alloc_counter.hpp"
#include "motion/geometry/bezier.hpp"
#include "motion/geometry/cubic_spline.hpp"
#include "motion/geometry/newton_polynomial.hpp"
#include "motion/geometry/nurbs.hpp"
#include "motion/geometry/polyline_smoothing.hpp"
#include "motion/geometry/segment_store.hpp"

using namespace softmc;
using namespace softmc::motion;

namespace {
Vec v3(double x, double y, double z = 0) {
  Vec v;
  v[0] = x;
  v[1] = y;
  v[2] = z;
  return v;
}

// Every piece kind the Channel stores, built by the code that builds them at load.
std::vector<Segment> every_kind() {
  std::vector<Segment> out;
  out.push_back(make_line(v3(0, 0, 0), v3(3, 4, -1)));
  out.push_back(make_line(v3(1, 1, 1), v3(1, 1, 1)));  // zero length
  out.push_back(make_arc(v3(10, 0, 0), v3(0, 10, 0), 0, 1, 0, 0, 1));
  out.push_back(make_arc(v3(10, 0, 0), v3(-10, 0, 5), 0, 1, 0, 0, 2));   // helix, two turns
  out.push_back(make_arc(v3(0, 10, 0), v3(0, 0, 10.0004), 1, 2, 0, 0, -1));  // YZ, its end off the circle
  out.push_back(trimmed(make_arc(v3(10, 0, 0), v3(0, 10, 0), 0, 1, 0, 0, 1), 1, 5));
  out.push_back(make_cubic_bezier(v3(0, 0, 0), v3(1, 2, 0), v3(3, 2, 0.5), v3(4, 0, 1)));
  out.push_back(g5_cubic_spline(v3(0, 0), v3(10, 5), 2, 3, -2, 4));
  out.push_back(g5_1_quadratic(v3(0, 0), v3(10, 0), 5, 5));
  const std::vector<Vec> ctrl = {v3(0, 0), v3(5, 10), v3(10, -10), v3(15, 0)};
  const std::vector<double> w = {1, 2, 0.5, 1};
  const auto rational = make_rational_bezier(ctrl, w);
  EXPECT_TRUE(rational.ok());
  out.push_back(rational.segment);
  const auto nu = nurbs_g5_2(std::vector<Vec>{v3(0, 0), v3(10, 0), v3(10, 10), v3(0, 10), v3(0, 20)},
                             std::vector<double>{1, 1, 2, 1, 1}, 3);
  EXPECT_EQ(nu.error, CurveError::Ok);
  out.insert(out.end(), nu.segments.begin(), nu.segments.end());
  // The thesis's Newton polynomial (cutting_table.md T-2: y = 5 at x = 90) at z = -1.
  const std::vector<Node2> nodes = {{0, 0}, {45, 10}, {90, 5}, {135, 20}};
  const auto nw = newton_polynomial(nodes, v3(0, 0, -1));
  EXPECT_EQ(nw.error, CurveError::Ok);
  out.insert(out.end(), nw.segments.begin(), nw.segments.end());
  const auto sp = cubic_spline(std::vector<Vec>{v3(0, 0), v3(3, 1), v3(6, -1), v3(9, 2)});
  EXPECT_EQ(sp.error, CurveError::Ok);
  out.insert(out.end(), sp.segments.begin(), sp.segments.end());
  // A smoothed CAM run: 0.25 mm lines over a wave in X and Z.
  std::vector<Vec> pts;
  for (int k = 0; k <= 200; ++k) pts.push_back(v3(0.25 * k, 0.1 * std::sin(0.05 * k), -2 + std::sin(0.02 * k)));
  std::vector<std::vector<Segment>> lines;
  smooth_polyline(pts, PolylineSmoothing{}, lines);
  for (const auto& l : lines) out.insert(out.end(), l.begin(), l.end());
  return out;
}
}  // namespace

TEST(SegmentStore, EveryKindOfPieceComesBackBitForBitInAThirdOfItsSize) {
  const auto pieces = every_kind();
  ASSERT_GT(pieces.size(), 200u);
  SegmentStore store;
  for (const auto& s : pieces) store.push_back(s);
  ASSERT_EQ(store.size(), pieces.size());
  EXPECT_EQ(store.whole(), 0u);  // none needed to be kept whole
  Segment back = make_cubic_bezier(v3(9, 9), v3(8, 8), v3(7, 7), v3(6, 6));  // overwritten entirely
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    store.get(i, back);
    ASSERT_TRUE(same_bits(back, pieces[i])) << "piece " << i;
    // and it behaves as the original: the same points, tangents and curvatures
    for (const double f : {0.0, 0.3, 0.77, 1.0}) {
      const double s = f * pieces[i].length;
      EXPECT_EQ(back.point(s), pieces[i].point(s));
      EXPECT_EQ(back.tangent(s), pieces[i].tangent(s));
      EXPECT_EQ(back.curvature(s), pieces[i].curvature(s));
    }
  }
  // The smoothed run's cubics on three axes are most of the pieces: under 600 bytes each on average
  // against sizeof(Segment).
  EXPECT_LT(static_cast<double>(store.bytes()) / static_cast<double>(store.size()), 600.0);
  EXPECT_GT(sizeof(Segment), 1400u);
}

// A piece with a field its kind does not use (a line with a Poly table left in it) is kept whole, and
// comes back as it was; a piece that moves the ninth axis keeps all nine; same_bits sees the sign of
// a zero on one axis, and an array's entry past its count.
TEST(SegmentStore, WhatTheCompactFormWouldLoseIsKeptWhole) {
  Segment odd = make_line(v3(0, 0), v3(1, 0));
  odd.poly.s_at[3] = 2.5;  // a line never reads it, but a copy keeps it
  Vec w0 = v3(0, 0), w3 = v3(3, 0);
  w0[8] = 1;
  w3[8] = 2;
  Segment ninth = make_cubic_bezier(w0, v3(1, 1), v3(2, 1), w3);
  SegmentStore store;
  store.push_back(odd);
  store.push_back(ninth);
  EXPECT_EQ(store.whole(), 1u);
  Segment back;
  store.get(0, back);
  EXPECT_TRUE(same_bits(back, odd));
  store.get(1, back);
  EXPECT_TRUE(same_bits(back, ninth));

  Segment a = make_line(v3(0, 0), v3(1, 0)), b = a;
  EXPECT_TRUE(same_bits(a, b));
  b.start[8] = -0.0;
  EXPECT_FALSE(same_bits(a, b));
  b = a;
  b.poly.moving[7] = 1;  // past its count
  EXPECT_FALSE(same_bits(a, b));
}

TEST(SegmentStore, ReadingAPieceBackNeverAllocates) {
  const auto pieces = every_kind();
  SegmentStore store;
  for (const auto& s : pieces) store.push_back(s);
  Segment back;
  const long before = softmc::testing::allocation_count();
  double sum = 0;
  for (std::size_t i = 0; i < store.size(); ++i) {
    store.get(i, back);
    sum += back.length;
  }
  EXPECT_EQ(softmc::testing::allocation_count(), before);
  EXPECT_GT(sum, 0);
}
