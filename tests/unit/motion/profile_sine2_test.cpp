// Sine-squared profile (SPC G02): the sin² acceleration shape, its jerk, and seeded random property tests.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "motion/profile/sine2.hpp"
#include "motion/profile/trapezoid.hpp"
#include "profile_checks.hpp"

using namespace softmc::motion;
constexpr double kPi = std::numbers::pi;

TEST(Sine2, S2_G02AccelerationIsSineSquared) {
  // Rest to rest, a_max reached: each ramp lasts 2·v/a = 0.2 s and covers v²/a = 10 mm.
  const auto p = plan_sin2(100, 0, 0, 100, 1000);
  ASSERT_TRUE(p);
  EXPECT_DOUBLE_EQ(p->v_peak, 100);
  EXPECT_NEAR(p->up.t, 0.2, 1e-12);
  EXPECT_NEAR(p->t_cruise, 0.8, 1e-12);
  EXPECT_NEAR(p->duration(), 1.2, 1e-12);
  for (double t = 0; t <= 0.2; t += 0.0125) {
    const double sn = std::sin(kPi * t / 0.2);
    EXPECT_NEAR(p->at(t).a, 1000 * sn * sn, 1e-9) << t;
  }
  for (double t = 1.0; t <= 1.2; t += 0.0125) {  // the deceleration mirrors it
    const double sn = std::sin(kPi * (t - 1.0) / 0.2);
    EXPECT_NEAR(p->at(t).a, -1000 * sn * sn, 1e-6) << t;
  }
  // The resulting jerk: a·π/T = π·a²/(2·v).
  EXPECT_NEAR(p->jerk_peak(), kPi * 1000 * 1000 / 200, 1e-6);
  EXPECT_NEAR(p->at(0.05).j, p->jerk_peak(), 1e-6);  // peak at T/4
  EXPECT_EQ(p->at(0).a, 0);
  EXPECT_EQ(p->at(p->duration()).s, 100);
}

TEST(Sine2, S2_G02ShortMoveNeverReachesSpeed) {
  // 2·v_p²/a = L → v_p = √(a·L/2).
  const auto p = plan_sin2(2, 0, 0, 1000, 1000);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->v_peak, std::sqrt(1000.0 * 2 / 2), 1e-9);
  EXPECT_NEAR(p->t_cruise, 0, 1e-9);
}

TEST(Sine2, S2_G02JerkLimitLowersThePeakAcceleration) {
  const double j = 5000;
  const auto p = plan_sin2(100, 0, 0, 100, 1000, j);
  ASSERT_TRUE(p);
  EXPECT_LE(p->jerk_peak(), j * (1 + 1e-12));
  EXPECT_NEAR(p->up.a_peak, std::sqrt(2 * 100 * j / kPi), 1e-9);  // √(2·dv·j/π) < a_max
  const auto free = plan_sin2(100, 0, 0, 100, 1000);
  EXPECT_GT(p->duration(), free->duration());
}

TEST(Sine2, RefusesUnreachableEndSpeedAndBadInput) {
  EXPECT_FALSE(plan_sin2(1, 0, 100, 200, 10));
  EXPECT_FALSE(plan_sin2(-1, 0, 0, 10, 10));
  EXPECT_FALSE(plan_sin2(1, 0, 0, 10, 0));
  EXPECT_FALSE(plan_sin2(1, 0, 0, 10, 10, -5));
  EXPECT_FALSE(plan_sin2(1, NAN, 0, 10, 10));
}

TEST(Sine2, RandomProfilesRespectLimitsAndReachTheEnd) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0, 1);
  int planned = 0;
  for (int n = 0; n < 4000; ++n) {
    const double L = std::pow(10, -3 + 5 * U(rng));
    const double vmax = std::pow(10, -1 + 3 * U(rng));
    const double amax = std::pow(10, 1 + 3 * U(rng));
    const double jmax = U(rng) < 0.5 ? 0 : std::pow(10, 2 + 5 * U(rng));
    const double v0 = U(rng) < 0.3 ? 0 : vmax * U(rng);
    const double v1 = U(rng) < 0.3 ? 0 : vmax * U(rng);
    const auto p = plan_sin2(L, v0, v1, vmax, amax, jmax);
    if (!p) {
      const Sine2Ramp r = plan_sine2_ramp(v0, v1, amax, jmax);
      EXPECT_GT(0.5 * (v0 + v1) * r.t, L * (1 - 1e-9));
      continue;
    }
    ++planned;
    const double T = p->duration();
    if (jmax > 0) {
      EXPECT_LE(p->jerk_peak(), jmax * (1 + 1e-9));
    }
    test::Bounds b{vmax, amax, p->jerk_peak(), true, L};
    const auto at = [&](double t) { return p->at(t); };
    ASSERT_EQ(test::check_samples(at, T, test::sample_step(T), b, "sine2 #" + std::to_string(n)), 0);
    EXPECT_EQ(p->at(T).s, L);
    EXPECT_NEAR(p->at(T * (1 - 1e-12)).s, L, 1e-9 * std::max(1.0, L));
    if (const auto tr = plan_trapezoid(L, v0, v1, vmax, amax)) {
      EXPECT_GE(T, tr->duration() * (1 - 1e-9));
    }
  }
  EXPECT_GT(planned, 2000);
}
