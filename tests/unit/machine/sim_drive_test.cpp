// Simulated drive: steady following error matches the loop model; encoder quantisation (T-1).
#include <gtest/gtest.h>

#include <cmath>

#include "machine/sim_drive.hpp"

using namespace softmc::machine;

namespace {
AxisConfig axis(double ff) {
  AxisConfig a;
  a.name = "x";
  a.min_mm = -1e6;
  a.max_mm = 1e6;
  a.counts_per_rev = 512;
  a.mm_per_rev = 65;
  a.kv_1_s = 30;
  a.feedforward = ff;
  a.drive_tau_s = 0.005;
  return a;
}
// Ramps a setpoint to `v` and holds it for `hold_s`; returns the mean following error over the last second.
double steady_ferror(SimDrive& d, double v, double hold_s) {
  const double dt = 0.001;
  double x = 0, sum = 0;
  int n = 0;
  for (double t = 0; t < hold_s; t += dt) {
    x += v * dt;
    d.update(x, v, dt);
    if (t > hold_s - 1.0) {
      sum += d.following_error_mm();
      ++n;
    }
  }
  return sum / n;
}
}  // namespace

TEST(SimDrive, T1_FeedbackQuantisedTo0127mm) {
  SimDrive d(axis(1.0));
  for (int i = 0; i < 2000; ++i) d.update(10.0, 0, 0.001);
  const double q = 65.0 / 512.0;
  EXPECT_NEAR(q, 0.126953125, 1e-12);
  const double counts = d.measured_mm() / q;
  EXPECT_NEAR(counts, std::round(counts), 1e-9);   // a whole number of counts
  EXPECT_LE(std::abs(d.true_mm() - 10.0), q);       // the real point lies within a count
  EXPECT_LE(std::abs(d.measured_mm() - d.true_mm()), q / 2 + 1e-12);
}

TEST(SimDrive, SteadyFollowingErrorIsVOverKvWithoutFeedForward) {
  SimDrive d(axis(0.0));
  const double v = 60.0;  // mm/s
  // v/Kv, less the one period of travel the sampled loop gains by acting on the previous sample
  // (the error is read after the period's move): 2 mm − 0.06 mm, within quantisation noise.
  EXPECT_NEAR(steady_ferror(d, v, 3.0), v / 30.0 - v * 0.001, 0.01);
}

TEST(SimDrive, SteadyFollowingErrorNearZeroWithFeedForward) {
  SimDrive d(axis(1.0));
  EXPECT_LT(std::abs(steady_ferror(d, 60.0, 3.0)), 0.07);  // below half a count
}

TEST(SimDrive, HeavierMassFollowsLessTightly) {
  // A step in velocity: the peak following error grows with the moving mass (SPC M37).
  auto peak = [](double mass) {
    SimDrive d(axis(1.0));
    d.set_mass_factor(mass);
    double x = 0, worst = 0;
    for (int i = 0; i < 500; ++i) {
      x += 100 * 0.001;
      d.update(x, 100, 0.001);
      worst = std::max(worst, std::abs(d.following_error_mm()));
    }
    return worst;
  };
  EXPECT_GT(peak(4.0), 1.5 * peak(1.0));
}

TEST(SimDrive, LimitSwitchesCloseBeyondTravel) {
  auto a = axis(1.0);
  a.min_mm = 0;
  a.max_mm = 100;
  a.switch_overtravel_mm = 2;
  SimDrive d(a, 50);
  EXPECT_FALSE(d.limit_negative());
  SimDrive low(a, -2.5);
  EXPECT_TRUE(low.limit_negative());
  SimDrive high(a, 102.0);
  EXPECT_TRUE(high.limit_positive());
}
