// The compact segment store: every kind of piece the Channel keeps comes back bit for bit, in a
// third of a Segment's bytes, and reading one back never allocates.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <utility>
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
    // and it behaves as the original, whatever same_bits compares: everything the planner and the
    // interpolator ask of a piece
    const Segment& o = pieces[i];
    EXPECT_EQ(back.length, o.length);
    EXPECT_EQ(back.max_abs_tangent(), o.max_abs_tangent());
    EXPECT_EQ(back.max_curvature(), o.max_curvature());
    Vec lo1, hi1, lo2, hi2;
    back.bounds(lo1, hi1);
    o.bounds(lo2, hi2);
    EXPECT_EQ(lo1, lo2);
    EXPECT_EQ(hi1, hi2);
    if (o.kind == SegmentKind::Arc) {
      EXPECT_EQ(back.max_abs_normal(), o.max_abs_normal());
      EXPECT_EQ(back.arc_bounds().k_speed, o.arc_bounds().k_speed);
      EXPECT_EQ(back.tangent_angles(), o.tangent_angles());
    }
    if (o.kind == SegmentKind::Poly) {
      EXPECT_EQ(back.poly.jerk_speed_term(), o.poly.jerk_speed_term());
    }
    for (const double f : {0.0, 0.3, 0.77, 1.0}) {
      const double s = f * o.length;
      const CurveFrame a = back.frame(s), b = o.frame(s);
      EXPECT_EQ(a.point, b.point);
      EXPECT_EQ(a.tangent, b.tangent);
      EXPECT_EQ(a.curvature, b.curvature);
      EXPECT_EQ(back.point(s), o.point(s));
      EXPECT_EQ(back.distance_to(b.point + v3(0.1, -0.2, 0.05)), o.distance_to(b.point + v3(0.1, -0.2, 0.05)));
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

// same_bits sees a change in any byte of every field (the union by the basis in use): what the
// store's own check relies on. A field added to Segment or PolyCurve fails segment_store.cpp's size
// assertion until it is stored, compared and listed here.
TEST(SegmentStore, SameBitsSeesEveryByteOfEveryField) {
  struct Field {
    const char* name;
    std::size_t offset, size;
  };
#define SEG_FIELD(m) Field{#m, offsetof(Segment, m), sizeof(Segment::m)}
#define POLY_FIELD(m) Field{"poly." #m, offsetof(Segment, poly) + offsetof(PolyCurve, m), sizeof(PolyCurve::m)}
  const std::size_t u = offsetof(Segment, poly) + offsetof(PolyCurve, bez);
#define BEZ_FIELD(m) Field{"poly.bez." #m, u + offsetof(PolyCurve::BezierData, m), sizeof(PolyCurve::BezierData::m)}
#define NEWTON_FIELD(m) Field{"poly.newton." #m, u + offsetof(PolyCurve::NewtonData, m), sizeof(PolyCurve::NewtonData::m)}
  const std::vector<Field> common = {
      SEG_FIELD(kind), SEG_FIELD(start), SEG_FIELD(end), SEG_FIELD(length), SEG_FIELD(dir), SEG_FIELD(axis0),
      SEG_FIELD(axis1), SEG_FIELD(c0), SEG_FIELD(c1), SEG_FIELD(radius), SEG_FIELD(theta0), SEG_FIELD(sweep),
      SEG_FIELD(dradius), SEG_FIELD(plane_rate), SEG_FIELD(linear), POLY_FIELD(basis), POLY_FIELD(degree),
      POLY_FIELD(s_at), POLY_FIELD(box_lo), POLY_FIELD(box_hi), POLY_FIELD(max_abs_tangent),
      POLY_FIELD(max_curvature), POLY_FIELD(max_dcurvature), POLY_FIELD(speed2), POLY_FIELD(speed2_degree),
      POLY_FIELD(has_speed2), POLY_FIELD(gl8_ok), POLY_FIELD(moving), POLY_FIELD(n_moving), POLY_FIELD(poly_axes),
      POLY_FIELD(n_poly_axes)};
  std::vector<Field> bezier = common, newton = common;
  bezier.push_back(BEZ_FIELD(hctrl));
  bezier.push_back(BEZ_FIELD(w));
  for (const Field& f : {NEWTON_FIELD(node_x), NEWTON_FIELD(coef), NEWTON_FIELD(x_begin), NEWTON_FIELD(x_end),
                         NEWTON_FIELD(base), NEWTON_FIELD(x_axis), NEWTON_FIELD(y_axis)})
    newton.push_back(f);
#undef SEG_FIELD
#undef POLY_FIELD
#undef BEZ_FIELD
#undef NEWTON_FIELD
  const std::vector<Node2> nodes = {{0, 0}, {1, 3}, {2, 1}};
  const auto nw = newton_polynomial(nodes);
  ASSERT_EQ(nw.error, CurveError::Ok);
  const Segment cubic = make_cubic_bezier(v3(0, 0), v3(1, 2), v3(3, 2), v3(4, 0));
  std::size_t bytes = 0;
  for (const auto& [piece, fields] : {std::pair{cubic, bezier}, std::pair{nw.segments.at(0), newton}}) {
    for (const Field& f : fields)
      for (std::size_t i = f.offset; i < f.offset + f.size; ++i, ++bytes) {
        Segment t = piece;
        auto* raw = reinterpret_cast<unsigned char*>(&t);
        raw[i] ^= 0x10;
        EXPECT_FALSE(same_bits(piece, t)) << f.name << " byte " << i - f.offset;
      }
  }
  EXPECT_GT(bytes, 2000u);
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

// A smoothed CAM run's cubics (most of a CAM program's pieces) are all kept in the compact form
// (weights, ends, length and |C'|² derived as they are read; the other doubles as their difference
// from a guess) and come back bit for bit, in about half the bytes of the plain form.
TEST(SegmentStore, SmoothedCubicsAreKeptCompactAndComeBackBitForBit) {
  std::vector<Vec> pts;
  for (int k = 0; k <= 2000; ++k)
    pts.push_back(v3(20 + 0.1 * k, 10 + 0.5 * std::floor(k / 1000.0), -1 + 0.5 * std::sin(0.02 * k) * std::cos(0.3)));
  std::vector<std::vector<Segment>> lines;
  smooth_polyline(pts, PolylineSmoothing{}, lines);
  std::vector<Segment> pieces;
  for (const auto& l : lines) pieces.insert(pieces.end(), l.begin(), l.end());
  SegmentStore store;
  std::size_t cubics = 0;
  for (const auto& s : pieces) {
    store.push_back(s);
    cubics += s.kind == SegmentKind::Poly && s.poly.degree == 3;
  }
  ASSERT_GT(cubics, 1900u);
  EXPECT_EQ(store.compact(), cubics);
  EXPECT_EQ(store.whole(), 0u);
  Segment back;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    store.get(i, back);
    ASSERT_TRUE(same_bits(back, pieces[i])) << "piece " << i;
  }
  // 159 bytes a piece when written (590 in the plain form).
  EXPECT_LT(static_cast<double>(store.bytes()) / static_cast<double>(store.size()), 200.0);
}

// A Bézier whose start is not its first control point (nothing builds one, but a Segment may hold
// it) cannot be derived in the compact form: it is kept in the plain form, not whole, and comes
// back bit for bit.
TEST(SegmentStore, WhatTheCompactFormCannotDeriveIsKeptPlain) {
  Segment off = make_cubic_bezier(v3(0, 0, 0), v3(1, 2, 0), v3(3, 2, 0.5), v3(4, 0, 1));
  off.start[0] = 1e-12;
  Segment fine = make_cubic_bezier(v3(0, 0, 0), v3(1, 2, 0), v3(3, 2, 0.5), v3(4, 0, 1));
  SegmentStore store;
  store.push_back(off);
  store.push_back(fine);
  EXPECT_EQ(store.compact(), 1u);
  EXPECT_EQ(store.whole(), 0u);
  EXPECT_TRUE(same_bits(store[0], off));
  EXPECT_TRUE(same_bits(store[1], fine));
}
