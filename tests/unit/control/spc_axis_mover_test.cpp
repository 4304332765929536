// The SPC axis setpoint generator: trapezoid, Otg1 S-curve and sine-squared kernels, and takeovers (S-2, S-3).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "control/spc/task_axis_mover.hpp"
#include "spc_task_rig.hpp"

namespace softmc::control::spc {
namespace {

constexpr double kDt = 0.001;

// Runs a mover to rest, differentiating its setpoints: peak |v|, |a|, |jerk| (the first two differences
// mix the state's instantaneous v and a with the sampled ones, so they do not count).
struct Peaks {
  double v = 0, a = 0, j = 0;
  long cycles = 0;
};
Peaks run_to_rest(AxisMover& m, long max_cycles = 100000) {
  Peaks pk;
  double p_prev = m.state().p_mm, v_prev = m.state().v_mm_s, a_prev = m.acceleration_mm_s2();
  for (; pk.cycles < max_cycles && !m.done(); ++pk.cycles) {
    const auto s = m.step();
    const double v = (s.p_mm - p_prev) / kDt;
    const double a = (v - v_prev) / kDt;
    pk.v = std::max(pk.v, std::fabs(v));
    pk.a = std::max(pk.a, std::fabs(a));
    if (pk.cycles > 1) pk.j = std::max(pk.j, std::fabs(a - a_prev) / kDt);
    p_prev = s.p_mm;
    v_prev = v;
    a_prev = a;
  }
  return pk;
}

TEST(Spc200, S2_MoverTrapezoidKeepsSeparateAccelerationAndDeceleration) {
  AxisMover m;
  m.configure(kDt, 0);
  m.retarget(200, {500, 5000, 1000, 0}, MoverProfile::Trapezoid);
  // Accelerating at 5000 for 10 cycles reaches 50 mm/s.
  for (int i = 0; i < 10; ++i) m.step();
  EXPECT_NEAR(m.state().v_mm_s, 50.0, 1e-9);
  const auto pk = run_to_rest(m);
  EXPECT_DOUBLE_EQ(m.state().p_mm, 200.0);
  EXPECT_LE(pk.v, 500.0 + 1e-6);
  // Braking at 1000 mm/s² from ~400 mm/s takes far longer than accelerating at 5000 to it.
  EXPECT_GT(pk.cycles, 400);
}

TEST(Spc200, S2_MoverSCurveIsJerkLimitedAndLandsExactly) {
  AxisMover m;
  m.configure(kDt, 10);
  m.retarget(310, {500, 5000, 5000, 100000}, MoverProfile::SCurve);
  const auto pk = run_to_rest(m);
  EXPECT_DOUBLE_EQ(m.state().p_mm, 310.0);
  EXPECT_LE(pk.v, 500.0 * 1.001);
  EXPECT_LE(pk.a, 5000.0 * 1.02);
  EXPECT_LE(pk.j, 100000.0 * 1.05);  // a trapezoid's jerk would be a/dt = 5e6
}

TEST(Spc200, S2_MoverG02IsSineSquaredWithBoundedJerk) {
  AxisMover m;
  m.configure(kDt, 0);
  const double j = 5000 * M_PI / 0.1;  // g02_ramp_s = 0.1
  m.retarget(-400, {500, 5000, 5000, j}, MoverProfile::SineSquared);
  // The first samples follow a sin² acceleration: a(t) = a_p·sin²(πt/T), T = 2·500/5000 = 0.2 s.
  m.step();
  EXPECT_NEAR(m.acceleration_mm_s2(), -5000 * std::pow(std::sin(M_PI * 0.001 / 0.2), 2), 1e-6);
  const auto pk = run_to_rest(m);
  EXPECT_DOUBLE_EQ(m.state().p_mm, -400.0);
  EXPECT_LE(pk.a, 5000.0 * 1.01);
  EXPECT_LE(pk.j, j * 1.05);
}

// G25 takeover of an S-curve or G02 motion: p, v and a stay continuous (no acceleration step).
void expect_smooth_takeover(MoverProfile first) {
  AxisMover m;
  m.configure(kDt, 0);
  const MoverLimits lim{500, 5000, 5000, 100000};
  m.retarget(1000, lim, first);
  while (m.state().p_mm < 300) m.step();
  const double a_before = m.acceleration_mm_s2(), v_before = m.state().v_mm_s;
  ASSERT_GT(v_before, 100);
  m.retarget(600, {250, 5000, 5000, 100000}, MoverProfile::SCurve);
  m.step();
  EXPECT_NEAR(m.state().v_mm_s, v_before, 5000 * kDt * 1.01);
  EXPECT_NEAR(m.acceleration_mm_s2(), a_before, 100000 * kDt * 1.01);
  const auto pk = run_to_rest(m);
  EXPECT_DOUBLE_EQ(m.state().p_mm, 600.0);
  EXPECT_LE(pk.j, 100000 * 1.05);
}

TEST(Spc200, S3_G25TakeoverOfAnSCurveIsContinuousInAcceleration) { expect_smooth_takeover(MoverProfile::SCurve); }
TEST(Spc200, S3_G25TakeoverOfAG02MotionIsContinuousInAcceleration) {
  expect_smooth_takeover(MoverProfile::SineSquared);
}

TEST(Spc200, S2_MoverHaltStopsAtOnce) {
  AxisMover m;
  m.configure(kDt, 0);
  m.retarget(1000, {500, 5000, 5000, 100000}, MoverProfile::SCurve);
  for (int i = 0; i < 100; ++i) m.step();
  const double p = m.state().p_mm;
  m.halt();
  EXPECT_TRUE(m.done());
  m.step();
  EXPECT_EQ(m.state().p_mm, p);
  EXPECT_EQ(m.state().v_mm_s, 0);
}

// Through the task: `g01_s_curve` makes G01 jerk-limited with the axis's jerk; without it G01 is a trapezoid.
TEST(Spc200, S2_G01SCurveOptionLimitsJerk) {
  auto max_jerk = [](bool s_curve) {
    auto cfg = testing::rig_axes();
    for (auto& a : cfg.axis) a.j_max_mm_s3 = 50000;
    cfg.s_curve = s_curve;
    program::spc::ProgramStore store;
    Registers regs;
    TaskAxes axes(cfg);
    IoImage io;
    Task t(TaskId::A, store, regs, axes);
    core::Diagnostics d;
    EXPECT_TRUE(store.add(1, "N000 G01 X300 FX0\n", "P1.spc", {false, 1}, d));
    t.set_program(1);
    t.start();
    double p_prev = 0, v_prev = 0, a_prev = 0, jmax = 0;
    for (int i = 0; i < 5000 && (t.status().running || axes.moving(0)); ++i) {
      t.update(kDt, io);
      axes.step();
      const double v = (axes.setpoint_mm(0) - p_prev) / kDt, a = (v - v_prev) / kDt;
      if (i > 1) jmax = std::max(jmax, std::fabs(a - a_prev) / kDt);
      p_prev = axes.setpoint_mm(0);
      v_prev = v;
      a_prev = a;
    }
    EXPECT_DOUBLE_EQ(axes.setpoint_mm(0), 300.0);
    return jmax;
  };
  EXPECT_LE(max_jerk(true), 50000 * 1.05);
  EXPECT_GT(max_jerk(false), 1e6);
}

}  // namespace
}  // namespace softmc::control::spc
