// Look-ahead: short segments run at the programmed feed, corners are blended within P, G61 stops.
#include <gtest/gtest.h>

#include <array>
#include <numbers>

#include "motion/geometry/bezier.hpp"
#include "planner_run.hpp"

using namespace softmc;
using namespace softmc::motion;
using namespace softmc::motion::testing;

namespace {
// Chords of `chord_mm` around a circle of radius r (centre at (r, 0), starting at the origin).
std::vector<PathRequest> chord_circle(double r, double chord_mm, double feed, double tol) {
  const int n = static_cast<int>(std::ceil(2 * std::numbers::pi * r / chord_mm));
  std::vector<PathRequest> reqs;
  core::Vec at = xyz(0, 0);
  for (int k = 1; k <= n; ++k) {
    const double ang = std::numbers::pi + 2 * std::numbers::pi * k / n;
    core::Vec to = k == n ? xyz(0, 0) : xyz(r + r * std::cos(ang), r * std::sin(ang));
    reqs.push_back(line_req(at, to, feed, static_cast<std::uint32_t>(k - 1), tol));
    at = to;
  }
  return reqs;
}
double length_of(const std::vector<PathRequest>& reqs) {
  double l = 0;
  for (const auto& r : reqs) l += r.geom.length;
  return l;
}
}  // namespace

// Issue 4: a circle of 0.05 mm chords at 100 mm/s (LinuxCNC 2.9: 49 mm/s) runs at the programmed
// feed, within 1.05× of the feed- and acceleration-limited time, inside the tolerance band.
TEST(Lookahead, ShortChordsOfACircleRunAtTheProgrammedFeed) {
  const auto lim = xyz_limits(200, 1000);
  const auto reqs = chord_circle(20, 0.05, 100, 0.01);
  const auto res = run_path(lim, reqs, 1000);
  ASSERT_TRUE(res.finished);
  const double ideal_s = length_of(reqs) / 100 + 100 / 1000.0;  // cruise + one ramp up and down
  const double t_s = static_cast<double>(res.cycles) * lim.period_s;
  EXPECT_LE(t_s, 1.05 * ideal_s) << t_s << " s vs " << ideal_s;
  EXPECT_NEAR(res.max_path_v, 100, 1e-6);
  EXPECT_LE(res.fig.deviation_mm, 0.01);
  EXPECT_LE(res.fig.a_ratio, 1 + 1e-5) << res.fig.describe();
  EXPECT_EQ(res.end, xyz(0, 0));
}

// Colinear CAM output: thousands of 0.01 mm pieces of one line flow at full feed.
TEST(Lookahead, ColinearTinySegmentsFlowAtFullFeed) {
  const auto lim = xyz_limits(200, 1000);
  std::vector<PathRequest> reqs;
  for (int k = 0; k < 5000; ++k)
    reqs.push_back(line_req(xyz(k * 0.01, k * 0.005), xyz((k + 1) * 0.01, (k + 1) * 0.005), 100,
                            static_cast<std::uint32_t>(k)));
  const auto res = run_path(lim, reqs, 2000);
  const double ideal_s = length_of(reqs) / 100 + 100 / 1000.0;
  EXPECT_LE(static_cast<double>(res.cycles) * lim.period_s, 1.01 * ideal_s);
  EXPECT_NEAR(res.max_path_v, 100, 1e-6);
  EXPECT_EQ(res.end, reqs.back().geom.end);
}

// 20,000 segments per second sustained: 0.004 mm chords at 100 mm/s (25,000 per second), the horizon
// (2 blocks per chord) covering the 5 mm braking distance, so look-ahead never limits the speed.
TEST(Lookahead, SustainsTwentyThousandSegmentsPerSecond) {
  const auto lim = xyz_limits(200, 1000);
  const auto reqs = chord_circle(20, 0.004, 100, 0.01);
  const auto res = run_path(lim, reqs, 4096);
  const double t_s = static_cast<double>(res.cycles) * lim.period_s;
  const double ideal_s = length_of(reqs) / 100 + 100 / 1000.0;
  EXPECT_GE(static_cast<double>(reqs.size()) / t_s, 20'000.0);  // ramps included
  EXPECT_LE(t_s, 1.05 * ideal_s);
  EXPECT_LE(res.fig.deviation_mm, 0.01);
  EXPECT_LE(res.fig.a_ratio, 1 + 1e-5) << res.fig.describe();
}

TEST(Lookahead, TenThousandBlockWindowWorks) {
  const auto lim = xyz_limits(200, 1000);
  const auto reqs = chord_circle(30, 0.02, 150, 0.005);
  const auto res = run_path(lim, reqs, 10'000);
  ASSERT_TRUE(res.finished);
  EXPECT_LE(res.fig.a_ratio, 1 + 1e-5);
  EXPECT_EQ(res.end, xyz(0, 0));
}

TEST(Lookahead, CornerBlendStaysWithinToleranceAndKeepsSpeed) {
  const auto lim = xyz_limits(200, 1000);
  const std::vector<PathRequest> reqs{line_req(xyz(0, 0), xyz(50, 0), 100, 0, 0.1),
                                      line_req(xyz(50, 0), xyz(50, 50), 100, 1, 0.1)};
  const auto res = run_path(lim, reqs, 64);
  // 90° corner, P = 0.1: R = 0.1·cos45°/(1 − cos45°) ≈ 0.241 mm, v ≤ √(0.8·1000·0.241) ≈ 13.9 mm/s.
  EXPECT_LE(res.fig.deviation_mm, 0.1 + 1e-12);
  EXPECT_GT(res.fig.deviation_mm, 0.05);  // the band is used, not wasted
  EXPECT_LE(res.fig.a_ratio, 1 + 1e-5);
  EXPECT_EQ(res.end, xyz(50, 50));
}

TEST(Lookahead, G61ExactStopStopsAtEveryCorner) {
  const auto lim = xyz_limits(200, 1000);
  std::vector<PathRequest> reqs{line_req(xyz(0, 0), xyz(10, 0), 100, 0, 0),
                                line_req(xyz(10, 0), xyz(10, 10), 100, 1, 0),
                                line_req(xyz(10, 10), xyz(0, 10), 100, 2, 0)};
  int stops = 0;
  double prev_v = 0;
  bool moving = false;
  const auto hook = [&](std::uint64_t, Interpolator& in) {
    const double v = in.setpoint().path_v;
    (void)lim;
    // The stop falls between two samples: the sampled speed dips below one cycle's worth of ramp.
    if (moving && v < 1000 * lim.period_s && prev_v >= 1000 * lim.period_s) ++stops;
    moving = moving || v > 0;
    prev_v = v;
  };
  const auto res = run_path(lim, reqs, 64, {}, hook);
  EXPECT_EQ(stops, 3);  // at both corners and at the end
  EXPECT_EQ(res.fig.deviation_mm, 0);
}

TEST(Lookahead, ZeroLengthMovesAreSkipped) {
  Planner p(xyz_limits(), 8);
  EXPECT_EQ(p.push(line_req(xyz(1, 1), xyz(1, 1), 10, 0)), PlanResult::Ok);
  p.flush();
  EXPECT_TRUE(p.queue().empty());
}

// A line into an arc at 15° (arc-fitted CAM output meets its lines at such angles), then the arc
// into a line at 30°: unblended, each corner is an exact stop (turning every axis by 0.26–0.5 of
// the speed in one cycle takes far more than the acceleration allows); blended within P by
// curvature-continuous quintics (docs/planner.md "Corner blends") each is crossed at speed. G61
// (P 0) stops at both. Limits kept, end exact, with and without a jerk limit.
TEST(Lookahead, LineArcCornersAreBlendedWithinP) {
  const double q = 15 * std::numbers::pi / 180;
  const core::Vec s0 = xyz(10, 0), c = xyz(10 - 10 * std::sin(q), 10 * std::cos(q));
  const core::Vec s1 = c + xyz(10 * std::cos(q), 10 * std::sin(q));  // a quarter turn on R10
  const core::Vec s2 = s1 + xyz(std::cos(9 * q), std::sin(9 * q)) * 10.0;  // 135°: 30° off the arc's end
  for (const double jerk : {0.0, 10000.0}) {
    auto lim = xyz_limits(100, 1000);
    for (int i = 0; i < 3; ++i) lim.axis[i].j_max_mm_s3 = jerk;
    const auto path = [&](double tol) {
      std::vector<PathRequest> reqs{line_req(xyz(0, 0), s0, 100, 0, tol)};
      PathRequest arc = arc_req(make_arc(s0, s1, 0, 1, c[0], c[1], 1), 100, 1);
      arc.tolerance_mm = tol;
      reqs.push_back(arc);
      reqs.push_back(line_req(s1, s2, 100, 2, tol));
      return reqs;
    };
    std::array<double, 2> v_corner{}, best{1e9, 1e9};  // path speed where the setpoints pass nearest each corner
    const auto hook = [&](std::uint64_t, Interpolator& in) {
      for (int k = 0; k < 2; ++k) {
        const double d = core::distance(in.setpoint().pos, k == 0 ? s0 : s1);
        if (d < best[k]) best[k] = d, v_corner[k] = in.setpoint().path_v;
      }
    };
    const auto blended = run_path(lim, path(0.05), 64, {}, hook);
    const auto v_blended = v_corner;
    best = {1e9, 1e9};
    const auto stopped = run_path(lim, path(0), 64, {}, hook);
    const std::string what = "jerk " + std::to_string(jerk);
    ASSERT_TRUE(blended.finished && stopped.finished) << what;
    EXPECT_LE(blended.fig.deviation_mm, 0.05 + 1e-9) << what;
    EXPECT_GT(blended.fig.deviation_mm, 0.01) << what;  // the band is used
    EXPECT_LT(stopped.fig.deviation_mm, 1e-9) << what;
    for (int k = 0; k < 2; ++k) EXPECT_LT(v_corner[k], 1.0) << what << " corner " << k;  // G61: at rest there
    // Blended: crossed at speed. Under the jerk limit the 30° corner's quintic (10 mm/s, its
    // tangential acceleration a twentieth of the arc's) would lose more time than the stop it
    // replaces, and the planner keeps the stop (Planner::blend_curves).
    EXPECT_GT(v_blended[0], 15.0) << what;
    if (jerk == 0) {
      EXPECT_GT(v_blended[1], 15.0) << what;
    }
    EXPECT_LT(blended.cycles, (jerk > 0 ? 0.95 : 0.9) * stopped.cycles) << what;
    for (const auto* r : {&blended, &stopped}) {
      EXPECT_LE(r->fig.v_ratio, 1 + 1e-6) << what << ": " << r->fig.describe();
      EXPECT_LE(r->fig.a_ratio, 1 + 1e-5) << what << ": " << r->fig.describe();
      if (jerk > 0) {
        EXPECT_LE(r->fig.j_ratio, 1 + 1e-4) << what << ": " << r->fig.describe();
      }
      EXPECT_EQ(r->end, s2) << what;
    }
  }
}

// A smoothed run ends in a stub, a line along the spline's end tangent. Merged with the lines after
// it (naive-CAM merge), it would leave the spline at a kink, which a jerk limit crosses at rest:
// 3D_Chips.ngc had 208 such stops. Requests marked unmergeable (the Channel's stubs) keep their
// direction: the spline, the stub and the next lines join without a stop.
TEST(Lookahead, UnmergeableLinesKeepTheirDirection) {
  auto lim = xyz_limits(100, 1000);
  for (int i = 0; i < 3; ++i) lim.axis[i].j_max_mm_s3 = 10000;
  const auto path = [](bool mergeable) {
    std::vector<PathRequest> reqs;
    PathRequest curve;
    curve.geom = make_cubic_bezier(xyz(0, 0), xyz(2, 1), xyz(4, 1), xyz(6, 1));  // leaves along +x at (6, 1)
    curve.feed_mm_s = 100;
    curve.tolerance_mm = 0.05;
    reqs.push_back(curve);
    PathRequest stub = line_req(xyz(6, 1), xyz(6.5, 1), 100, 1, 0.05);
    stub.mergeable = mergeable;
    reqs.push_back(stub);
    const double t = 0.01;  // the next lines turn 0.6° from the stub: within Q of one chord with it
    reqs.push_back(line_req(xyz(6.5, 1), xyz(6.5 + 3 * std::cos(t), 1 + 3 * std::sin(t)), 100, 2, 0.05));
    reqs.push_back(line_req(reqs.back().geom.end, reqs.back().geom.end + xyz(3 * std::cos(t), 3 * std::sin(t)), 100, 3, 0.05));
    return reqs;
  };
  for (const bool mergeable : {false, true}) {
    Planner planner(lim, 32);
    for (const auto& r : path(mergeable)) ASSERT_EQ(planner.push(r), PlanResult::Ok);
    planner.flush();
    const auto& ring = planner.queue().ring();
    std::size_t stops = 0;  // exact stops between the first block and the end
    for (std::size_t k = 1; k < ring.size(); ++k) stops += ring.at(k).v2_junction <= 0;
    EXPECT_EQ(stops, mergeable ? 1u : 0u) << mergeable;
    EXPECT_EQ(ring.at(1).seg.kind, SegmentKind::Line);
    if (!mergeable) {
      EXPECT_LT(core::norm(ring.at(1).seg.dir - xyz(1, 0)), 1e-12);  // the stub as programmed
    }
  }
  const auto res = run_path(lim, path(false), 32);
  ASSERT_TRUE(res.finished);
  EXPECT_LE(res.fig.deviation_mm, 0.05 + 1e-9);
  EXPECT_LE(res.fig.j_ratio, 1 + 1e-4) << res.fig.describe();
  EXPECT_EQ(res.end, path(false).back().geom.end);
}

// The interpolator passes at most max_blocks_per_cycle (512) blocks a cycle: past that it used to
// drop the rest of the cycle (trapezoids: a speed dip, 14× the acceleration) or let the setpoints
// lag the follower and catch up (jerk mode). A full window of 0.1 µm lines that cannot merge (G61:
// no tolerance) reached 100 mm/s there: 1 000 blocks a cycle. The planner now caps each block at
// the speed at which the 256 blocks ending with it take a cycle, so no cycle needs more than the
// budget: the speed follows the block density and every limit holds.
TEST(Lookahead, DenseTinyBlocksNeverOutrunTheCycleBudget) {
  for (const double j : {0.0, 50000.0}) {
    MachineLimits lim = xyz_limits(100, 2000);
    for (int i = 0; i < 3; ++i) lim.axis[i].j_max_mm_s3 = j;
    std::vector<PathRequest> reqs;
    // 2 mm of 0.1 µm lines between two 20 mm lines, the whole of it in the window at once.
    reqs.push_back(line_req(xyz(0, 0), xyz(20, 0), 100, 0, 0));
    for (int k = 0; k < 20000; ++k)
      reqs.push_back(line_req(xyz(20 + k * 1e-4, 0), xyz(20 + (k + 1) * 1e-4, 0), 100, static_cast<std::uint32_t>(k + 1), 0));
    reqs.push_back(line_req(xyz(22, 0), xyz(42, 0), 100, 20001, 0));
    const auto res = run_path(lim, reqs, 30000);
    ASSERT_EQ(res.error, PlanResult::Ok);
    EXPECT_TRUE(res.finished);
    EXPECT_EQ(res.end, xyz(42, 0));
    EXPECT_LE(res.fig.v_ratio, 1 + 1e-9) << "jerk " << j << ": " << res.fig.describe();
    EXPECT_LE(res.fig.a_ratio, 1 + 1e-6) << "jerk " << j << ": " << res.fig.describe();
    if (j > 0) {
      EXPECT_LE(res.fig.j_ratio, 1 + 1e-3) << res.fig.describe();
    }
    // Through the tiny blocks at 256 × 0.1 µm per ms = 25.6 mm/s, not crawling.
    EXPECT_LT(res.cycles, 1300u) << "jerk " << j;
  }
}

// A G-code arc whose end is off its circle runs as a spiral. A tiny one (r 0.01 → 0.037 mm, within
// LinuxCNC's allowance) ran 1.38 times its feed when its angle advanced linearly with s (a fuzzer's
// case); its feed was then lowered by that, and its small end ran at 0.41 of the feed. Now s is the
// spiral's arc length: it runs at its feed from end to end, with and without a jerk limit.
TEST(Lookahead, SpiralArcsNeverRunFasterThanTheirFeed) {
  for (const double j : {0.0, 5e6}) {  // 5e6 mm/s³: the jerk caps this R0.01 curve above the feed
    MachineLimits lim = xyz_limits(100, 2000);
    for (int i = 0; i < 3; ++i) lim.axis[i].j_max_mm_s3 = j;
    const double feed = 1.0;
    const auto arc = make_arc(xyz(10, 10), xyz(10.047, 10), 0, 1, 10.01, 10, -1);
    ASSERT_GT(arc.dradius, 0.02);
    std::vector<core::Vec> trace;
    const auto res = run_path(lim, {arc_req(arc, feed, 0)}, 64, {}, {}, 20'000'000, {}, &trace);
    ASSERT_TRUE(res.finished);
    double fastest = 0, slowest = 1e300;
    for (std::size_t k = 1; k < trace.size(); ++k) {
      const double v = core::norm(trace[k] - trace[k - 1]) / lim.period_s;
      fastest = std::max(fastest, v);
      if (k > trace.size() / 10 && k < trace.size() * 9 / 10) slowest = std::min(slowest, v);  // past the ramps
    }
    EXPECT_LE(fastest, feed * (1 + 1e-6)) << "jerk " << j;
    // The feed all along (a 1 µm chord of an R0.01 arc is 2e-4 shorter than the arc).
    EXPECT_GT(slowest, feed * (1 - 1e-3)) << "jerk " << j;
  }
}
