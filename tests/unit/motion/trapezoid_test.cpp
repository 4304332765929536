// Trapezoidal profile: limits never exceeded, target reached, speed continuous (seeded property tests).
#include <gtest/gtest.h>

#include <random>

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
