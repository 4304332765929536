// PlannerJerk, corners: quintic and curve blends, fillets, nanometre zigzags, near reversals, trapezoid/jerk hand-overs.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "motion/interp/jerk_follower.hpp"
#include "planner_jerk_support.hpp"

using namespace softmc;
using namespace softmc::motion;
using namespace softmc::motion::testing;

// Corner blends in jerk mode (docs/planner.md, "Corner blends"): a circular blend's curvature
// steps from 0 to 1/R where it meets each line, and one cycle's share of jerk caps the corner
// speed at √(kink_share·j·dt·R) (under 1 mm/s at a 90° corner with P = 0.05 and 10 000 mm/s³).
// The curvature-continuous quintic has no step: a staircase of 90° corners 5 mm apart takes 12 % less time (3565 vs 4040 cycles when written), within every
// limit and P. With a high jerk the arc's step costs little and its acceleration
// (a Poly piece keeps less of it along the path) wins: the planner keeps the arc there.
TEST(PlannerJerk, CurvatureContinuousCornersBeatArcsWhereTheJerkIsLow) {
  std::vector<PathRequest> reqs;
  for (int k = 0; k < 8; ++k) {
    const double x = 5.0 * ((k + 1) / 2), y = 5.0 * (k / 2);
    const core::Vec a = xyz(x, y), b = k % 2 ? xyz(x, y + 5) : xyz(x + 5, y);
    reqs.push_back(line_req(a, b, 100, static_cast<std::uint32_t>(k), 0.05));
  }
  const auto blends = [&](const MachineLimits& lim, const PlannerConfig& pc, int& quintics, int& arcs) {
    Planner planner(lim, 64, pc);
    for (const auto& r : reqs) ASSERT_EQ(planner.push(r), PlanResult::Ok);
    planner.flush();
    quintics = arcs = 0;
    for (std::size_t k = 0; k < planner.queue().ring().size(); ++k) {
      const Block& b = planner.queue().ring().at(k);
      quintics += !b.is_blend && b.seg.kind == SegmentKind::Poly;
      arcs += b.is_blend;
    }
  };
  // Every corner blended (these 90° corners would be stops: "Blend or stop", the next test).
  PlannerConfig blend_all;
  blend_all.corner_stop_when_quicker = false;
  PlannerConfig arcs_only = blend_all;
  arcs_only.g2_blend_min_rad = 1e9;
  const auto lim = jerk_limits(100, 1000, 10000);
  int q = 0, a = 0;
  blends(lim, blend_all, q, a);
  EXPECT_EQ(q, 7);
  EXPECT_EQ(a, 0);
  const auto g2 = run_path(lim, reqs, 64, blend_all);
  const auto arc = run_path(lim, reqs, 64, arcs_only);
  expect_within(g2, 0.05, "quintic corners");
  expect_within(arc, 0.05, "arc corners");
  EXPECT_EQ(g2.end, reqs.back().geom.end);
  EXPECT_LT(static_cast<double>(g2.cycles), 0.95 * static_cast<double>(arc.cycles)) << g2.cycles << " vs " << arc.cycles;
  blends(jerk_limits(100, 1000, 2'000'000), blend_all, q, a);
  EXPECT_EQ(q, 0);
  EXPECT_EQ(a, 7);
}

// Blend or stop (docs/planner.md): under a jerk limit a sharp corner's blend is slow (a 90° quintic
// within P0.05 at 10 000 mm/s³: 3.7 mm/s), and the path must slow to it at the blend's lower jerk
// and speed up again, so stopping on the corner can be quicker. The planner times both from the
// corner to the middle of each line and takes the quicker: on these zigzags the run is never slower
// than exact stops (G61, P = 0), and where the blends pay they are kept. Measured when written
// (`softmc run` at F6000 on these limits, seconds, P0.05 / every corner blended / G61): 90° corners
// 10 mm apart 12.721 / 15.022 / 12.721; 45° corners 1 mm apart 4.480 / 4.480 / 5.601.
TEST(PlannerJerk, ACornerIsAStopWhereStoppingIsQuickerThanItsBlend) {
  const auto lim = jerk_limits(100, 1000, 10000);
  const auto zigzag = [](double turn_deg, double leg, double tol) {
    std::vector<PathRequest> reqs;
    core::Vec at = xyz(0, 0);
    double th = 0;
    for (int k = 0; k < 40; ++k) {
      const core::Vec to = at + xyz(leg * std::cos(th), leg * std::sin(th));
      reqs.push_back(line_req(at, to, 100, static_cast<std::uint32_t>(k), tol));
      at = to;
      th += (k % 2 ? -1 : 1) * turn_deg * std::numbers::pi / 180;
    }
    return reqs;
  };
  PlannerConfig blend_all;
  blend_all.corner_stop_when_quicker = false;
  const auto curves = [&](const std::vector<PathRequest>& reqs, const PlannerConfig& pc) {
    Planner planner(lim, 512, pc);
    for (const auto& r : reqs) EXPECT_EQ(planner.push(r), PlanResult::Ok);
    planner.flush();
    int n = 0;
    for (std::size_t k = 0; k < planner.queue().ring().size(); ++k) n += planner.queue().ring().at(k).seg.kind == SegmentKind::Poly;
    return n;
  };
  // 90° corners between 10 mm lines: stops, as quick as G61; blended they cost 18 % more.
  const auto sharp = zigzag(90, 10, 0.05);
  EXPECT_EQ(curves(sharp, {}), 0);
  EXPECT_GT(curves(sharp, blend_all), 30);
  const auto chosen = run_path(lim, sharp, 64);
  const auto blended = run_path(lim, sharp, 64, blend_all);
  const auto stops = run_path(lim, zigzag(90, 10, 0), 64);
  expect_within(chosen, 0.05, "90° chosen");
  expect_within(blended, 0.05, "90° blended");
  EXPECT_LE(chosen.cycles, stops.cycles + 1) << chosen.cycles << " vs " << stops.cycles;
  EXPECT_GT(blended.cycles, 1.1 * static_cast<double>(stops.cycles)) << blended.cycles << " vs " << stops.cycles;
  EXPECT_EQ(chosen.end, sharp.back().geom.end);
  // 45° corners between 1 mm lines: the blends pay and are kept.
  const auto short_legs = zigzag(45, 1, 0.05);
  EXPECT_GT(curves(short_legs, {}), 30);
  const auto kept = run_path(lim, short_legs, 64);
  const auto stops45 = run_path(lim, zigzag(45, 1, 0), 64);
  expect_within(kept, 0.05, "45° kept");
  EXPECT_LT(kept.cycles, 0.85 * static_cast<double>(stops45.cycles)) << kept.cycles << " vs " << stops45.cycles;
}

// Gentle corners between long lines (5° every 10 mm: not smoothed, the spline would leave P) take
// the quintic too (PlannerConfig::g2_blend_min_rad 0.01 rad, 0.1 before): a 5° arc blend within
// P0.05 has R 52 mm, but its curvature steps cap it at 11 mm/s; on the quintics the path reaches
// 83 mm/s between corners. Measured when written: 5 099 cycles, against 12 722 stopping at each
// corner and 28 070 on arcs.
TEST(PlannerJerk, GentleCornersBetweenLongLinesAreCrossedOnQuintics) {
  const auto lim = jerk_limits(100, 1000, 10000);
  std::vector<PathRequest> reqs, stops;
  core::Vec at = xyz(0, 0);
  double th = 0;
  for (int k = 0; k < 40; ++k) {
    const core::Vec to = at + xyz(10 * std::cos(th), 10 * std::sin(th));
    reqs.push_back(line_req(at, to, 100, static_cast<std::uint32_t>(k), 0.05));
    stops.push_back(line_req(at, to, 100, static_cast<std::uint32_t>(k), 0));
    at = to;
    th += (k % 2 ? -1 : 1) * 5 * std::numbers::pi / 180;
  }
  const auto run = run_path(lim, reqs, 64);
  const auto stopped = run_path(lim, stops, 64);
  expect_within(run, 0.05, "5° corners");
  EXPECT_GT(run.max_path_v, 80);
  EXPECT_LT(run.cycles, 0.5 * static_cast<double>(stopped.cycles)) << run.cycles << " vs " << stopped.cycles;
  EXPECT_EQ(run.end, reqs.back().geom.end);
}

// A line into a tangent arc steps the curvature from 0 to 1/R: unblended, every axis's acceleration
// would step by v²/R in one cycle, so the junction allows only √(kink_share·j·dt·R) (1.1 mm/s at
// R 0.5 and 10 000 mm/s³: a pocket's corner arcs). With P the step is replaced by a quintic that
// ramps the curvature within P (the arc and the line are cut back), crossed several times faster.
// (Fillets off: this arc between two lines would otherwise become one quintic, the next tests'.)
TEST(PlannerJerk, TangentCurvatureStepsAreBlendedWithinP) {
  const auto lim = jerk_limits(100, 1000, 10000);
  PlannerConfig pc;
  pc.fillet_share = 0;
  const auto path = [](double tol) {
    std::vector<PathRequest> reqs{line_req(xyz(0, 0), xyz(10, 0), 100, 0, tol)};
    PathRequest arc = arc_req(make_arc(xyz(10, 0), xyz(12, 2), 0, 1, 10, 2, 1), 100, 1);  // R2 quarter, tangent
    arc.tolerance_mm = tol;
    reqs.push_back(arc);
    reqs.push_back(line_req(xyz(12, 2), xyz(12, 12), 100, 2, tol));
    return reqs;
  };
  double v_min = 1e9;  // slowest between leaving the first line's middle and reaching the last one's
  const auto hook = [&](std::uint64_t, Interpolator& in) {
    const auto& p = in.setpoint().pos;
    if (p[0] > 5 && p[1] < 7) v_min = std::min(v_min, in.setpoint().path_v);
  };
  const auto blended = run_path(lim, path(0.05), 64, pc, hook);
  const double v_blended = v_min;
  v_min = 1e9;
  const auto stepped = run_path(lim, path(0), 64, pc, hook);
  expect_within(blended, 0.05, "blended");
  expect_within(stepped, 0, "stepped");
  EXPECT_GT(blended.fig.deviation_mm, 0.005);
  EXPECT_LT(v_min, std::sqrt(0.25 * 10000 * 0.001 * 2) + 0.01);  // the step's speed, 1.58 mm/s
  EXPECT_GT(v_blended, 3 * v_min);
  EXPECT_LT(blended.cycles, stepped.cycles);
  EXPECT_EQ(blended.end, xyz(12, 12));
}

// Under a jerk limit a corner's quintic (or an arc) allows a fraction of its lines' tangential
// acceleration (the 3·v·a_t·κ share of the jerk): a 30° corner at P 0.05 gets 44.5 mm/s² against
// 1000. Every fallback brake that is one ramp to rest must then brake at that low acceleration
// from far ahead, or stop before the corner: the follower crept into it from rest. The gated
// certificate (JerkGuard::certify_gated: ramp to the corner's cap on the line's limits, then to
// rest from there) lets it brake on the line and enter at the corner's cap.
TEST(PlannerJerk, LowAccelerationBlocksAreEnteredAtTheirCapNotFromRest) {
  const auto lim = jerk_limits(100, 1000, 10000);
  const std::vector<PathRequest> reqs{line_req(xyz(0, 0), xyz(10, 0), 100, 0, 0.05),
                                      line_req(xyz(10, 0), xyz(20, 10 * std::tan(std::numbers::pi / 6)), 100, 1, 0.05)};
  PlannerConfig blend_all;  // this corner would be a stop ("Blend or stop"): its blend is what is tested
  blend_all.corner_stop_when_quicker = false;
  double cap = 0, a_corner = 0;
  {
    Planner planner(lim, 16, blend_all);
    for (const auto& r : reqs) ASSERT_EQ(planner.push(r), PlanResult::Ok);
    planner.flush();
    for (std::size_t k = 0; k < planner.queue().ring().size(); ++k) {
      const Block& b = planner.queue().ring().at(k);
      if (b.seg.kind == SegmentKind::Poly) cap = b.v_cap_mm_s, a_corner = b.a_mm_s2;
    }
  }
  ASSERT_GT(cap, 5);
  ASSERT_LT(a_corner, 100);  // the low acceleration this is about
  double v_min = 1e9;  // slowest from the first line's middle to the second's
  const auto hook = [&](std::uint64_t, Interpolator& in) {
    if (in.setpoint().pos[0] > 5 && in.setpoint().pos[0] < 15) v_min = std::min(v_min, in.setpoint().path_v);
  };
  const auto gated = run_path(lim, reqs, 16, blend_all, hook);
  const double v_gated = v_min;
  v_min = 1e9;
  InterpolatorConfig plain;
  plain.guard_gate = false;
  const auto ramp = run_path(lim, reqs, 16, blend_all, hook, 20'000'000, plain);
  expect_within(gated, 0.05, "gated");
  expect_within(ramp, 0.05, "one ramp");
  EXPECT_GT(v_gated, 0.9 * cap);
  // Without the gate: far below the cap before the corner (0.22 of it; < 0.1, nearly at rest, until
  // the follower eased its brakes at the jerk of the block it is in).
  EXPECT_LT(v_min, 0.3 * cap);
  EXPECT_LT(gated.cycles, 0.85 * ramp.cycles) << gated.cycles << " vs " << ramp.cycles;
  EXPECT_EQ(gated.end, reqs.back().geom.end);
}

// A straight run into a sharp corner (surfacing.ngc's passes start and end so): the line brakes at
// its jerk (10 000 mm/s³), the corner's quintic allows 3 000 and a few mm/s². Every candidate eased
// the brake at the corner's jerk, and the guard (certificate and π both taking the jerk of every
// block in π's scan) refused those states or kept them on a 3 000 ramp to rest: the path stopped
// just before the quintic (0.0003 mm/s) and crept in at its acceleration, 261 cycles from 1 mm
// before the corner to 0.1 mm past it. Now the corner is a gate of the certificate when its jerk is
// far lower (a brake to its cap on the line's limits, then to rest in it), and the follower eases
// its brake at the jerk of the block it is in: it enters the corner at its cap, in 165 cycles.
TEST(PlannerJerk, AStraightRunEntersASharpLowJerkCornerAtItsCap) {
  const auto lim = jerk_limits(100, 1000, 10'000);
  const core::Vec corner = xyz(0, 0, 0), out = xyz(0.25, 0, 0.137);  // 119° from the run down
  const core::Vec e = corner + out * (0.15 / core::norm(out));
  const std::vector<PathRequest> reqs{line_req(xyz(0, 0, 8), corner, 100, 0, 0.05),
                                      line_req(corner, e, 100, 1, 0.05),
                                      line_req(e, e + xyz(3, 0, 0), 100, 2, 0.05)};
  PlannerConfig blend_all;  // the corner would be a stop ("Blend or stop"): its blend is what is tested
  blend_all.corner_stop_when_quicker = false;
  double cap = 0, a_corner = 0, j_corner = 0, j_line = 0;
  {
    Planner planner(lim, 16, blend_all);
    for (const auto& r : reqs) ASSERT_EQ(planner.push(r), PlanResult::Ok);
    planner.flush();
    const auto& ring = planner.queue().ring();
    ASSERT_GE(ring.size(), 2u);
    ASSERT_EQ(ring.at(1).seg.kind, SegmentKind::Poly);  // the corner's quintic after the run
    j_line = ring.at(0).j_mm_s3;
    cap = ring.at(1).v_cap_mm_s, a_corner = ring.at(1).a_mm_s2, j_corner = ring.at(1).j_mm_s3;
  }
  ASSERT_LT(j_corner, 0.5 * j_line);  // what this is about: a far lower jerk ...
  ASSERT_LT(a_corner, 20);            // ... and acceleration in the corner
  ASSERT_LT(cap, 2);
  // Each of the two alone enters the corner at its cap (so each is pinned here); without both the
  // path stops short of it and creeps in.
  for (const auto& [jerk_gate, ease] : {std::pair{true, true}, {true, false}, {false, true}, {false, false}}) {
    SCOPED_TRACE(::testing::Message() << "jerk gate " << jerk_gate << ", eased brake " << ease);
    InterpolatorConfig ic;
    ic.guard_jerk_gate = jerk_gate;
    ic.ease_brake = ease;
    double v_min = 1e9;  // slowest from 1 mm before the corner until just past it
    std::uint64_t from = 0, to = 0;
    const auto hook = [&](std::uint64_t cycle, Interpolator& in) {
      const auto& p = in.setpoint().pos;
      if (p[2] < 1 && p[0] < 0.01) v_min = std::min(v_min, in.setpoint().path_v);
      if (p[2] < 1 && from == 0) from = cycle;
      if (p[0] > 0.1 && to == 0) to = cycle;
    };
    const auto res = run_path(lim, reqs, 16, blend_all, hook, 20'000'000, ic);
    expect_within(res, 0.05, "a run into a sharp corner");
    EXPECT_LE(res.block_v_ratio, 1 + 1e-9);  // every block's own limits too
    EXPECT_LE(res.block_a_ratio, 1 + 1e-6);
    EXPECT_LE(res.block_j_ratio, 1 + 1e-4);
    EXPECT_EQ(res.end, reqs.back().geom.end);
    if (jerk_gate || ease) {
      EXPECT_GT(v_min, 0.9 * cap) << "cap " << cap;       // 0.0003 mm/s before
      EXPECT_LT(to - from, 200u) << from << " to " << to;  // 261 cycles before
    } else {
      EXPECT_LT(v_min, 0.01 * cap);
      EXPECT_GT(to - from, 240u);
    }
  }
}

// The blends at arcs continue each neighbour with its position, unit tangent and curvature vector
// (make_g2_blend): the planned blocks join with no step of either, so no axis's acceleration steps
// at a junction (a G1-only blend would pass the limits only through the junction's speed limit).
TEST(PlannerJerk, CurveBlendsJoinTheirNeighboursWithTheirCurvature) {
  const auto lim = jerk_limits(100, 1000, 10000);
  std::vector<PathRequest> reqs{line_req(xyz(0, 0), xyz(10, 0), 100, 0, 0.05)};
  PathRequest arc = arc_req(make_arc(xyz(10, 0), xyz(12, 2), 0, 1, 10, 2, 1), 100, 1);  // tangent R2
  arc.tolerance_mm = 0.05;
  reqs.push_back(arc);
  // A corner: on at 20° to the arc's end tangent (+y).
  reqs.push_back(line_req(xyz(12, 2), xyz(12 - 10 * std::sin(0.35), 2 + 10 * std::cos(0.35)), 100, 2, 0.05));
  PlannerConfig pc;
  pc.fillet_share = 0;  // the blends at the arc, not the fillet that would replace it
  Planner planner(lim, 16, pc);
  for (const auto& r : reqs) ASSERT_EQ(planner.push(r), PlanResult::Ok);
  planner.flush();
  const auto& ring = planner.queue().ring();
  std::size_t poly = 0;
  for (std::size_t k = 0; k + 1 < ring.size(); ++k) {
    const Block& a = ring.at(k);
    const Block& b = ring.at(k + 1);
    poly += b.seg.kind == SegmentKind::Poly;
    EXPECT_LT(core::distance(a.end(), b.start()), 1e-12) << k;
    EXPECT_LT(core::norm(a.tangent(a.length) - b.tangent(0)), 1e-9) << k;
    const core::Vec ka = a.curvature(a.length), kb = b.curvature(0);
    EXPECT_LT(core::norm(ka - kb), 1e-6 * std::max(1.0, core::norm(ka))) << k << ": " << core::norm(ka) << " vs " << core::norm(kb);
  }
  EXPECT_EQ(poly, 2u);  // the tangent step and the corner were both blended
}

// A pocket's corner: a line, a tangent quarter arc of R 0.5 and a line. Under a jerk limit the arc
// is entered through curvature steps (1.1 mm/s unblended, 3.3 mm/s through the quintics that ramp
// its curvature within P); held until the line after it arrives, it becomes one quintic from line
// to line within 0.95·P of line, arc and line (Planner::fillet), run at its own cap (8.9 mm/s at
// P 0.05, 10 000 mm/s³: the arc's own is 7.9). The blocks join with position, tangent and zero
// curvature; every limit is kept and the corner takes far less time.
// A pocket's corner at P 0.05: a 10 mm line along +x, a tangent R0.5 quarter arc at `arc_feed`,
// a 10 mm line along +y (F100 both).
static std::vector<PathRequest> pocket_corner(double arc_feed) {
  std::vector<PathRequest> reqs{line_req(xyz(0, 0), xyz(10, 0), 100, 0, 0.05)};
  PathRequest arc = arc_req(make_arc(xyz(10, 0), xyz(10.5, 0.5), 0, 1, 10, 0.5, 1), arc_feed, 1);
  arc.tolerance_mm = 0.05;
  reqs.push_back(arc);
  reqs.push_back(line_req(xyz(10.5, 0.5), xyz(10.5, 10.5), 100, 2, 0.05));
  return reqs;
}

TEST(PlannerJerk, FilletArcsBecomeOneQuinticWithinP) {
  const auto lim = jerk_limits(100, 1000, 10000);
  const auto reqs = pocket_corner(100);
  const auto blocks = [&](const PlannerConfig& pc) {
    Planner planner(lim, 16, pc);
    for (const auto& r : reqs) EXPECT_EQ(planner.push(r), PlanResult::Ok);
    EXPECT_FALSE(planner.queue().empty());  // the arc is held, the line pending
    planner.flush();
    std::vector<Block> out;
    for (std::size_t k = 0; k < planner.queue().ring().size(); ++k) out.push_back(planner.queue().ring().at(k));
    return out;
  };
  PlannerConfig off;
  off.fillet_share = 0;
  const auto f = blocks({});
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f[0].seg.kind, SegmentKind::Line);
  EXPECT_EQ(f[1].seg.kind, SegmentKind::Poly);
  EXPECT_EQ(f[2].seg.kind, SegmentKind::Line);
  EXPECT_GT(f[1].v_cap_mm_s, 8.5);
  EXPECT_EQ(f[1].tag, 0u);
  EXPECT_EQ(f[1].tag_last, 2u);
  for (std::size_t k = 0; k + 1 < f.size(); ++k) {
    EXPECT_LT(core::distance(f[k].end(), f[k + 1].start()), 1e-12) << k;
    EXPECT_LT(core::norm(f[k].tangent(f[k].length) - f[k + 1].tangent(0)), 1e-12) << k;
    EXPECT_LT(core::norm(f[k].curvature(f[k].length) - f[k + 1].curvature(0)), 1e-9) << k;
  }
  const auto g = blocks(off);
  ASSERT_EQ(g.size(), 3u);  // the arc, entered and left through curvature steps
  EXPECT_EQ(g[1].seg.kind, SegmentKind::Arc);
  double v_min = 1e9;       // slowest over the corner
  const auto hook = [&](std::uint64_t, Interpolator& in) {
    const auto& p = in.setpoint().pos;
    if (p[0] > 9 && p[1] < 1.5) v_min = std::min(v_min, in.setpoint().path_v);
  };
  const auto filleted = run_path(lim, reqs, 16, {}, hook);
  const double v_fillet = v_min;
  v_min = 1e9;
  const auto arcs = run_path(lim, reqs, 16, off, hook);
  expect_within(filleted, 0.05, "fillet");
  expect_within(arcs, 0.05, "arc");
  EXPECT_GT(filleted.fig.deviation_mm, 0.04);  // the band is used
  EXPECT_GT(v_fillet, 0.9 * f[1].v_cap_mm_s);
  EXPECT_LT(v_min, 4.0);
  EXPECT_LT(filleted.cycles + 150, arcs.cycles) << filleted.cycles << " vs " << arcs.cycles;
  EXPECT_EQ(filleted.end, xyz(10.5, 10.5));
}

// A held arc that cannot become a fillet is planned as it would have been: the program ends on it
// (flush), an arc follows it, the line after it reverses, or P is 0 (G61: not even held). Each
// keeps its arc block, and the queue counts the held arc while it waits.
TEST(PlannerJerk, HeldArcIsPlannedOnItsOwnWhereNoFilletFits) {
  const auto lim = jerk_limits(100, 1000, 10000);
  const auto quarter = [](double tol) {
    PathRequest arc = arc_req(make_arc(xyz(10, 0), xyz(10.5, 0.5), 0, 1, 10, 0.5, 1), 100, 1);
    arc.tolerance_mm = tol;
    return arc;
  };
  PathRequest arc2 = arc_req(make_arc(xyz(10.5, 0.5), xyz(10, 1), 0, 1, 10, 0.5, 1), 100, 2);
  arc2.tolerance_mm = 0.05;
  const std::vector<std::vector<PathRequest>> cases{
      {line_req(xyz(0, 0), xyz(10, 0), 100, 0, 0.05), quarter(0.05)},
      {line_req(xyz(0, 0), xyz(10, 0), 100, 0, 0.05), quarter(0.05), arc2},
      {line_req(xyz(0, 0), xyz(10, 0), 100, 0, 0.05), quarter(0.05), line_req(xyz(10.5, 0.5), xyz(10.5, -5), 100, 2, 0.05)},
      {line_req(xyz(0, 0), xyz(10, 0), 100, 0, 0), quarter(0), line_req(xyz(10.5, 0.5), xyz(10.5, 10.5), 100, 2, 0)}};
  for (std::size_t c = 0; c < cases.size(); ++c) {
    Planner planner(lim, 32);
    for (std::size_t k = 0; k < cases[c].size(); ++k) {
      ASSERT_EQ(planner.push(cases[c][k]), PlanResult::Ok) << c;
      if (k > 1) continue;
      EXPECT_EQ(planner.queue().size(), k + 1) << c << " " << k;  // staged, pending, held or committed
      if (k == 1) {
        EXPECT_EQ(planner.queue().ring().size(), c == 3 ? 1u : 0u) << c;  // held: the line stays pending
      }
    }
    planner.flush();
    std::size_t arcs = 0;
    for (std::size_t k = 0; k < planner.queue().ring().size(); ++k) arcs += planner.queue().ring().at(k).seg.kind == SegmentKind::Arc;
    EXPECT_GE(arcs, 1u) << c;
    const auto res = run_path(lim, cases[c], 32);
    expect_within(res, c == 3 ? 0.0 : 0.05, ("case " + std::to_string(c)).c_str());
    EXPECT_EQ(res.end, cases[c].back().geom.end) << c;
  }
}

// Seeded polygons with rounded corners, as CAM pockets and profiles are written: lines joined by
// tangent arcs of R 0.1–3 turning up to 150°, now and then leaving the arc at a corner, on random
// axis limits and P: every fillet the planner builds keeps every axis's speed, acceleration and
// jerk, and every setpoint within P of the program (most arcs become fillets).
static std::vector<PathRequest> fillet_chain(std::mt19937_64& rng, std::uniform_real_distribution<double>& u, double tol) {
  std::vector<PathRequest> reqs;
  core::Vec at = xyz(0, 0, 0);
  double h = 2 * std::numbers::pi * u(rng);
  const int n = 2 + static_cast<int>(rng() % 12);
  const double feed = 20 + 200 * u(rng);
  for (int k = 0; k < n; ++k) {
    const double len = rng() % 5 == 0 ? 0.05 + 0.5 * u(rng) : 0.5 + 15 * u(rng);
    reqs.push_back(line_req(at, at + xyz(std::cos(h), std::sin(h)) * len, feed, static_cast<std::uint32_t>(2 * k), tol));
    at = reqs.back().geom.end;
    const double rad = 0.1 + 3 * u(rng) * u(rng), dir = rng() % 2 ? 1.0 : -1.0, sweep = 0.1 + 2.5 * u(rng);
    const double c0 = at[0] - dir * rad * std::sin(h), c1 = at[1] + dir * rad * std::cos(h);
    const double a1 = std::atan2(at[1] - c1, at[0] - c0) + dir * sweep;
    PathRequest arc = arc_req(make_arc(at, xyz(c0 + rad * std::cos(a1), c1 + rad * std::sin(a1)), 0, 1, c0, c1, dir > 0 ? 1 : -1),
                              feed, static_cast<std::uint32_t>(2 * k + 1));
    arc.tolerance_mm = tol;
    reqs.push_back(arc);
    at = arc.geom.end;
    h += dir * sweep + (rng() % 4 == 0 ? (u(rng) - 0.5) * 2 : 0.0);  // now and then a corner after the arc
  }
  reqs.push_back(line_req(at, at + xyz(std::cos(h), std::sin(h)) * (1 + 10 * u(rng)), feed, static_cast<std::uint32_t>(2 * n), tol));
  return reqs;
}

TEST(PlannerJerk, RandomRoundedPolygonsKeepTheLimitsThroughTheirFillets) {
  expect_random_jerk_paths(200, {0.01, 0.05, 0.2}, fillet_chain);
  // The draws do make fillets: arcs left in the planned window, against the arcs programmed.
  std::size_t programmed = 0, left = 0;
  for (std::uint64_t seed = 1; seed <= 50; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const auto reqs = fillet_chain(rng, u, 0.05);
    Planner planner(jerk_limits(100, 1000, 10000), 256);
    for (const auto& r : reqs) {
      ASSERT_EQ(planner.push(r), PlanResult::Ok) << seed;
      programmed += r.geom.kind == SegmentKind::Arc;
    }
    planner.flush();
    for (std::size_t k = 0; k < planner.queue().ring().size(); ++k) left += planner.queue().ring().at(k).seg.kind == SegmentKind::Arc;
  }
  EXPECT_LT(left, programmed / 2) << left << " of " << programmed;
}

// A fillet runs no faster than any of the three moves it replaces: CAM lowers the feed on corner
// arcs (here F5 on the arc between two F100 lines), and the quintic keeps the arc's feed. And an
// arc that turns against its corner (a right-hand arc between lines turning left) is no fillet:
// the quintic would pass the arc's far side; the arc is kept, and both the setpoints and the
// program's arc lie within P of each other.
TEST(PlannerJerk, FilletsKeepTheArcsFeedAndItsSide) {
  const auto lim = jerk_limits(100, 1000, 10000);
  const auto reqs = pocket_corner(5);
  double v_corner = 0;  // fastest over the fillet: from where it leaves the first line to where it joins the second
  const auto hook = [&](std::uint64_t, Interpolator& in) {
    const auto& p = in.setpoint().pos;
    if (p[0] > 9.7 && p[1] < 0.8) v_corner = std::max(v_corner, in.setpoint().path_v);
  };
  const auto res = run_path(lim, reqs, 16, {}, hook);
  expect_within(res, 0.05, "F5 fillet");
  EXPECT_GT(v_corner, 4.0);
  EXPECT_LE(v_corner, 5 + 1e-9);
  {
    Planner planner(lim, 16);
    for (const auto& r : reqs) ASSERT_EQ(planner.push(r), PlanResult::Ok);
    planner.flush();
    ASSERT_EQ(planner.queue().ring().size(), 3u);  // still a fillet, at the arc's feed
    EXPECT_EQ(planner.queue().ring().at(1).feed_mm_s, 5.0);
  }
  // The wrong way: a clockwise R0.04 arc of 1 rad after a +x line, then on at 30° to the left.
  const double r = 0.04, th = 1.0, k = 30 * std::numbers::pi / 180;
  const core::Vec e = xyz(r * std::sin(th), -r + r * std::cos(th));
  std::vector<PathRequest> wrong{line_req(xyz(-10, 0), xyz(0, 0), 20, 0, 0.05)};
  PathRequest cw = arc_req(make_arc(xyz(0, 0), e, 0, 1, 0, -r, -1), 20, 1);
  cw.tolerance_mm = 0.05;
  wrong.push_back(cw);
  wrong.push_back(line_req(e, e + xyz(std::cos(k), std::sin(k)) * 10, 20, 2, 0.05));
  Planner planner(lim, 16);
  for (const auto& q : wrong) ASSERT_EQ(planner.push(q), PlanResult::Ok);
  planner.flush();
  std::size_t arcs = 0;
  for (std::size_t i = 0; i < planner.queue().ring().size(); ++i) arcs += planner.queue().ring().at(i).seg.kind == SegmentKind::Arc;
  EXPECT_EQ(arcs, 1u);
  std::vector<core::Vec> trace;
  const auto wr = run_path(lim, wrong, 16, {}, {}, 20'000'000, {}, &trace);
  expect_within(wr, 0.05, "wrong-way arc");
  double far = 0;  // the program's arc from the setpoints
  for (int i = 0; i <= 50; ++i) {
    const core::Vec p = cw.geom.point(cw.geom.length * i / 50);
    double d = 1e300;
    for (std::size_t s = 0; s + 1 < trace.size(); ++s) d = std::min(d, make_line(trace[s], trace[s + 1]).distance_to(p));
    far = std::max(far, d);
  }
  EXPECT_LE(far, 0.05);
}

// A seeded random run: every limit and P kept, ending exactly on the last point.
static void expect_run_within(const RunResult& res, const std::vector<PathRequest>& reqs, double tol, std::uint64_t seed) {
  const std::string what = "seed " + std::to_string(seed);
  expect_within(res, tol, what.c_str());
  EXPECT_EQ(res.end, reqs.back().geom.end) << what;
}

// CAM zigzags of a few nanometres (a 0.1 µm step back and on again, printed rounding of a polyline)
// make blocks of 1e-8 mm whose caps are a few 1e-4 mm/s: one cycle at full jerk from rest passes
// them far too fast. The fallback brake came to rest 6e-8 to 2.4e-7 mm before such a block and no
// candidate moved again: the run never ended (an end-to-end fuzzer's seeds; `softmc run` grew its
// trace until it ran out of memory). From rest the follower now also ramps up to the speed the ramp
// to the cruise speed missed, and a ramp or a position-mode stop refused for a slower limit or a
// nearer point to stop at further on is replaced by the one for that limit (interpolator_jerk.cpp).
TEST(PlannerJerk, FromRestBeforeNanometreZigzagsTheFollowerMovesOn) {
  const MachineLimits lim = limits_vaj({{{250, 2794.714609443104, 133915.06614817033},
                                         {250, 3174.6937844178638, 190614.19905667653},
                                         {250, 2305.076564163681, 178457.45398354644}}},
                                       0.001);
  const double f = 3542.23 / 60;
  // A tiny step back and on again; then a step back, a 1e-7 mm step on and an exact stop.
  const std::vector<std::vector<core::Vec>> paths = {
      {xyz(0, 0, 0), xyz(6.147389, 3.1280778, 2.5025897), xyz(6.1473308, 3.1279967, 2.5025897),
       xyz(6.1518692, 3.134319, 2.5025897)},
      {xyz(0, 0, 0), xyz(6.1454359, 3.125357, 2.5025897), xyz(6.1454016, 3.1253093, 2.5025897),
       xyz(6.1454017, 3.1253094, 2.5025897)}};
  for (std::size_t p = 0; p < paths.size(); ++p) {
    std::vector<PathRequest> reqs;
    for (std::size_t k = 0; k + 1 < paths[p].size(); ++k)
      reqs.push_back(line_req(paths[p][k], paths[p][k + 1], f, static_cast<std::uint32_t>(k), 0.05));
    const auto res = run_path(lim, reqs, 64, {}, {}, 20'000);
    const std::string what = "zigzag " + std::to_string(p);
    expect_within(res, 0.05, what.c_str());
    EXPECT_EQ(res.end, reqs.back().geom.end) << what;
    EXPECT_LT(res.cycles, 1000u) << what;  // 0.22 s; it never ended before
  }
}

// Random CAM polylines with nanometre noise: steps of 1e-8 to 1e-3 mm, back and on, zero-length
// moves, on random uneven axes: every run ends, on the last point, within every limit and P.
TEST(PlannerJerk, RandomNanometreZigzagsEndWithinTheLimits) {
  for (std::uint64_t seed = 1; seed < 121; ++seed) {
    std::mt19937_64 rng(seed * 7919);
    std::uniform_real_distribution<double> u(0, 1);
    MachineLimits lim = random_jerk_limits(rng, u);
    lim.period_s = rng() % 2 ? 0.001 : 0.00025;
    const double tol = std::array{0.0, 0.01, 0.05}[rng() % 3];
    const double feed = 10 + 100 * u(rng);
    const auto reqs = chain(4 + static_cast<int>(rng() % 12), tol, [&](int k, const core::Vec& at, const auto&, PathRequest& r) {
      core::Vec to = at;
      if (k == 0) {
        to = xyz(1 + 5 * u(rng), 1 + 5 * u(rng), 2 * u(rng));
      } else if (rng() % 6 != 0) {  // else a zero-length move
        const double len = std::pow(10.0, -8 + 5 * u(rng));
        for (int i = 0; i < 3; ++i) to[i] += len * (2 * u(rng) - 1);
      }
      r.geom = make_line(at, to);
      r.feed_mm_s = feed;
    });
    const auto res = run_path(lim, reqs, 3 + rng() % 64, {}, {}, 2'000'000);
    expect_run_within(res, reqs, tol, seed);
    if (HasFailure()) break;
  }
}

// A return line that runs back almost onto its outgoing one (3e-4 mm off over 15 mm): the corner's
// blend is 1.6e-6 mm long and capped at 1.4e-3 mm/s. The follower braked to rest 4.2e-7 mm before it
// and every candidate was refused from then on, with or without a feed hold there (a review's
// exploration: 89 of 400 such corners hung). At rest for three cycles before blocks that short, the
// follower takes their end as one step within J·dt³/8 (interpolator_jerk.cpp).
TEST(PlannerJerk, NearReversalsArePassedAfterRestOrAHold) {
  MachineLimits lim = xyz_limits(100, 1000);
  for (int i = 0; i < 3; ++i) lim.axis[i].j_max_mm_s3 = 50000;
  {
    const std::vector<PathRequest> reqs{line_req(xyz(0, 0), xyz(20, 0), 100, 0, 0.05),
                                        line_req(xyz(20, 0), xyz(5, 3e-4), 10, 1, 0.05)};
    const auto res = run_path(lim, reqs, 16, {}, {}, 100'000);
    expect_within(res, 0.05, "near-reversal");
    EXPECT_EQ(res.end, xyz(5, 3e-4));
  }
  lim.period_s = 0.002;
  const std::vector<PathRequest> reqs{line_req(xyz(0, 0), xyz(20, 0), 100, 0, 0.01),
                                      line_req(xyz(20, 0), xyz(10, 1.1761032597068243e-05), 10, 1, 0.01)};
  const auto hook = [](std::uint64_t c, Interpolator& in) {
    if (c == 178) in.set_feed_hold(true);
    if (c == 478) in.set_feed_hold(false);
  };
  const auto res = run_path(lim, reqs, 16, {}, hook, 60'000);
  expect_within(res, 0.01, "near-reversal after a hold");
  EXPECT_EQ(res.end, reqs.back().geom.end);
}

// Near-reversals at random: offsets 1e-6 to 1e-2 mm, P 0.001 to 0.2 mm, cycles 0.25 to 2 ms.
TEST(PlannerJerk, RandomNearReversalsEndWithinTheLimits) {
  for (std::uint64_t seed = 1; seed < 201; ++seed) {
    std::mt19937_64 rng(seed * 6151);
    std::uniform_real_distribution<double> u(0, 1);
    MachineLimits lim = random_jerk_limits(rng, u);
    lim.period_s = std::array{0.00025, 0.0005, 0.001, 0.002}[rng() % 4];
    const double tol = std::pow(10.0, -3 + 2.3 * u(rng));
    const double off = std::pow(10.0, -6 + 4 * u(rng));
    const core::Vec c = xyz(10 + 20 * u(rng), 0, 0);
    const std::vector<PathRequest> reqs{line_req(xyz(0, 0), c, 20 + 100 * u(rng), 0, tol),
                                        line_req(c, xyz(c[0] * u(rng), off, 0), 5 + 100 * u(rng), 1, tol)};
    const auto res = run_path(lim, reqs, 16, {}, {}, 2'000'000);
    expect_run_within(res, reqs, tol, seed);
    if (HasFailure()) break;
  }
}

// A handover to a block without a jerk limit starts it from the instant the cycle's step crossed
// the junction (Run.AJerkBlockHandsOverAtTheCrossingOfACycleWithTwoJerkPhases): step_at and
// StopPlan::last_at give that instant on the phases the step ran. Cut at the cycle's end they are
// the step; cut at t, the rest of the ramp from there (its remainder is the same ramp) ends where
// the step did; a constant-jerk step is the cubic; the stop plan's instants match the plan taken on.
TEST(PlannerJerk, AStepCutAtAnInstantLiesOnThePhasesItRan) {
  std::mt19937_64 rng(20261204);
  std::uniform_real_distribution<double> u(0, 1);
  const double dt = 1e-3;
  double worst = 0;
  for (int k = 0; k < 2000; ++k) {
    const ProfileState x{0, 100 * u(rng), 4000 * u(rng) - 2000, 0};
    const double vt = 120 * u(rng), a = 200 + 1800 * u(rng), j = 1e4 * std::pow(100, u(rng));
    const PathStep st = ramp_cycle(x, vt, a, j, dt);
    ASSERT_EQ(st.gen, StepGen::Ramp);
    const ProfileState end = step_at(x, st, dt);
    EXPECT_EQ(end.s, st.x.s);
    EXPECT_EQ(end.v, st.x.v);
    EXPECT_EQ(end.a, st.x.a);
    const double t = dt * u(rng);
    const ProfileState mid = step_at(x, st, t);
    EXPECT_GE(mid.v, st.v_min - 1e-9);
    EXPECT_LE(mid.v, st.v_peak + 1e-9);
    const PathStep rest = ramp_cycle(mid, vt, a, j, dt - t);
    worst = std::max({worst, std::abs(mid.s + rest.x.s - st.x.s), std::abs(rest.x.v - st.x.v) * dt});
    const double jj = j * (2 * u(rng) - 1);
    const PathStep c = jerk_cycle(x, jj, dt);
    const ProfileState cm = step_at(x, c, t);
    EXPECT_NEAR(cm.s, x.v * t + x.a * t * t / 2 + jj * t * t * t / 6, 1e-12);
    EXPECT_NEAR(cm.v, x.v + x.a * t + jj * t * t / 2, 1e-9);
  }
  EXPECT_LT(worst, 1e-12);
  // A position-mode stop: solved, then sampled on; last_at cuts the step just returned.
  StopPlan plan;
  ProfileState x{0, 80, 500, 0};
  double left = 10;
  for (int c = 0; c < 500 && left > 0 && (x.v > 0 || c == 0); ++c) {
    const ProfileState y = plan.step(x, left, 100, 1000, 1e5, dt);
    left -= y.s;
    const ProfileState e = plan.last_at(dt);
    EXPECT_EQ(e.s, y.s);
    EXPECT_EQ(e.v, y.v);
    const ProfileState h = plan.last_at(dt / 2), z = plan.last_at(0);
    EXPECT_NEAR(z.s, 0, 1e-12);
    EXPECT_EQ(z.v, x.v);
    EXPECT_GT(h.s, 0);
    EXPECT_LE(h.s, y.s);
    EXPECT_GE(h.v, 0);
    plan.taken(true);
    x = {0, y.v, y.a, 0};
  }
  EXPECT_GT(plan.reuses(), 10u);
}

// A jerk-limited block running on into one without a jerk limit (a Trapezoid move, or a line of an
// axis configured with j = 0) dropped the rest of the cycle that crossed into it: a one-cycle dip
// in speed, 50 times the acceleration limit (a review's exploration). The time that cycle ran
// past the end now runs on the next block.
TEST(PlannerJerk, IntoABlockWithoutAJerkLimitTheCycleRunsOn) {
  {
    auto lim = xyz_limits(100, 1000);
    for (int i = 0; i < 3; ++i) lim.axis[i].j_max_mm_s3 = 20000;
    auto a = line_req(xyz(0, 0), xyz(50, 0), 50, 0);
    auto b = line_req(xyz(50, 0), xyz(100, 0), 60, 1);
    b.profile = ProfileKind::Trapezoid;
    const auto res = run_path(lim, {a, b}, 16);
    ASSERT_TRUE(res.finished);
    EXPECT_LE(res.fig.a_ratio, 1 + 1e-4) << res.fig.describe();
    EXPECT_EQ(res.end, xyz(100, 0));
  }
  for (const double deg : {10.0, 30.0, 60.0}) {
    auto lim = xyz_limits(100, 1000);
    lim.axis[0].j_max_mm_s3 = 20000;
    lim.axis[1].j_max_mm_s3 = 20000;  // Z: no jerk limit
    const double r = deg * std::numbers::pi / 180;
    const core::Vec p1 = xyz(50, 0, 0), p2 = xyz(50 + 50 * std::cos(r), 0, 50 * std::sin(r));
    const std::vector<PathRequest> reqs{line_req(xyz(0, 0, 0), p1, 50, 0, 0.5), line_req(p1, p2, 50, 1, 0.5),
                                        line_req(p2, p2 + xyz(0, 0, 30), 50, 2, 0.5)};
    const auto res = run_path(lim, reqs, 16);
    ASSERT_TRUE(res.finished);
    EXPECT_LE(res.fig.a_ratio, 1 + 1e-4) << deg << "°: " << res.fig.describe();
    EXPECT_LE(res.fig.deviation_mm, 0.5 + 1e-9) << deg << "°";
    EXPECT_EQ(res.end, reqs.back().geom.end);
  }
}

// The other way: a block without a jerk limit into one with a limit. The trapezoid follower plans
// its exit with the backward pass's constant deceleration, which knows nothing of jerk ramps: a
// fuzzer's program on X and Y without jerk and Z with 10 000 mm/s³ handed the jerk follower the
// last line at 22 mm/s, more than its 1.04 mm allow under the jerk, and the path reached the end at
// 3 mm/s: X at 10.3× its acceleration, Z at 33× its jerk. Such a junction is a stop now.
TEST(PlannerJerk, FromABlockWithoutAJerkLimitIntoOneWithTheJerkFollowerStartsAtRest) {
  auto lim = xyz_limits(100, 1000);
  lim.axis[0] = {500, 200, 0, -1e6, 1e6};
  lim.axis[1] = {200, 3000, 0, -1e6, 1e6};
  lim.axis[2] = {200, 10000, 10000, -1e6, 1e6};
  const core::Vec p0 = xyz(50, 50, 10), p1 = xyz(51.8541, 60.4412, 11.7465), p2 = xyz(37.0163, 53.7904, 11.7465),
                  p3 = xyz(36.1384, 53.2476, 11.6072);
  const std::vector<PathRequest> reqs{line_req(p0, p1, 100, 0, 0.05), line_req(p1, p2, 100, 1, 0.05),
                                      line_req(p2, p3, 100, 2, 0.05)};
  std::vector<core::Vec> trace;
  const auto res = run_path(lim, reqs, 16, {}, {}, 20'000'000, {}, &trace);
  ASSERT_TRUE(res.finished);
  EXPECT_LE(res.fig.v_ratio, 1 + 1e-6) << res.fig.describe();
  EXPECT_LE(res.fig.a_ratio, 1 + 1e-6) << res.fig.describe();
  EXPECT_LE(res.fig.j_ratio, 1 + 1e-6) << res.fig.describe();  // Z's: the only axis with a jerk limit
  EXPECT_LE(res.fig.deviation_mm, 0.05 + 1e-9) << res.fig.describe();
  EXPECT_EQ(res.end, p3);
  // The last cycles come to rest on the end point, the speed falling to 0 without a step.
  ASSERT_GE(trace.size(), 3u);
  const double v_last = core::norm(trace[trace.size() - 1] - trace[trace.size() - 2]) / lim.period_s;
  EXPECT_LT(v_last, 0.5);
}

// The trapezoid follower hands a jerk block the rest of its cycle when it ends; where that block is
// the open back alone (the next push has not come), it is not planned with (PlanQueue::visible):
// the path waits at rest on its start until the next commit or the flush, as step() waits (a
// review's case: a window of 2, X and Y without jerk limits and Z with one).
TEST(PlannerJerk, TheTrapezoidFollowerDoesNotHandAnOpenBackToTheJerkFollower) {
  auto lim = xyz_limits(100, 1000);
  lim.axis[2].j_max_mm_s3 = 10000;  // Z alone has a jerk limit
  Planner planner(lim, 16);
  Interpolator in(planner.queue(), xyz(0, 0, 0));
  ASSERT_EQ(planner.push(line_req(xyz(0, 0, 0), xyz(5, 0, 0), 50, 0, 0)), PlanResult::Ok);  // X: no jerk limit
  ASSERT_EQ(planner.push(line_req(xyz(5, 0, 0), xyz(5, 0, 2), 50, 1, 0)), PlanResult::Ok);  // Z: jerk block
  ASSERT_EQ(planner.push(line_req(xyz(5, 0, 2), xyz(5, 3, 2), 50, 2, 0)), PlanResult::Ok);  // commits the Z line
  const auto& ring = planner.queue().ring();
  ASSERT_EQ(ring.size(), 2u);
  ASSERT_EQ(planner.queue().visible(), 1u);  // the Z line is the open back
  int waited = 0;
  for (int c = 0; c < 2000 && !in.idle(); ++c) {
    in.step(lim.period_s);
    if (ring.size() == 1 && planner.queue().visible() == 0) {
      // On the open Z line alone: at rest on its start.
      EXPECT_EQ(in.setpoint().path_v, 0) << "cycle " << c;
      EXPECT_EQ(in.front_progress(), 0) << "cycle " << c;
      EXPECT_EQ(in.setpoint().pos, xyz(5, 0, 0)) << "cycle " << c;
      if (++waited == 5) planner.flush();  // the next commit or the flush closes it
    }
  }
  EXPECT_EQ(waited, 5);
  EXPECT_TRUE(in.idle());
  EXPECT_EQ(in.setpoint().pos, xyz(5, 3, 2));
}
