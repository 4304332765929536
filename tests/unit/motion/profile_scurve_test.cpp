// Jerk-limited S-curve: closed-form cases, refusals, and seeded random property tests (limits, continuity,
// end reached, no NaN, never faster than the trapezoid, converging to it as the jerk limit grows).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "motion/profile/scurve.hpp"
#include "motion/profile/trapezoid.hpp"
#include "profile_checks.hpp"

using namespace softmc::motion;

TEST(Scurve, RestToRestReachingEveryLimit) {
  // a²/j = 100 ≤ v = 100: each ramp holds a_max; ramp time v/a + a/j = 0.2 s over v·0.2/2 = 10 mm.
  const auto p = plan_scurve(100, 0, 0, 100, 1000, 10000);
  ASSERT_TRUE(p);
  EXPECT_DOUBLE_EQ(p->v_peak, 100);
  EXPECT_NEAR(p->up.t1, 0.1, 1e-12);
  EXPECT_NEAR(p->up.t2, 0.0, 1e-12);
  EXPECT_NEAR(p->t_cruise, 0.8, 1e-12);
  EXPECT_NEAR(p->duration(), 100.0 / 100 + 100.0 / 1000 + 1000.0 / 10000, 1e-12);  // L/v + v/a + a/j
  EXPECT_NEAR(p->at(0.05).a, 500, 1e-9);   // halfway up the first jerk phase
  EXPECT_NEAR(p->at(0.05).j, 10000, 1e-9);
  EXPECT_NEAR(p->at(0.6).v, 100, 1e-9);
  EXPECT_EQ(p->at(p->duration()).s, 100);
  EXPECT_EQ(p->at(1e9).s, 100);
}

TEST(Scurve, AccelerationLimitNotReached) {
  // a_max²/j = 1000 > v = 100: the acceleration peaks at √(v·j) and each ramp lasts 2·√(v/j).
  const auto p = plan_scurve(1000, 0, 0, 100, 1000, 1000);
  ASSERT_TRUE(p);
  EXPECT_DOUBLE_EQ(p->v_peak, 100);
  EXPECT_NEAR(p->up.a_peak, std::sqrt(100.0 * 1000), 1e-9);
  EXPECT_NEAR(p->up.duration(), 2 * std::sqrt(0.1), 1e-12);
  EXPECT_NEAR(p->duration(), 1000.0 / 100 + 2 * std::sqrt(0.1), 1e-9);  // L/v + ramp time
}

TEST(Scurve, SpeedLimitNotReachedIsTimeOptimal) {
  // Short move with a_max reached: each ramp covers v_p/2·(v_p/a + a/j), so L = v_p²/a + v_p·a/j.
  const double L = 5, a = 1000, j = 100000;
  const auto p = plan_scurve(L, 0, 0, 1000, a, j);
  ASSERT_TRUE(p);
  const double c = a / j;  // v_p² / a + v_p·c − L = 0
  const double vp = (-c + std::sqrt(c * c + 4 * L / a)) / (2 / a);
  EXPECT_NEAR(p->v_peak, vp, 1e-9 * vp);
  EXPECT_NEAR(p->t_cruise, 0, 1e-9);
  EXPECT_NEAR(p->duration(), 2 * (vp / a + a / j), 1e-9);
  EXPECT_NEAR(p->at(p->duration() / 2).v, vp, 1e-6);
}

TEST(Scurve, NonZeroEndSpeeds) {
  const auto p = plan_scurve(50, 20, 5, 100, 1000, 20000);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->at(0).v, 20);
  EXPECT_EQ(p->at(0).a, 0);
  EXPECT_EQ(p->at(p->duration()).v, 5);
  EXPECT_NEAR(p->at(p->duration() * (1 - 1e-12)).v, 5, 1e-6);
}

TEST(Scurve, RefusesUnreachableEndSpeedAndBadInput) {
  EXPECT_FALSE(plan_scurve(1, 0, 100, 200, 10, 100));      // cannot gain 100 mm/s in 1 mm
  EXPECT_FALSE(plan_scurve(0.001, 100, 0, 200, 1e4, 1e5));  // cannot stop in 1 µm
  EXPECT_FALSE(plan_scurve(-1, 0, 0, 1, 10, 100));
  EXPECT_FALSE(plan_scurve(1, 0, 0, 0, 10, 100));
  EXPECT_FALSE(plan_scurve(1, 0, 0, 1, 0, 100));
  EXPECT_FALSE(plan_scurve(1, 0, 0, 1, 10, -1));
  EXPECT_FALSE(plan_scurve(NAN, 0, 0, 1, 10, 100));
  EXPECT_FALSE(plan_scurve(1, 0, 0, 1, 10, NAN));
  ASSERT_TRUE(plan_scurve(0, 0, 0, 1, 10, 100));  // zero length: nothing to do
  EXPECT_EQ(plan_scurve(0, 0, 0, 1, 10, 100)->duration(), 0);
}

TEST(Scurve, JerkUnlimitedIsTheTrapezoid) {
  const auto s = plan_scurve(10, 3, 1, 40, 200, 0);
  const auto t = plan_trapezoid(10, 3, 1, 40, 200);
  ASSERT_TRUE(s && t);
  EXPECT_NEAR(s->duration(), t->duration(), 1e-12);
  for (double x = 0; x <= t->duration(); x += t->duration() / 37) {
    EXPECT_NEAR(s->at(x).s, t->at(x).s, 1e-9);
    EXPECT_NEAR(s->at(x).v, t->at(x).v, 1e-9);
  }
}

TEST(Scurve, ConvergesToTrapezoidAsJerkGrows) {
  const auto t = plan_trapezoid(30, 0, 0, 50, 500);
  ASSERT_TRUE(t);
  double prev = INFINITY;
  for (double j = 1e3; j <= 1e12; j *= 10) {
    const auto s = plan_scurve(30, 0, 0, 50, 500, j);
    ASSERT_TRUE(s);
    const double extra = s->duration() - t->duration();
    EXPECT_GE(extra, -1e-12);
    EXPECT_LE(extra, prev);
    EXPECT_LE(extra, 2 * 500 / j + 1e-12);  // at most one a/j per ramp
    prev = extra;
  }
  EXPECT_LT(prev, 1e-8);
}

TEST(Scurve, RandomProfilesRespectLimitsAndReachTheEnd) {
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> U(0, 1);
  int planned = 0, refused = 0;
  for (int n = 0; n < 4000; ++n) {
    const double L = std::pow(10, -3 + 5 * U(rng));
    const double vmax = std::pow(10, -1 + 3 * U(rng));
    const double amax = std::pow(10, 1 + 3 * U(rng));
    const double jmax = std::pow(10, 2 + 5 * U(rng));
    const double v0 = U(rng) < 0.3 ? 0 : vmax * U(rng);
    const double v1 = U(rng) < 0.3 ? 0 : vmax * U(rng);
    const auto p = plan_scurve(L, v0, v1, vmax, amax, jmax);
    if (!p) {
      // Refused only when the direct ramp v0 → v1 is longer than L.
      const Ramp r = plan_ramp(v0, 0, v1, amax, jmax);
      EXPECT_GT(0.5 * (v0 + v1) * r.duration(), L * (1 - 1e-9)) << L << " " << v0 << " " << v1;
      ++refused;
      continue;
    }
    ++planned;
    const double T = p->duration();
    ASSERT_TRUE(std::isfinite(T));
    test::Bounds b{vmax, amax, jmax, true, L};
    const auto at = [&](double t) { return p->at(t); };
    ASSERT_EQ(test::check_samples(at, T, test::sample_step(T), b, "scurve #" + std::to_string(n)), 0);
    EXPECT_EQ(p->at(T).s, L);
    EXPECT_NEAR(p->at(T * (1 - 1e-12)).s, L, 1e-9 * std::max(1.0, L));
    // Already there just before the end: the snap to the exact end state only removes rounding.
    const ProfileState end = p->at(T * (1 - 1e-12));
    EXPECT_NEAR(end.v, v1, 1e-9 * std::max(1.0, vmax));
    EXPECT_NEAR(end.a, 0, 2 * jmax * T * 1e-12 + 1e-9 * amax);  // a = j·δ at δ = T·1e-12 before the end
    EXPECT_NEAR(p->at(0).v, v0, 1e-12);
    // Never faster than the trapezoid with the same speed and acceleration.
    if (const auto tr = plan_trapezoid(L, v0, v1, vmax, amax)) {
      EXPECT_GE(T, tr->duration() * (1 - 1e-9));
    }
  }
  EXPECT_GT(planned, 2000);
  EXPECT_GT(refused, 10);
}
