// S-8 Start/Stop mode on the real controller: self-test, START, STOP, reset, ENABLE, errors, and the
// S-7 M00 handshake through the filtered I/O image.
#include <gtest/gtest.h>

#include <cmath>

#include "spc_modes_rig.hpp"

namespace softmc::control::spc {
namespace {

using modes_testing::ModesRig;

ControllerConfig start_stop_cfg() {
  ControllerConfig c;
  c.mode = SpcMode::StartStop;
  c.program_a = 1;
  c.program_b = 2;
  c.self_test_s = 0.2;
  return c;
}

// Task A moves X, task B moves Y; both end with M30.
void load_two_moves(ModesRig& r) {
  r.load(1, "N000 G01 X500 FX0\nN001 G01 X100 FX0\nN002 M30\n", false);
  r.load(2, "N000 G01 Y300 FY50\nN001 M30\n", false);
}

TEST(Spc200, S8_PowerUpSelfTestThenReadyMcSync) {
  ModesRig r;
  load_two_moves(r);
  r.power_up(start_stop_cfg());
  r.run(0.19);
  EXPECT_FALSE(r.out(sig::kReady));
  EXPECT_FALSE(r.out(sig::kMcA));
  EXPECT_EQ(r.ctl->status().start_stop, StartStopState::SelfTest);
  r.run(0.02);
  EXPECT_TRUE(r.out(sig::kReady));
  EXPECT_TRUE(r.out(sig::kMcA));
  EXPECT_TRUE(r.out(sig::kMcB));
  EXPECT_FALSE(r.out(sig::kSyncOA));
  EXPECT_FALSE(r.out(sig::kSyncOB));
  EXPECT_EQ(r.ctl->status().start_stop, StartStopState::Idle);
}

TEST(Spc200, S8_SelfTestWaitsForEnableStopAndNoStart) {
  ModesRig r;
  load_two_moves(r);
  r.power_up(start_stop_cfg(), /*enable=*/true, /*stop=*/false);
  r.run(1.0);
  EXPECT_FALSE(r.out(sig::kReady));
  r.set(sig::kStop, true);
  r.run(0.1);
  r.set(sig::kStart, true);  // a held START restarts the self-test
  r.run(0.15);
  r.set(sig::kStart, false);
  r.run(0.15);
  EXPECT_FALSE(r.out(sig::kReady));
  EXPECT_GE(r.run_until([&] { return r.out(sig::kReady); }, 0.2), 1);
  // The START that was held during the self-test did not start anything.
  EXPECT_EQ(r.ctl->status().start_stop, StartStopState::Idle);
}

TEST(Spc200, S8_SelfTestFailureIsNotClearable) {
  ModesRig r;
  load_two_moves(r);
  auto cfg = start_stop_cfg();
  cfg.self_test_fails = true;
  r.power_up(cfg);
  r.run(0.3);
  EXPECT_TRUE(r.ctl->status().fatal);
  r.pulse(sig::kStart, 0.02);
  r.set(sig::kStop, false);
  r.run(0.02);
  r.pulse(sig::kStart, 0.02);
  r.run(0.1);
  EXPECT_FALSE(r.out(sig::kReady));
  EXPECT_DOUBLE_EQ(r.x(), 0.0);
}

TEST(Spc200, S8_StartPulseRunsBothTasks) {
  ModesRig r;
  load_two_moves(r);
  r.power_up(start_stop_cfg());
  r.run(0.25);
  r.pulse(sig::kStart, 0.02);
  EXPECT_EQ(r.ctl->status().start_stop, StartStopState::Running);
  EXPECT_GT(r.x(), 0.0);
  EXPECT_GT(r.y(), 0.0);
  EXPECT_FALSE(r.out(sig::kMcA));  // S-8: MC = motion of the current instruction finished
  EXPECT_FALSE(r.out(sig::kMcB));
  ASSERT_GT(r.run_until([&] { return r.ctl->status().start_stop == StartStopState::Idle; }, 5.0), 0);
  EXPECT_NEAR(r.x(), 100.0, 1e-9);
  EXPECT_NEAR(r.y(), 300.0, 1e-9);
  EXPECT_TRUE(r.out(sig::kMcA));
  EXPECT_TRUE(r.out(sig::kMcB));
  EXPECT_TRUE(r.out(sig::kReady));
}

TEST(Spc200, S8_StopHaltsAxesAtOnceAndStartResumes) {
  ModesRig r;
  load_two_moves(r);
  r.power_up(start_stop_cfg());
  r.run(0.25);
  r.pulse(sig::kStart, 0.02);
  r.run(0.2);  // X cruising at 1000 mm/s
  ASSERT_GT(r.axes.output().velocity_mm_s[0], 900.0);
  r.set(sig::kStop, false);
  // The filter takes 5 ms; then the very next setpoint stands still (no ramp).
  ASSERT_GT(r.run_until([&] { return r.ctl->status().start_stop == StartStopState::Stopped; }, 0.01), 0);
  const double x_stop = r.x();
  EXPECT_EQ(r.axes.output().velocity_mm_s[0], 0.0);
  r.run(0.1);
  EXPECT_EQ(r.x(), x_stop);
  EXPECT_FALSE(r.out(sig::kMcA));
  EXPECT_TRUE(r.out(sig::kReady));
  // STOP back to 1 alone does not move anything; a START pulse resumes the halted programs.
  r.set(sig::kStop, true);
  r.run(0.1);
  EXPECT_EQ(r.x(), x_stop);
  r.pulse(sig::kStart, 0.02);
  ASSERT_GT(r.run_until([&] { return r.ctl->status().start_stop == StartStopState::Idle; }, 5.0), 0);
  EXPECT_NEAR(r.x(), 100.0, 1e-9);
  EXPECT_NEAR(r.y(), 300.0, 1e-9);
}

TEST(Spc200, S8_StartPulseWithStopLowIsReset) {
  ModesRig r;
  load_two_moves(r);
  r.power_up(start_stop_cfg());
  r.run(0.25);
  r.pulse(sig::kStart, 0.02);
  ASSERT_GT(r.run_until([&] { return r.ctl->task(TaskId::A).status().line == 1; }, 2.0), 0);
  r.run(0.05);  // on its way back to X100
  r.set(sig::kStop, false);
  r.run(0.02);
  EXPECT_EQ(r.ctl->task(TaskId::A).status().line, 1);
  r.pulse(sig::kStart, 0.02);  // STOP=0: the reset function
  r.run(0.01);
  EXPECT_EQ(r.ctl->status().start_stop, StartStopState::Idle);
  EXPECT_EQ(r.ctl->task(TaskId::A).status().line, 0);  // pointers back to the first line
  EXPECT_TRUE(r.out(sig::kMcA));
  EXPECT_TRUE(r.out(sig::kMcB));
  // A new start runs from N000 (X back to 500 first).
  r.set(sig::kStop, true);
  r.run(0.02);
  r.pulse(sig::kStart, 0.02);
  double x_max = 0;
  ASSERT_GT(r.run_until(
                [&] {
                  x_max = std::max(x_max, r.x());
                  return r.ctl->status().start_stop == StartStopState::Idle;
                },
                5.0),
            0);
  EXPECT_NEAR(x_max, 500.0, 1e-9);
  EXPECT_NEAR(r.x(), 100.0, 1e-9);
}

TEST(Spc200, S8_StartPulseClearsAClearableError) {
  ModesRig r;
  load_two_moves(r);
  r.power_up(start_stop_cfg());
  r.run(0.25);
  r.pulse(sig::kStart, 0.02);
  r.run(0.1);
  r.ctl->raise_fault("following error on X");
  r.cycle();
  EXPECT_FALSE(r.out(sig::kReady));
  EXPECT_STREQ(r.ctl->status().message, "following error on X");
  const double x_stop = r.x();
  r.run(0.05);
  EXPECT_EQ(r.x(), x_stop);  // the error stopped the axes
  r.pulse(sig::kStart, 0.02);  // clears, does not start
  r.run(0.01);
  EXPECT_TRUE(r.out(sig::kReady));
  EXPECT_FALSE(r.ctl->status().error);
  EXPECT_EQ(r.ctl->status().start_stop, StartStopState::Stopped);
  EXPECT_EQ(r.x(), x_stop);
  r.pulse(sig::kStart, 0.02);  // now it starts
  ASSERT_GT(r.run_until([&] { return r.ctl->status().start_stop == StartStopState::Idle; }, 5.0), 0);
  EXPECT_NEAR(r.x(), 100.0, 1e-9);
}

TEST(Spc200, S8_TaskErrorDropsReady) {
  ModesRig r;
  r.load(1, "N000 G01 X2000 FX0\nN001 M30\n", false);  // beyond the travel: the task refuses it
  r.power_up([] {
    auto c = start_stop_cfg();
    c.program_b = -1;
    return c;
  }());
  r.run(0.25);
  r.pulse(sig::kStart, 0.02);
  EXPECT_FALSE(r.out(sig::kReady));
  EXPECT_EQ(r.ctl->status().start_stop, StartStopState::Error);
  EXPECT_NE(std::string(r.ctl->status().message), "");
}

TEST(Spc200, S8_EnableLowDisablesDrivesAndDropsReady) {
  ModesRig r;
  load_two_moves(r);
  r.power_up(start_stop_cfg());
  r.run(0.25);
  r.pulse(sig::kStart, 0.02);
  r.run(0.05);
  r.set(sig::kEnable, false);
  r.run(0.01);
  EXPECT_FALSE(r.out(sig::kReady));
  EXPECT_FALSE(r.ctl->status().drives_enabled);
  const double x_off = r.x();
  r.run(0.1);
  EXPECT_EQ(r.x(), x_off);
  r.pulse(sig::kStart, 0.02);  // ignored while disabled
  EXPECT_EQ(r.x(), x_off);
  r.set(sig::kEnable, true);
  r.run(0.01);
  EXPECT_TRUE(r.out(sig::kReady));
  EXPECT_TRUE(r.ctl->status().drives_enabled);
  EXPECT_EQ(r.ctl->status().start_stop, StartStopState::Stopped);
}

TEST(Spc200, S7_M00HandshakeThroughFilteredInputs) {
  ModesRig r;
  r.load(1, "N000 M00\nN001 G01 X50 FX0\nN002 M30\n", false);
  auto cfg = start_stop_cfg();
  cfg.program_b = -1;
  r.power_up(cfg);
  r.run(0.25);
  r.pulse(sig::kStart, 0.02);
  r.run(0.05);
  EXPECT_TRUE(r.ctl->task(TaskId::A).status().waiting_sync);
  EXPECT_FALSE(r.out(sig::kSyncOA));
  r.set(sig::kSyncIA, true);
  // Rising edge (after the 5 ms filter): SYNC_OA=1, the pointer stays on M00.
  ASSERT_GT(r.run_until([&] { return r.out(sig::kSyncOA); }, 0.02), 3);
  r.run(0.05);
  EXPECT_DOUBLE_EQ(r.x(), 0.0);
  r.set(sig::kSyncIA, false);
  ASSERT_GT(r.run_until([&] { return !r.out(sig::kSyncOA); }, 0.02), 3);
  ASSERT_GT(r.run_until([&] { return r.ctl->status().start_stop == StartStopState::Idle; }, 2.0), 0);
  EXPECT_NEAR(r.x(), 50.0, 1e-9);
  EXPECT_FALSE(r.out(sig::kSyncOB));
}

}  // namespace
}  // namespace softmc::control::spc
