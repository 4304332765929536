// Planner and interpolator basics: per-axis limits, soft limits, setpoints on the path, exact ends.
#include <gtest/gtest.h>

#include <cmath>

#include "motion/interp/interpolator.hpp"
#include "motion/planner/planner.hpp"

using namespace softmc;
using namespace softmc::motion;

namespace {
MachineLimits xy_limits() {
  MachineLimits m;
  for (int i = 0; i < 3; ++i) {
    m.axis[i].v_max_mm_s = 100;
    m.axis[i].a_max_mm_s2 = 1000;
    m.axis[i].min_mm = -500;
    m.axis[i].max_mm = 500;
  }
  m.axis[1].v_max_mm_s = 50;  // Y slower
  return m;
}
core::Vec xy(double x, double y) {
  core::Vec v;
  v[0] = x;
  v[1] = y;
  return v;
}
}  // namespace

TEST(Planner, DiagonalSpeedLimitedBySlowestAxis) {
  const auto sl = segment_limits(make_line(xy(0, 0), xy(100, 100)), xy_limits());
  EXPECT_NEAR(sl.v_max_mm_s, 50 * std::sqrt(2.0), 1e-9);  // Y at 50 mm/s
  EXPECT_NEAR(sl.a_max_mm_s2, 1000 * std::sqrt(2.0), 1e-9);
}

TEST(Planner, ArcCentripetalLimit) {
  auto lim = xy_limits();
  lim.axis[1].v_max_mm_s = 100;
  // R = 1 mm: v² / R ≤ 0.8·a (the centripetal share) → v ≤ √800 ≈ 28.3 mm/s; tangential 0.6·a.
  const auto sl = segment_limits(make_arc(xy(1, 0), xy(-1, 0), 0, 1, 0, 0, 1), lim);
  EXPECT_NEAR(sl.v_max_mm_s, std::sqrt(800.0), 1e-9);
  EXPECT_NEAR(sl.a_max_mm_s2, 600.0, 1e-9);
}

TEST(Planner, P9_SoftLimitRefusesArcLeavingTravel) {
  Planner p(xy_limits(), 8);
  // Both end points inside, but the arc bulges to y = 510.
  PathRequest r{make_arc(xy(10, 500), xy(-10, 500), 0, 1, 0, 500, 1), 10, false, 0};
  EXPECT_EQ(p.push(r), PlanResult::OutsideTravel);
  EXPECT_TRUE(p.queue().empty());
}

TEST(Planner, QueueFullIsReported) {
  Planner p(xy_limits(), 3);
  // Square corners: each line is held back (merge stage, then pending) before it commits with its
  // blend, so the fourth push is the first to fill the window (two lines and two blends, 4 > 3 − 1).
  EXPECT_EQ(p.push({make_line(xy(0, 0), xy(1, 0)), 10, false, 0}), PlanResult::Ok);
  EXPECT_EQ(p.push({make_line(xy(1, 0), xy(1, 1)), 10, false, 1}), PlanResult::Ok);
  EXPECT_EQ(p.queue().ring().size(), 0u);
  EXPECT_EQ(p.push({make_line(xy(1, 1), xy(0, 1)), 10, false, 2}), PlanResult::Ok);
  EXPECT_EQ(p.queue().ring().size(), 2u);
  EXPECT_FALSE(p.queue().full());
  EXPECT_EQ(p.push({make_line(xy(0, 1), xy(0, 2)), 10, false, 3}), PlanResult::Ok);
  EXPECT_EQ(p.queue().ring().size(), 4u);
  EXPECT_TRUE(p.queue().full());
  EXPECT_EQ(p.push({make_line(xy(0, 2), xy(1, 2)), 10, false, 4}), PlanResult::QueueFull);
  PathRequest r{make_line(xy(0, 0), xy(1, 0)), 10, false, 0};
  r.feed_mm_s = 0;
  EXPECT_EQ(Planner(xy_limits(), 2).push(r), PlanResult::BadFeed);
}

// Naive-CAM merge (G64 Q, Q = P/2): corners within Q of the chord disappear into one line; a corner
// farther off, a feed change or a stop keeps them.
TEST(Planner, MergeNearlyCollinearLinesWithinHalfP) {
  Planner p(xy_limits(), 64);  // P = 0.05 mm: Q = 0.025 mm
  double x = 0;
  for (int k = 0; k < 10; ++k, x += 0.5)
    ASSERT_EQ(p.push({make_line(xy(x, k % 2 ? 0.02 : 0), xy(x + 0.5, k % 2 ? 0 : 0.02)), 10, false,
                      static_cast<std::uint32_t>(k)}),
              PlanResult::Ok);
  p.flush();
  ASSERT_EQ(p.queue().ring().size(), 1u);  // ten zig-zag pieces 0.02 mm high: one line
  EXPECT_EQ(p.queue().ring().front().seg.end, xy(5, 0));
  EXPECT_NEAR(p.queue().ring().front().merge_q_mm, 0.02, 1e-12);  // the corners' distance, kept for blends

  Planner q(xy_limits(), 64);
  ASSERT_EQ(q.push({make_line(xy(0, 0), xy(0.5, 0)), 10, false, 0}), PlanResult::Ok);
  ASSERT_EQ(q.push({make_line(xy(0.5, 0), xy(1, 0.06)), 10, false, 1}), PlanResult::Ok);   // 0.03 > Q off
  ASSERT_EQ(q.push({make_line(xy(1, 0.06), xy(1.5, 0.06)), 20, false, 2}), PlanResult::Ok);  // new feed
  q.flush();
  EXPECT_EQ(q.queue().ring().size(), 5u);  // three lines, two blends

  Planner c(xy_limits(), 64);
  ASSERT_EQ(c.push({make_line(xy(0, 0), xy(0.5, 0)), 10, false, 0}), PlanResult::Ok);
  c.queue().clear();  // a stop drops the held-back line too
  EXPECT_TRUE(c.queue().empty());
  ASSERT_EQ(c.push({make_line(xy(2, 0), xy(2.5, 0)), 10, false, 1}), PlanResult::Ok);
  c.flush();
  ASSERT_EQ(c.queue().ring().size(), 1u);
  EXPECT_EQ(c.queue().ring().front().seg.start, xy(2, 0));
}

TEST(Interpolator, LineEndsExactlyAndRespectsLimits) {
  Planner p(xy_limits(), 8);
  ASSERT_EQ(p.push({make_line(xy(0, 0), xy(100, 30)), 1e9, false, 7}), PlanResult::Ok);
  p.flush();
  Interpolator in(p.queue(), xy(0, 0));
  const double dt = 0.001;
  core::Vec prev = xy(0, 0), prev_v{};
  int n = 0;
  while (!in.idle() && n < 100000) {
    const auto& sp = in.step(dt);
    for (int i = 0; i < 2; ++i) {
      const double v = (sp.pos[i] - prev[i]) / dt;
      EXPECT_LE(std::abs(v), xy_limits().axis[i].v_max_mm_s + 1e-6);
      EXPECT_LE(std::abs(v - prev_v[i]) / dt, 1000 + 1e-3);
      prev_v[i] = v;
    }
    EXPECT_NEAR(sp.pos[1], sp.pos[0] * 0.3, 1e-9);  // on the line
    prev = sp.pos;
    ++n;
  }
  EXPECT_EQ(in.setpoint().pos, xy(100, 30));
  EXPECT_EQ(in.setpoint().tag, 7u);
}

TEST(Interpolator, T2_ArcSetpointsOnCircleWithin1nm) {
  Planner p(xy_limits(), 8);
  ASSERT_EQ(p.push({make_arc(xy(40, 10), xy(50, 20), 0, 1, 40, 20, 1), 8, false, 0}), PlanResult::Ok);
  p.flush();
  Interpolator in(p.queue(), xy(40, 10));
  double worst = 0;
  while (!in.idle()) {
    const auto& sp = in.step(0.025);  // the thesis's cycle T = 25 ms
    worst = std::max(worst, std::abs(std::hypot(sp.pos[0] - 40, sp.pos[1] - 20) - 10));
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_EQ(in.setpoint().pos, xy(50, 20));
}
