// Trapezoidal profile: limits never exceeded, target reached, speed continuous (seeded property tests).
#include <gtest/gtest.h>

#include <random>

#include "motion/interp/velocity_ramp.hpp"
#include "motion/profile/trapezoid.hpp"

using softmc::motion::plan_trapezoid;

TEST(Trapezoid, RestToRestReachesCruise) {
  const auto p = plan_trapezoid(100, 0, 0, 10, 100);
  ASSERT_TRUE(p);
  EXPECT_DOUBLE_EQ(p->v_peak, 10);
  EXPECT_DOUBLE_EQ(p->t_acc, 0.1);
  EXPECT_NEAR(p->duration(), 10.1, 1e-12);
  EXPECT_DOUBLE_EQ(p->at(p->duration()).s, 100);
  EXPECT_NEAR(p->at(5).v, 10, 1e-12);
}

TEST(Trapezoid, ShortMoveIsTriangular) {
  const auto p = plan_trapezoid(1, 0, 0, 1000, 100);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->v_peak, 10, 1e-12);  // v² = a·L
  EXPECT_NEAR(p->t_cruise, 0, 1e-12);
}

TEST(Trapezoid, UnreachableEndSpeedIsRefused) {
  EXPECT_FALSE(plan_trapezoid(1, 0, 100, 200, 10));
  EXPECT_FALSE(plan_trapezoid(1, 0, 0, 0, 10));
  EXPECT_FALSE(plan_trapezoid(-1, 0, 0, 1, 10));
}

TEST(Trapezoid, RandomProfilesRespectLimits) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> U(0, 1);
  for (int n = 0; n < 5000; ++n) {
    const double L = std::pow(10, -3 + 6 * U(rng)), vmax = 0.1 + 500 * U(rng), acc = 1 + 5000 * U(rng);
    const double v0 = vmax * U(rng) * (U(rng) < 0.5 ? 0 : 1);
    const double v1max = std::sqrt(v0 * v0 + 2 * acc * L);
    const double v1min = std::sqrt(std::max(0.0, v0 * v0 - 2 * acc * L));  // can decelerate that far
    const double v1 = v1min + (std::min(vmax, v1max) - v1min) * U(rng);
    const auto p = plan_trapezoid(L, v0, v1, vmax, acc);
    ASSERT_TRUE(p) << L << " " << v0 << " " << v1;
    const int k = 200;
    double s_prev = 0, v_prev = v0;
    for (int i = 0; i <= k; ++i) {
      const auto st = p->at(p->duration() * i / k);
      ASSERT_TRUE(std::isfinite(st.s));
      EXPECT_LE(st.v, std::max(vmax, v0) * (1 + 1e-12));
      EXPECT_GE(st.v, -1e-9);
      EXPECT_LE(std::abs(st.a), acc * (1 + 1e-12));
      EXPECT_GE(st.s, s_prev - 1e-9);  // never goes back
      EXPECT_LE(std::abs(st.v - v_prev), acc * p->duration() / k * (1 + 1e-9) + 1e-9);  // continuous
      s_prev = st.s;
      v_prev = st.v;
    }
    EXPECT_NEAR(p->at(p->duration()).s, L, 1e-9 * std::max(1.0, L));
    EXPECT_NEAR(p->at(p->duration()).v, v1, 1e-9 * std::max(1.0, vmax));
  }
}

// The planner's passes and the interpolator reach a block's entry speed by different roundings: an
// entry a hair of v² above what the block's deceleration brakes to rest over its length must still
// end at rest (a reversal left at 1.4e-6 mm/s stepped the speed and broke the acceleration limit by
// 1e-6 in the next cycle), braking harder only by that hair; a real excess still brakes all the way.
TEST(VelocityRamp, AnEntryAHairTooFastStillEndsAtTheWantedSpeed) {
  using softmc::motion::plan_ramp;
  const double acc = 2022.82657797245, dist = 0.00400519662438767;
  for (const double v1 : {0.0, 0.5, 2.0}) {
    for (const double hair : {1e-15, 1e-13, 1e-11}) {
      const double v0 = std::sqrt((2 * acc * dist + v1 * v1) * (1 + hair));
      const auto r = plan_ramp(dist, v0, v0, v1, v1, acc);
      EXPECT_EQ(r.v1, v1) << "v1 " << v1 << " hair " << hair;
      EXPECT_LE(std::abs(r.a1), acc * (1 + 1e-9));
      EXPECT_LE(std::abs(r.a3), acc * (1 + 1e-9));
      EXPECT_NEAR(r.at(r.duration()).s, dist, 1e-15);
      EXPECT_NEAR(r.at(r.duration() - 1e-12).v, v1, 1e-6);
    }
  }
  // Too fast by a real margin: brakes all the way at `acc` and leaves above the wanted speed.
  const double v0 = std::sqrt(2 * acc * dist * (1 + 1e-6));
  const auto r = plan_ramp(dist, v0, v0, 0, 0, acc);
  EXPECT_GT(r.v1, 1e-3);
  EXPECT_LE(std::max(std::abs(r.a1), std::abs(r.a3)), acc * (1 + 1e-15));
}
