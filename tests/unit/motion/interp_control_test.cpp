// Feed override (P-8), feed hold, motion enable (P-2) and stops (P-5) acting on the moving path.
#include <gtest/gtest.h>

#include <cmath>

#include "planner_run.hpp"

using namespace softmc;
using namespace softmc::motion;
using namespace softmc::motion::testing;

namespace {
constexpr double kDt = 0.001;

// One long X line at 100 mm/s (a = 1000): cruise from 5 mm on.
struct Rig {
  MachineLimits lim = xyz_limits(200, 1000);
  Planner planner{lim, 64};
  Interpolator in{planner.queue(), xyz(0, 0)};
  TraceChecker chk{lim, kDt, {make_line(xyz(0, 0), xyz(200, 0))}};
  Rig() {
    EXPECT_EQ(planner.push(line_req(xyz(0, 0), xyz(200, 0), 100, 0)), PlanResult::Ok);
    planner.flush();
  }
  const Setpoint& step() {
    const auto& sp = in.step(kDt);
    chk.add(sp.pos, sp.tag);
    return sp;
  }
  void steps(int n) {
    for (int i = 0; i < n; ++i) step();
  }
  void expect_limits() {
    EXPECT_LE(chk.figures().v_ratio, 1 + 1e-9) << chk.figures().describe();
    EXPECT_LE(chk.figures().a_ratio, 1 + 1e-6) << chk.figures().describe();
  }
};
}  // namespace

TEST(Interp, P8_OverrideActsWithinOneCycleWithTheRamp) {
  Rig r;
  r.steps(300);  // cruising at 100
  ASSERT_NEAR(r.in.setpoint().path_v, 100, 1e-9);
  r.in.set_feed_override(0.5);
  const double v1 = r.step().path_v;
  EXPECT_NEAR(v1, 100 - 1000 * kDt, 1e-9);  // decelerating in the very next cycle, at the ramp
  r.steps(100);
  EXPECT_NEAR(r.in.setpoint().path_v, 50, 1e-9);
  r.in.set_feed_override(1.5);  // above 100 %: 150 mm/s, still under the axis's 200
  r.steps(200);
  EXPECT_NEAR(r.in.setpoint().path_v, 150, 1e-9);
  r.in.set_feed_override(10);  // clamped to the configured maximum (2) and to the axis limit (200)
  r.steps(200);
  EXPECT_NEAR(r.in.setpoint().path_v, 200, 1e-9);
  while (!r.in.idle()) r.step();
  EXPECT_EQ(r.in.setpoint().pos, xyz(200, 0));
  r.expect_limits();
}

TEST(Interp, FeedHoldStopsOnThePathAndResumesFromThere) {
  Rig r;
  r.steps(300);
  r.in.set_feed_hold(true);
  EXPECT_LT(r.step().path_v, 100);  // acts within one cycle
  r.steps(150);
  const auto held = r.in.setpoint().pos;
  EXPECT_EQ(r.in.setpoint().path_v, 0);
  EXPECT_TRUE(r.in.halted_at_rest());
  // 5 mm of ramp and 20 mm of cruise, then braking from 100 mm/s at 1000 mm/s² takes 5 mm.
  EXPECT_NEAR(held[0], 25 + 5, 0.2);
  r.steps(500);
  EXPECT_EQ(r.in.setpoint().pos, held);  // stays put while held
  r.in.set_feed_hold(false);
  EXPECT_GT(r.step().path_v, 0);
  while (!r.in.idle()) r.step();
  EXPECT_EQ(r.in.setpoint().pos, xyz(200, 0));
  EXPECT_EQ(r.chk.figures().deviation_mm, 0);
  r.expect_limits();
}

TEST(Interp, P2_MotionEnableDropStopsAndReturnResumesWithoutJump) {
  Rig r;
  r.steps(300);
  r.in.set_motion_enable(false);
  r.steps(200);
  EXPECT_EQ(r.in.setpoint().path_v, 0);
  const auto at = r.in.setpoint().pos;
  r.in.set_motion_enable(true);
  r.step();
  EXPECT_NEAR(r.in.setpoint().pos[0], at[0] + 0.5 * 1000 * kDt * kDt, 1e-9);  // on the path, ramping up
  while (!r.in.idle()) r.step();
  EXPECT_EQ(r.in.setpoint().pos, xyz(200, 0));
  r.expect_limits();
}

TEST(Interp, P5_NormalStopBrakesOnThePathThenDropsThePlan) {
  Rig r;
  r.steps(300);
  r.in.request_stop(StopKind::Normal);
  int n = 0;
  while (!r.in.stopped() && n < 1000) {
    r.step();
    ++n;
  }
  EXPECT_TRUE(r.in.stopped());
  EXPECT_NEAR(n, 100, 1);  // 100 mm/s at 1000 mm/s²
  EXPECT_TRUE(r.in.idle());
  EXPECT_FALSE(r.in.setpoint().moving);
  EXPECT_NEAR(r.in.setpoint().pos[0], 25 + 5, 0.2);
  r.expect_limits();
}

TEST(Interp, P5_EmergencyStopUsesTheEmergencyRamp) {
  MachineLimits lim = xyz_limits(200, 1000);
  Planner planner(lim, 64);
  InterpolatorConfig ic;
  ic.emergency_accel_scale = 2.0;
  Interpolator in(planner.queue(), xyz(0, 0), ic);
  ASSERT_EQ(planner.push(line_req(xyz(0, 0), xyz(200, 0), 100, 0)), PlanResult::Ok);
  planner.flush();
  for (int i = 0; i < 300; ++i) in.step(kDt);
  in.request_stop(StopKind::Emergency);
  int n = 0;
  while (!in.stopped() && n < 1000) {
    in.step(kDt);
    ++n;
  }
  EXPECT_NEAR(n, 50, 1);  // twice the deceleration: half the time
}

TEST(Interp, HoldAcrossManyShortBlocksKeepsTheLimits) {
  // Braking distance (5 mm) spans many 0.05 mm blocks: the hold carries over block ends.
  const auto lim = xyz_limits(200, 1000);
  std::vector<PathRequest> reqs;
  for (int k = 0; k < 2000; ++k)
    reqs.push_back(line_req(xyz(k * 0.05, (k % 2) * 1e-4), xyz((k + 1) * 0.05, ((k + 1) % 2) * 1e-4), 100,
                            static_cast<std::uint32_t>(k), 0.01));
  std::uint64_t held_at = 0;
  core::Vec held_pos{};
  const auto hook = [&](std::uint64_t c, Interpolator& in) {
    if (c == 400) in.set_feed_hold(true);
    if (c == 700) {
      held_at = c;
      held_pos = in.setpoint().pos;
      EXPECT_EQ(in.setpoint().path_v, 0);
    }
    if (c == 800) in.set_feed_hold(false);
  };
  const auto res = run_path(lim, reqs, 4096, {}, hook);
  EXPECT_EQ(held_at, 700u);
  EXPECT_GT(held_pos[0], 30);
  EXPECT_LE(res.fig.a_ratio, 1 + 1e-6) << res.fig.describe();
  EXPECT_LE(res.fig.deviation_mm, 0.01 + 1e-9);
  EXPECT_EQ(res.end, reqs.back().geom.end);
}
