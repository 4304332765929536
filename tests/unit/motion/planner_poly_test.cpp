// Poly segments (Bézier pieces) through planner and interpolator: segment_limits uses the curve's
// sampled per-axis tangent and curvature maxima, so no axis limit is exceeded on curves.
#include <gtest/gtest.h>

#include <cstdlib>
#include <random>

#include "motion/geometry/bezier.hpp"
#include "motion/geometry/nurbs.hpp"
#include "planner_run.hpp"

using namespace softmc;
using namespace softmc::motion;
using namespace softmc::motion::testing;

TEST(PlannerPoly, LimitsComeFromTheCurveNotTheArcBranch) {
  const auto lim = xyz_limits(100, 1000);
  // A flat S: mostly X, so Y's share (its largest tangent component) is small.
  const Segment s = make_cubic_bezier(xyz(0, 0), xyz(10, 1), xyz(20, -1), xyz(30, 0));
  const auto sl = segment_limits(s, lim);
  const Vec t = s.max_abs_tangent();
  EXPECT_NEAR(sl.v_max_mm_s, std::min(100 / t[0], std::sqrt(0.8 * 1000 / s.max_curvature())), 1e-9);
  EXPECT_GT(sl.v_max_mm_s, 0);
  EXPECT_TRUE(std::isfinite(sl.a_max_mm_s2));
}

// A piece that could go faster than its feed at the highest override ever asks (v_target) keeps only
// the centripetal and curvature-jerk shares that speed needs: its cap is that speed, and the rest goes
// to the acceleration and jerk along the path (the planner passes feed × max_feed_override). A
// target above what the curve allows changes nothing.
TEST(PlannerPoly, AGentleCurveTradesTheCentripetalShareItDoesNotNeed) {
  auto lim = xyz_limits(100, 1000);
  for (int i = 0; i < 3; ++i) lim.axis[i].j_max_mm_s3 = 10000;
  const Segment s = make_cubic_bezier(xyz(0, 0), xyz(10, 1), xyz(20, -1), xyz(30, 0));
  const auto full = segment_limits(s, lim);
  ASSERT_GT(full.v_max_mm_s, 40);
  const auto sl = segment_limits(s, lim, 0.8, 30, false);  // 3·v·a_t·κ: the plain sum's share
  EXPECT_NEAR(sl.v_max_mm_s, 30, 1e-9);
  const double k = s.max_curvature(), t = s.max_abs_tangent()[0];
  EXPECT_NEAR(sl.a_max_mm_s2, std::min((1 - k * 30 * 30 / 1000) * 1000 / t, 0.2 * 10000 / (3 * 30 * k)), 1e-9);
  EXPECT_GT(sl.a_max_mm_s2, 1.5 * segment_limits(s, lim, 0.8, 1e300, false).a_max_mm_s2);
  // The speed terms of the jerk, v³·dκ/ds (κ the curvature vector: its −κ²·T part included).
  const double sk = 30.0 * 30 * 30 * s.poly.max_dcurvature / 10000;
  EXPECT_NEAR(sl.j_max_mm_s3, (0.8 - sk) * 10000 / t, 1e-6);
  EXPECT_GT(sl.j_max_mm_s3, 1.15 * full.j_max_mm_s3);  // full: planned for the axes' 100 mm/s
  const auto high = segment_limits(s, lim, 0.8, 1e6);
  EXPECT_EQ(high.v_max_mm_s, full.v_max_mm_s);
  EXPECT_EQ(high.a_max_mm_s2, full.a_max_mm_s2);
  EXPECT_EQ(high.j_max_mm_s3, full.j_max_mm_s3);
}

// The jerk vector along a curve is j_t·T + 3·v·a_t·κ⃗ + v³·dκ⃗/ds, with T ⟂ κ⃗ and dκ⃗/ds = −κ²·T + n⃗
// (n⃗ ⟂ T): an axis sees at most its length, √((|j_t| + v³κ²)² + (3·v·a_t·κ + v³|n⃗|)²) ≤
// v³·|dκ⃗/ds| + √(j_t² + (3·v·a_t·κ)²). Where that leaves 3·v·a_t·κ more of j_max than the plain sum
// of the shares (|j_t|·T_i + v³·|dκ⃗/ds| + 3·v·a_t·κ), the piece gets that much more acceleration:
// here, at the axes' 100 mm/s, 803 mm/s² along it instead of 338. The cap and the tangential jerk
// are the sum's.
TEST(PlannerPoly, CurvesTakeTheTangentialAccelerationTheJerkNormLeaves) {
  auto lim = xyz_limits(100, 1000);
  for (int i = 0; i < 3; ++i) lim.axis[i].j_max_mm_s3 = 10000;
  const Segment s = make_cubic_bezier(xyz(0, 0), xyz(10, 1), xyz(20, -1), xyz(30, 0));
  const auto sum = segment_limits(s, lim, 0.8, 1e300, false);
  const auto norm = segment_limits(s, lim);
  EXPECT_EQ(norm.v_max_mm_s, sum.v_max_mm_s);
  EXPECT_EQ(norm.j_max_mm_s3, sum.j_max_mm_s3);
  const double j = 10000, v = norm.v_max_mm_s, k = s.max_curvature(), k3 = s.poly.jerk_speed_term();
  const double share_v = v * v * v * k3 / j, share_t = norm.j_max_mm_s3 / j;  // of each axis's j_max
  double u = 1;  // the least over the axes the curve moves of the larger bound
  for (int i : {0, 1}) {
    const double plain = 1 - share_t * s.max_abs_tangent()[static_cast<std::size_t>(i)] - share_v;
    u = std::min(u, std::max(plain, std::sqrt((1 - share_v) * (1 - share_v) - share_t * share_t)));
  }
  const double a_axes = (1 - k * v * v / 1000) * 1000 / s.max_abs_tangent()[0];  // the acceleration's own share
  EXPECT_NEAR(norm.a_max_mm_s2, std::min(a_axes, u * j / (3 * v * k)), 1e-9);
  EXPECT_GT(u, 0.4);
  EXPECT_GT(norm.a_max_mm_s2, 2 * sum.a_max_mm_s2);
}

TEST(PlannerPoly, RandomBezierChainsKeepEveryLimit) {
  // Tame pieces (no loops or cusps, where the geometry's own length table is coarser): the control
  // points lie ahead along the chord, offset sideways by less than the chord.
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {  // each run checks every sample against the curve: ~2 s
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-20, 20);
    for (const double jerk : {0.0, 30000.0}) {
      auto lim = xyz_limits(50 + std::abs(u(rng)) * 5, 500 + std::abs(u(rng)) * 100);
      for (int i = 0; i < 3; ++i) lim.axis[i].j_max_mm_s3 = jerk;
      std::vector<PathRequest> reqs;
      core::Vec at = xyz(0, 0);
      for (int k = 0; k < 6; ++k) {
        const core::Vec p3 = at + xyz(10 + std::abs(u(rng)), u(rng));
        const core::Vec chord = p3 - at;
        const core::Vec side = xyz(-chord[1], chord[0]) * 0.02;
        const core::Vec p1 = at + chord * 0.33 + side * u(rng), p2 = at + chord * 0.66 + side * u(rng);
        PathRequest r;
        r.geom = make_cubic_bezier(at, p1, p2, p3);
        r.feed_mm_s = 20 + std::abs(u(rng)) * 10;
        r.tag = static_cast<std::uint32_t>(k);
        reqs.push_back(r);
        at = p3;
      }
      const auto res = run_path(lim, reqs, 64);
      ASSERT_EQ(res.error, PlanResult::Ok) << seed;
      ASSERT_TRUE(res.finished) << seed;
      // The curve limits are sampled maxima (dense, not a proof): 1 % slack for what falls between samples.
      EXPECT_LE(res.fig.v_ratio, 1.01) << "seed " << seed << " jerk " << jerk << ": " << res.fig.describe();
      EXPECT_LE(res.fig.a_ratio, 1.01) << "seed " << seed << " jerk " << jerk << ": " << res.fig.describe();
      // Jerk: the planner's bound holds v³·dκ/ds of the curvature vector (since 2026-12-02; up to
      // 1.17× here before) and gives 3·v·a_t·κ what the jerk vector's norm leaves (stop 14).
      if (jerk > 0) {
        EXPECT_LE(res.fig.j_ratio, 1.01) << "seed " << seed << ": " << res.fig.describe();
      }
      EXPECT_LE(res.fig.deviation_mm, 1e-6) << "seed " << seed << ": " << res.fig.describe();
      EXPECT_EQ(res.end, reqs.back().geom.end);
      if (HasFailure()) return;
    }
  }
}

// A NURBS whose last control points double back along X on Y = 5 (a fuzzer's G5.2 block) has a
// cusp: C' passes through 0 and the curve reverses on a line, where the curvature is 0 on both sides
// (C' ∥ C''), so no sampled limit saw it and the path crossed it at speed: X's jerk 627× its 60
// mm/s³ (605× on this shorter one). The curve is now split at the cusp (append_rational_bezier), the pieces arrive and leave in
// opposite directions (Segment::tangent at a stationary end), and the planner stops there.
TEST(PlannerPoly, NurbsCuspIsAReversalNotCrossedAtSpeed) {
  MachineLimits lim = xyz_limits(250, 2000);
  for (int i = 0; i < 3; ++i) lim.axis[i].j_max_mm_s3 = 50000;
  lim.axis[0].j_max_mm_s3 = 60;
  const std::vector<core::Vec> ctrl = {xyz(420, 8),      xyz(425.783947, 8.220495), xyz(444.207815, 5),
                                       xyz(438.461971, 12.380027), xyz(436.177679, 5), xyz(432.164157, 5),
                                       xyz(440.046766, 5)};
  const std::vector<double> w = {1, 1, 2.077, 2.9, 1, 1, 1};
  const auto c = nurbs_g5_2(ctrl, w, 3);
  ASSERT_TRUE(c.ok());
  // One junction where the tangent reverses, on Y = 5 between X 432 and 440.
  int reversals = 0;
  for (std::size_t k = 0; k + 1 < c.segments.size(); ++k) {
    const auto& a = c.segments[k];
    const auto& b = c.segments[k + 1];
    if (core::dot(a.tangent(a.length), b.tangent(0)) < -0.999) {
      ++reversals;
      EXPECT_NEAR(a.end[1], 5, 1e-9);
    }
  }
  EXPECT_EQ(reversals, 1);
  std::vector<PathRequest> reqs;
  for (std::size_t k = 0; k < c.segments.size(); ++k) {
    PathRequest r;
    r.geom = c.segments[k];
    r.feed_mm_s = 50;
    r.tag = static_cast<std::uint32_t>(k);
    r.tolerance_mm = 0.05;
    reqs.push_back(r);
  }
  const auto res = run_path(lim, reqs, 64, {}, {}, 1'000'000);
  ASSERT_TRUE(res.finished);
  EXPECT_LE(res.fig.j_ratio, 1 + 1e-4) << res.fig.describe();
  EXPECT_LE(res.fig.a_ratio, 1 + 1e-4) << res.fig.describe();
  EXPECT_LE(res.fig.deviation_mm, 0.05) << res.fig.describe();
  EXPECT_EQ(res.end, ctrl.back());
}

// P-5: a stop lets the curves ahead use the limits their geometry allows at the speed the path has
// (Planner::limit_for_stop). A Poly piece planned for its cap gets a larger acceleration and jerk,
// capped at that speed, in the same ratio segment_limits gives at that speed; asked again at the same
// speed nothing moves (no compounding), at a lower one they rise further, never fall; lines keep
// theirs, and nothing changes while the path still accelerates.
TEST(PlannerPoly, P5_AStopRaisesACurvesLimitsToWhatItsSpeedAllows) {
  auto lim = xyz_limits(100, 1000);
  for (int i = 0; i < 3; ++i) lim.axis[i].j_max_mm_s3 = 10000;
  Planner planner(lim, 64);
  const Segment curve = make_cubic_bezier(xyz(10, 0), xyz(13, 0), xyz(16, 1.5), xyz(18, 4));
  PathRequest line = line_req(xyz(0, 0), xyz(10, 0), 100, 0);
  PathRequest bend;
  bend.geom = curve;
  bend.feed_mm_s = 100;
  bend.tag = 1;
  bend.mergeable = false;
  ASSERT_EQ(planner.push(line), PlanResult::Ok);
  ASSERT_EQ(planner.push(bend), PlanResult::Ok);
  planner.flush();
  auto& ring = planner.queue().ring();
  std::size_t k = ring.size();
  for (std::size_t i = 0; i < ring.size(); ++i)
    if (ring.at(i).seg.kind == SegmentKind::Poly && ring.at(i).length > 1) k = i;
  ASSERT_LT(k, ring.size());
  const Block before = ring.at(k), line_before = ring.at(0);
  ASSERT_GT(before.v_cap_mm_s, 20);
  // 0.5 mm before the curve (9.5 mm into the line, the front block): within reach of any brake.
  const auto changes = ring.changes();
  planner.limit_for_stop(20, 50, 9.5);  // still accelerating: nothing yet
  EXPECT_EQ(ring.at(k).a_mm_s2, before.a_mm_s2);
  EXPECT_EQ(ring.changes(), changes);
  planner.limit_for_stop(20, -10, 9.5);
  const Block at20 = ring.at(k);
  const auto l_cap = segment_limits(curve, lim, planner.config().centripetal_share, 200);
  const auto l_20 = segment_limits(curve, lim, planner.config().centripetal_share, 20);
  EXPECT_EQ(at20.v_cap_mm_s, 20);
  EXPECT_NEAR(at20.a_mm_s2, before.a_mm_s2 * l_20.a_max_mm_s2 / l_cap.a_max_mm_s2, 1e-9 * at20.a_mm_s2);
  EXPECT_GT(at20.a_mm_s2, 1.2 * before.a_mm_s2);
  EXPECT_GE(at20.j_mm_s3, before.j_mm_s3);
  EXPECT_NE(ring.changes(), changes);  // the guard's index begins again
  EXPECT_EQ(ring.at(0).a_mm_s2, line_before.a_mm_s2);  // a line keeps its limits
  planner.limit_for_stop(20, -10, 9.5);
  EXPECT_EQ(ring.at(k).a_mm_s2, at20.a_mm_s2);  // the same speed again: the same limits
  EXPECT_EQ(ring.at(k).j_mm_s3, at20.j_mm_s3);
  planner.limit_for_stop(5, -10, 9.5);
  EXPECT_GT(ring.at(k).a_mm_s2, at20.a_mm_s2);
  EXPECT_GE(ring.at(k).j_mm_s3, at20.j_mm_s3);
  EXPECT_EQ(ring.at(k).v_cap_mm_s, 5);
  // A feed hold brakes the same way, and the blocks stay: at rest they take back what they were
  // planned with, to the bit, before the path goes on (Planner::restore_limits).
  EXPECT_TRUE(planner.limits_raised());
  const auto raised = ring.changes();
  planner.restore_limits();
  EXPECT_FALSE(planner.limits_raised());
  EXPECT_NE(ring.changes(), raised);  // the guard's index begins again
  EXPECT_EQ(ring.at(k).v_cap_mm_s, before.v_cap_mm_s);
  EXPECT_EQ(ring.at(k).v_split_mm_s, before.v_split_mm_s);
  EXPECT_EQ(ring.at(k).a_mm_s2, before.a_mm_s2);
  EXPECT_EQ(ring.at(k).j_mm_s3, before.j_mm_s3);
  EXPECT_EQ(ring.at(k).law.root(400, 2), before.law.root(400, 2));
  EXPECT_EQ(ring.at(0).a_mm_s2, line_before.a_mm_s2);
  const auto restored = ring.changes();
  planner.restore_limits();  // nothing raised since: nothing walked, nothing changed
  EXPECT_EQ(ring.changes(), restored);
  planner.limit_for_stop(20, -10, 9.5);  // raised again from the planned limits, not compounded
  EXPECT_EQ(ring.at(k).a_mm_s2, at20.a_mm_s2);
  EXPECT_EQ(ring.at(k).j_mm_s3, at20.j_mm_s3);
}

// A curve entered or left at rest (exact stops on both sides here) can never run faster than it
// reaches from rest within its length, whatever its cap: its limits are derived for that speed, a
// cap it never meets, with the tangential acceleration and jerk the curvature terms leave there
// (Planner::limit_to_reach; docs/planner.md, "Blocks at rest"). Every limit kept in the trace, and
// the curve is crossed quicker than with the limits of its cap.
TEST(PlannerPoly, ACurveEnteredOrLeftAtRestTakesTheLimitsOfTheSpeedItReaches) {
  auto lim = xyz_limits(100, 1000);
  for (int i = 0; i < 3; ++i) lim.axis[i].j_max_mm_s3 = 10000;
  PathRequest hook;
  // An arc of R20 through 0.05 rad as a Bézier: its cap is the feed, its length 1 mm.
  const double th = 0.05, h = 4.0 / 3 * std::tan(th / 4) * 20;
  const core::Vec p3 = xyz(10 + 20 * std::sin(th), 20 - 20 * std::cos(th));
  hook.geom = make_cubic_bezier(xyz(10, 0), xyz(10 + h, 0), xyz(p3[0] - h * std::cos(th), p3[1] - h * std::sin(th)), p3);
  hook.feed_mm_s = 100;
  hook.tag = 1;
  hook.tolerance_mm = 0;
  hook.mergeable = false;
  const std::vector<PathRequest> reqs{line_req(xyz(10, -10), xyz(10, 0), 100, 0, 0), hook,
                                      line_req(p3, p3 + xyz(0, 10), 100, 2, 0)};
  const auto curve_block = [&](const PlannerConfig& pc) {
    Planner planner(lim, 64, pc);
    for (const auto& r : reqs) EXPECT_EQ(planner.push(r), PlanResult::Ok);
    planner.flush();
    for (std::size_t i = 0; i < planner.queue().ring().size(); ++i)
      if (planner.queue().ring().at(i).seg.kind == SegmentKind::Poly) return planner.queue().ring().at(i);
    ADD_FAILURE() << "no curve block";
    return Block{};
  };
  PlannerConfig off;
  off.limit_to_reach = false;
  const Block on_b = curve_block({}), off_b = curve_block(off);
  EXPECT_EQ(on_b.v2_junction, 0.0);  // entered at rest
  EXPECT_LT(on_b.v_cap_mm_s, 0.8 * off_b.v_cap_mm_s);
  EXPECT_GT(on_b.a_mm_s2, 1.2 * off_b.a_mm_s2);
  EXPECT_GT(on_b.j_mm_s3, 1.2 * off_b.j_mm_s3);
  // The cap it got is at least what it reaches from rest with the limits it got (never met).
  const double A = on_b.a_mm_s2, J = on_b.j_mm_s3, L = on_b.length;
  const double d1 = A * A * A / (6 * J * J);
  const double reach = L <= d1 ? 0.5 * J * std::pow(6 * L / J, 2.0 / 3.0)
                               : std::sqrt(A * A * A * A / (4 * J * J) + 2 * A * (L - d1));
  EXPECT_GE(on_b.v_cap_mm_s, reach);
  EXPECT_LT(on_b.v_cap_mm_s, 1.01 * reach);
  const auto on = run_path(lim, reqs, 64);
  const auto slow = run_path(lim, reqs, 64, off);
  ASSERT_TRUE(on.finished && slow.finished);
  for (const auto* r : {&on, &slow}) {
    EXPECT_LE(r->fig.v_ratio, 1 + 1e-9) << r->fig.describe();
    EXPECT_LE(r->fig.a_ratio, 1 + 1e-6) << r->fig.describe();
    EXPECT_LE(r->fig.j_ratio, 1 + 1e-3) << r->fig.describe();
    EXPECT_LE(r->block_v_ratio, 1 + 1e-9);
  }
  // Cap 100 → 32.9 mm/s, acceleration 340 → 946 mm/s², jerk 5 500 → 7 911 mm/s³: 796 cycles against 816.
  EXPECT_LT(on.cycles + 15, slow.cycles) << on.cycles << " against " << slow.cycles;
}

namespace {
// 24 short Bézier curves, each turning up to ±max_turn, with exact-stop corners (0.5–2 rad) before
// about three in ten of them, feeds 40–100 mm/s: the chains of the tests below.
std::vector<PathRequest> curve_chain(std::uint64_t seed, double max_turn) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<PathRequest> reqs;
  core::Vec at = xyz(0, 0);
  double heading = 0;
  for (int k = 0; k < 24; ++k) {
    const bool stop = u(rng) < 0.3;
    if (stop) heading += (u(rng) < 0.5 ? -1 : 1) * (0.5 + 1.5 * u(rng));  // a corner: an exact stop
    const double len = 0.2 + 3 * u(rng) * u(rng), turn = (u(rng) * 2 - 1) * max_turn;  // short
    const double h = 4.0 / 3 * std::tan(turn / 4) * (len / std::max(1e-9, std::abs(turn)));
    const core::Vec d0 = xyz(std::cos(heading), std::sin(heading));
    const core::Vec p3 = at + xyz(std::cos(heading + turn / 2), std::sin(heading + turn / 2)) * len;
    const core::Vec d1 = xyz(std::cos(heading + turn), std::sin(heading + turn));
    const double hl = std::abs(turn) > 1e-6 ? std::abs(h) : len / 3;  // handles of an arc through `turn`
    PathRequest r;
    r.geom = make_cubic_bezier(at, at + d0 * hl, p3 - d1 * hl, p3);
    r.feed_mm_s = 40 + 60 * u(rng);
    r.tag = static_cast<std::uint32_t>(k);
    r.tolerance_mm = stop ? 0 : -1;
    r.mergeable = false;
    reqs.push_back(r);
    at = p3;
    heading += turn;
  }
  return reqs;
}
MachineLimits jerk_xyz() {
  auto lim = xyz_limits(100, 1000);
  for (int i = 0; i < 3; ++i) lim.axis[i].j_max_mm_s3 = 10000;
  return lim;
}
}  // namespace

// Chains of short curves with exact stops here and there, streamed into short windows, so that a
// stop often arrives while the path already runs through the curves before it: the caps those
// curves then get (their reach before the stop) are never under the path, and every limit holds
// (the trace against the axes, the path speed against the executing block's cap).
TEST(PlannerPoly, CurvesLimitedToTheirReachAtStopsKeepEveryLimit) {
  double t_on = 0, t_off = 0;
  const auto lim = jerk_xyz();
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const auto reqs = curve_chain(seed, 0.6);
    for (const std::size_t cap : {std::size_t{3}, std::size_t{8}, std::size_t{64}}) {
      for (const bool reach : {true, false}) {
        PlannerConfig pc;
        pc.limit_to_reach = reach;
        const auto res = run_path(lim, reqs, cap, pc);
        const std::string what = "seed " + std::to_string(seed) + " window " + std::to_string(cap) + (reach ? " reach" : "");
        ASSERT_EQ(res.error, PlanResult::Ok) << what;
        ASSERT_TRUE(res.finished) << what;
        EXPECT_LE(res.fig.v_ratio, 1.01) << what << ": " << res.fig.describe();
        EXPECT_LE(res.fig.a_ratio, 1.01) << what << ": " << res.fig.describe();
        EXPECT_LE(res.fig.j_ratio, 1.01) << what << ": " << res.fig.describe();
        EXPECT_LE(res.block_v_ratio, 1 + 1e-9) << what;
        EXPECT_LE(res.block_a_ratio, 1 + 1e-6) << what;
        EXPECT_LE(res.fig.deviation_mm, 1e-6) << what << ": " << res.fig.describe();
        EXPECT_EQ(res.end, reqs.back().geom.end) << what;
        (reach ? t_on : t_off) += static_cast<double>(res.cycles);
      }
      if (HasFailure()) return;
    }
  }
  EXPECT_LT(t_on, 0.99 * t_off) << t_on << " cycles against " << t_off;
  std::printf("curves at stops: %.0f cycles limited to their reach, %.0f with the limits of their caps\n", t_on, t_off);
}


// The block the planner committed last is not planned with while more may follow (PlanQueue::
// visible): the next commit may lower its jerk by what the curvature step at their junction takes.
// The simulated fallback brake π reads the blocks' jerk every cycle, so a state it accepted in a
// window of 2–3 blocks then had no brake within the lowered limit (seeds 78 and 172: 4.8× and 3.7×
// an axis's jerk). With the back held out until the next block or the flush, every limit holds in
// either guard mode.
TEST(PlannerPoly, TheOpenBackBlockIsNotPlannedWithSoATinyWindowKeepsEveryLimit) {
  const auto lim = jerk_xyz();
  {
    Planner p(lim, 64);
    const auto reqs = curve_chain(1, 0.6);
    ASSERT_EQ(p.push(reqs[0]), PlanResult::Ok);
    ASSERT_EQ(p.push(reqs[1]), PlanResult::Ok);
    ASSERT_EQ(p.push(reqs[2]), PlanResult::Ok);
    EXPECT_GE(p.queue().ring().size(), 2u);
    EXPECT_EQ(p.queue().visible(), p.queue().ring().size() - 1);
    p.flush();
    EXPECT_EQ(p.queue().visible(), p.queue().ring().size());
  }
  for (const std::uint64_t seed : {78u, 172u, 5u, 6u}) {
    const auto reqs = curve_chain(seed, 1.5);
    for (const std::size_t window : {std::size_t{2}, std::size_t{3}}) {
      for (const bool simulate : {true, false}) {
        PlannerConfig pc;
        pc.limit_to_reach = !simulate;  // as softmc runs each mode
        InterpolatorConfig ic;
        ic.guard_simulate = simulate;
        const auto res = run_path(lim, reqs, window, pc, {}, 2'000'000, ic);
        const std::string what = "seed " + std::to_string(seed) + " window " + std::to_string(window) +
                                 (simulate ? " simulated" : " certificate");
        ASSERT_TRUE(res.finished) << what;
        EXPECT_LE(res.fig.v_ratio, 1 + 1e-6) << what << ": " << res.fig.describe();
        EXPECT_LE(res.fig.a_ratio, 1 + 1e-6) << what << ": " << res.fig.describe();
        EXPECT_LE(res.fig.j_ratio, 1 + 1e-6) << what << ": " << res.fig.describe();
        EXPECT_LE(res.block_v_ratio, 1 + 1e-9) << what;
        EXPECT_EQ(res.end, reqs.back().geom.end) << what;
      }
    }
  }
}
