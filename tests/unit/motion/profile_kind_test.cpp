// Profile: one value type holding any kind, selected per move; sampling dispatches to the kind held.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <type_traits>

#include "motion/profile/profile.hpp"

using namespace softmc::motion;

// Copying a Profile into a queue slot in the cycle must not allocate.
static_assert(std::is_trivially_copyable_v<Profile>);

TEST(Profile, DefaultIsAnEmptyTrapezoid) {
  const Profile p;
  EXPECT_EQ(p.kind(), ProfileKind::Trapezoid);
  EXPECT_EQ(p.duration(), 0);
  EXPECT_EQ(p.at(1).s, 0);
}

TEST(Profile, S2_EachKindIsSelectablePerMove) {
  const ProfileKind kinds[] = {ProfileKind::Trapezoid, ProfileKind::Scurve, ProfileKind::Sine2};
  double durations[3];
  for (int k = 0; k < 3; ++k) {
    const auto p = plan_profile(kinds[k], 100, 0, 0, 100, 1000, 10000);
    ASSERT_TRUE(p);
    EXPECT_EQ(p->kind(), kinds[k]);
    EXPECT_EQ(p->length(), 100);
    EXPECT_EQ(p->at(p->duration()).s, 100);
    durations[k] = p->duration();
  }
  EXPECT_NEAR(durations[0], 1.1, 1e-12);  // L/v + v/a
  EXPECT_NEAR(durations[1], 1.2, 1e-12);  // + a/j
  // L/v + 2v/a_p with the peak acceleration capped by the jerk: a_p = √(2·v·j/π) < a_max.
  EXPECT_NEAR(durations[2], 1 + 200 / std::sqrt(2 * 100 * 10000 / std::numbers::pi), 1e-12);
  EXPECT_STREQ(to_string(ProfileKind::Sine2), "sine2");
}

TEST(Profile, MatchesTheKindItHolds) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(0, 1);
  for (int n = 0; n < 300; ++n) {
    const double L = 1 + 100 * U(rng), v0 = 10 * U(rng), v1 = 10 * U(rng);  // 10 mm/s changes within 0.2 mm
    const auto s = plan_scurve(L, v0, v1, 50, 500, 5000);
    const auto q = plan_sin2(L, v0, v1, 50, 500, 0);
    const auto t = plan_trapezoid(L, v0, v1, 50, 500);
    ASSERT_TRUE(s && q && t);
    const Profile ps(*s), pq(*q), pt(*t);
    ASSERT_NE(ps.scurve(), nullptr);
    EXPECT_EQ(ps.trapezoid(), nullptr);
    for (int i = 0; i <= 20; ++i) {
      const double x = s->duration() * i / 20;
      EXPECT_EQ(ps.at(x).s, s->at(x).s);
      EXPECT_EQ(pq.at(x).v, q->at(x).v);
      EXPECT_EQ(pt.at(x).a, t->at(x).a);
    }
  }
}

TEST(Profile, RefusalsPassThrough) {
  EXPECT_FALSE(plan_profile(ProfileKind::Trapezoid, 1, 0, 100, 200, 10, 0));
  EXPECT_FALSE(plan_profile(ProfileKind::Scurve, 1, 0, 100, 200, 10, 100));
  EXPECT_FALSE(plan_profile(ProfileKind::Sine2, 1, 0, 100, 200, 10, 100));
}
