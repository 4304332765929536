// SPC task execution: flow, calls, registers, waits, M00, motion rules (S-2..S-7).
#include <gtest/gtest.h>

#include <cmath>

#include "spc_task_rig.hpp"

namespace softmc::control::spc {
namespace {

using testing::Rig;

TEST(Spc200, S4_ConditionalJumpLoopCountsWithRegisters) {
  Rig r;
  r.load(1, "N000 #LR4=0\nN001 #AR4=1\nN002 #TR4=5 4\nN003 E05 1\nN004 #SF7\nN005 M30\n");
  r.a.set_program(1);
  r.a.start();
  r.cycle();
  EXPECT_EQ(r.regs.integer(4), 5);
  EXPECT_TRUE(r.regs.flag(7));
  EXPECT_FALSE(r.a.status().running);  // M30 ended the task, pointer back at the first line
  EXPECT_EQ(r.a.status().line, 0);
}

TEST(Spc200, S4_JumpThroughRegisterToAMissingLineIsAnError) {
  Rig r;
  r.load(1, "N000 #LR2=20\nN010 E05 R2\nN020 #LR2=7\nN030 E05 R2\n");
  r.a.set_program(1);
  r.a.start();
  r.cycle();
  const auto s = r.a.status();
  EXPECT_TRUE(s.error);
  EXPECT_EQ(s.program, 1);
  EXPECT_EQ(s.line, 30);
  EXPECT_STREQ(s.message, "jump to a line this program does not have (S-4)");
}

// P1 → P2 → P3 → P4 → P5 is four nested calls; P5 calling P6 would be the fifth.
void load_chain(Rig& r, bool fifth) {
  r.load(1, "N000 L2\nN001 #AR0=1\nN002 M30\n");
  for (int n = 2; n <= 4; ++n)
    r.load(n, "N000 L" + std::to_string(n + 1) + "\nN001 #AR" + std::to_string(n) + "=1\nN002 M02\n");
  r.load(5, fifth ? "N000 #AR5=1\nN001 L6\nN002 M02\n" : "N000 #AR5=1\nN001 M02\n");
  r.load(6, "N000 M02\n");
}

TEST(Spc200, S4_FourNestedCallsReturnInOrder) {
  Rig r;
  load_chain(r, false);
  r.a.set_program(1);
  r.a.start();
  r.cycle();
  ASSERT_FALSE(r.a.status().error) << r.a.status().message;
  for (int i : {0, 2, 3, 4, 5}) EXPECT_EQ(r.regs.integer(i), 1) << i;
  EXPECT_FALSE(r.a.status().running);
}

TEST(Spc200, S4_FifthNestedCallIsAnError) {
  Rig r;
  load_chain(r, true);
  r.a.set_program(1);
  r.a.start();
  r.cycle();
  const auto s = r.a.status();
  ASSERT_TRUE(s.error);
  EXPECT_EQ(s.program, 5);
  EXPECT_EQ(s.line, 1);
  EXPECT_STREQ(s.message, "a fifth nested call: at most 4 (S-4)");
  EXPECT_EQ(r.regs.integer(5), 1);
}

TEST(Spc200, S4_CallThroughRegisterOfAMissingProgramIsAnError) {
  Rig r;
  r.load(1, "N000 #LR9=42\nN001 LR9\n");
  r.a.set_program(1);
  r.a.start();
  r.cycle();
  EXPECT_TRUE(r.a.status().error);
  EXPECT_EQ(r.a.status().line, 1);
}

TEST(Spc200, S5_IntegerOverflowIsAnError) {
  Rig r;
  r.load(1, "N000 #LR1=32767\nN001 #AR1=1\nN002 M30\n");
  r.a.set_program(1);
  r.a.start();
  r.cycle();
  EXPECT_TRUE(r.a.status().error);
  EXPECT_EQ(r.a.status().line, 1);
  EXPECT_EQ(r.regs.integer(1), 32767);  // not wrapped, not changed
  Rig n;
  n.load(1, "N000 #LR1=-32767\nN001 #AR1=-1\n");
  n.a.set_program(1);
  n.a.start();
  n.cycle();
  EXPECT_TRUE(n.a.status().error);
  EXPECT_EQ(n.regs.integer(1), -32767);
}

TEST(Spc200, S5_PositionRegistersLoadAddCapture) {
  Rig r;
  r.load(1, "N000 G28 @10 X12.5 Y-3 Z0 U9999.99\nN001 G29 @10 X@10 Y0.01\nN002 G00 X250.25\nN003 M38 @11 X\n"
            "N004 G29 @10 U0.01\nN005 M30\n");
  r.a.set_program(1);
  r.a.start();
  ASSERT_GT(r.run_until([&] { return !r.a.status().running; }), 0);
  EXPECT_EQ(r.regs.position_centi(0, 10), 2500);
  EXPECT_EQ(r.regs.position_centi(1, 10), -299);
  EXPECT_EQ(r.regs.position_centi(0, 11), 25025);
  // G29 past 9999.99 is an error and leaves the register as it was.
  EXPECT_TRUE(r.a.status().error);
  EXPECT_EQ(r.a.status().line, 4);
  EXPECT_EQ(r.regs.position_centi(3, 10), 999999);
}

TEST(Spc200, S6_WaitOnItsOwnLineCostsOneEvaluationPerCycle) {
  Rig r;
  r.load(1, "N100 #TNI0.0 100\nN101 #SQ2.3\nN102 #SF1\nN103 M30\n");
  r.a.set_program(1);
  r.a.start();
  for (int i = 0; i < 100; ++i) r.cycle();
  EXPECT_EQ(r.a.instructions_executed(), 100u);
  EXPECT_EQ(r.a.status().line, 100);
  EXPECT_FALSE(r.io.get_output(2, 3));
  r.io.set_input(0, 0, true);
  r.cycle();
  EXPECT_TRUE(r.io.get_output(2, 3));
  EXPECT_TRUE(r.regs.flag(1));
}

TEST(Spc200, S6_TestsOfOutputsAndFlagsBranchBothWays) {
  Rig r;
  r.load(1, "N0 #TQ2.0 3\nN1 #SF2\nN2 E05 4\nN3 #SF3\nN4 #TNF2 6\nN5 #SQ3.15\nN6 #TF9 8\nN7 #SQ1.0\nN8 M30\n");
  r.a.set_program(1);
  r.a.start();
  r.cycle();
  EXPECT_TRUE(r.regs.flag(2));
  EXPECT_FALSE(r.regs.flag(3));
  EXPECT_TRUE(r.io.get_output(3, 15));
  EXPECT_TRUE(r.io.get_output(1, 0));
  Rig s;
  s.load(1, "N0 #TQ2.0 3\nN1 #SF2\nN2 E05 4\nN3 #SF3\nN4 M30\n");
  s.io.set_output(2, 0, true);
  s.a.set_program(1);
  s.a.start();
  s.cycle();
  EXPECT_FALSE(s.regs.flag(2));
  EXPECT_TRUE(s.regs.flag(3));
}

TEST(Spc200, S6_ABusyLoopIsBoundedPerCycle) {
  Rig r;
  r.load(1, "N000 #AR0=1\nN001 #TR0=30000 3\nN002 E05 0\nN003 M30\n");
  r.a.set_program(1);
  r.a.start();
  r.cycle();
  EXPECT_EQ(r.a.instructions_executed(), static_cast<std::uint64_t>(kMaxInstructionsPerCycle));
  EXPECT_TRUE(r.a.status().running);
}

TEST(Spc200, S7_SyncStepTransitions) {
  struct Row {
    SyncState s;
    bool prev, in, out_before;
    SyncState next;
    bool out_after;
  };
  const Row rows[] = {
      {SyncState::Idle, false, true, false, SyncState::Idle, false},
      {SyncState::WaitRise, false, false, false, SyncState::WaitRise, false},
      {SyncState::WaitRise, true, true, false, SyncState::WaitRise, false},  // already high: no edge
      {SyncState::WaitRise, true, false, false, SyncState::WaitRise, false},
      {SyncState::WaitRise, false, true, false, SyncState::WaitFall, true},
      {SyncState::WaitFall, true, true, true, SyncState::WaitFall, true},
      {SyncState::WaitFall, true, false, true, SyncState::Done, false},
      {SyncState::Done, false, false, false, SyncState::Done, false},
  };
  for (const auto& r : rows) {
    bool out = r.out_before;
    EXPECT_EQ(sync_step(r.s, r.prev, r.in, out), r.next) << static_cast<int>(r.s) << r.prev << r.in;
    EXPECT_EQ(out, r.out_after);
  }
}

TEST(Spc200, S7_M00WaitsForRisingEdgeThenFallingEdge) {
  Rig r;
  r.load(1, "N000 M00\nN001 #SQ2.0\nN002 M30\n");
  r.load(2, "N000 M00\nN001 #SQ2.1\nN002 M30\n");
  r.a.set_program(1);
  r.b.set_program(2);
  r.io.set_input(0, 6, true);  // SYNC_IA already high when M00 is reached: not an edge
  r.a.start();
  r.b.start();
  for (int i = 0; i < 5; ++i) r.cycle();
  EXPECT_TRUE(r.a.status().waiting_sync);
  EXPECT_FALSE(r.io.get_output(0, 6));
  r.io.set_input(0, 6, false);
  r.cycle();
  r.io.set_input(0, 6, true);
  r.cycle();
  EXPECT_TRUE(r.io.get_output(0, 6));   // SYNC_OA: the pointer stands on M00
  EXPECT_FALSE(r.io.get_output(0, 5));  // task B untouched
  EXPECT_FALSE(r.io.get_output(2, 0));
  r.cycle();
  EXPECT_TRUE(r.a.status().waiting_sync);
  r.io.set_input(0, 6, false);
  r.cycle();
  EXPECT_FALSE(r.io.get_output(0, 6));
  EXPECT_TRUE(r.io.get_output(2, 0));
  EXPECT_FALSE(r.a.status().running);
  // Task B on SYNC_IB (I0.5) / SYNC_OB (Q0.5).
  EXPECT_TRUE(r.b.status().waiting_sync);
  r.io.set_input(0, 5, true);
  r.cycle();
  EXPECT_TRUE(r.io.get_output(0, 5));
  r.io.set_input(0, 5, false);
  r.cycle();
  EXPECT_FALSE(r.io.get_output(0, 5));
  EXPECT_TRUE(r.io.get_output(2, 1));
}

TEST(Spc200, S3_DwellCountsHundredths) {
  Rig r;
  r.load(1, "N000 G04 10\nN001 #SF0\n");
  r.a.set_program(1);
  r.a.start();
  const long n = r.run_until([&] { return r.regs.flag(0); });
  EXPECT_EQ(n, 101);  // started in cycle 1, 100 cycles of 1 ms, the next line in cycle 101
}

TEST(Spc200, S3_G25Example1ReleasesThePointerAtX500) {
  Rig r;
  r.load(1, "N000 G00 X100\nN001 G25 X50\nN002 G01 X1000 FX0\nN003 G01 X1000 FX50\nN004 M30\n");
  r.a.set_program(1);
  r.a.start();
  ASSERT_GT(r.run_until([&] { return r.a.status().line == 2; }), 0);
  EXPECT_NEAR(r.x(), 100.0, 0.01);  // N002 has just started
  double x_prev = r.x(), v_prev = 0;
  double max_dv = 0;
  bool released = false;
  long released_at = -1;
  for (int i = 0; i < 20000 && (r.a.status().running || r.axes.moving(0)); ++i) {
    const bool before = r.a.status().line == 2;
    r.cycle();
    if (before && r.a.status().line == 3 && !released) {
      released = true;
      // The pointer left N002 the cycle after the setpoint reached 500 (the tasks run before the axes).
      EXPECT_GE(x_prev, 500.0);
      EXPECT_LT(x_prev, 500.0 + 500.0 * 0.001 + 1e-9);
      released_at = i;
    }
    const double v = (r.x() - x_prev) / 0.001;
    if (released && i < released_at + 200) max_dv = std::max(max_dv, std::fabs(v - v_prev));
    x_prev = r.x();
    v_prev = v;
  }
  EXPECT_TRUE(released);
  // G25 stays in force: N003 starts beyond its pass point (500), so the pointer leaves it at once
  // and the task ends while X still slows to 50 % and runs on to 1000.
  EXPECT_DOUBLE_EQ(r.x(), 1000.0);
  // N003 took X over on the fly: the speed changed by at most one acceleration step per cycle.
  EXPECT_LE(max_dv, 5000.0 * 0.001 + 1e-6);
}

TEST(Spc200, S3_G25Example2YStartsOnceXPassed400) {
  Rig r;
  r.load(1, "N000 G00 X0 Y0\nN001 G25 X40\nN002 G00 X1000\nN003 G00 Y300\nN004 M30\n");
  r.a.set_program(1);
  r.a.start();
  ASSERT_GT(r.run_until([&] { return r.axes.setpoint_mm(1) > 0; }), 0);
  EXPECT_GE(r.x(), 400.0);
  EXPECT_LT(r.x(), 401.0);
  ASSERT_GT(r.run_until([&] { return !r.a.status().running; }), 0);
  EXPECT_DOUBLE_EQ(r.axes.setpoint_mm(1), 300.0);
}

TEST(Spc200, S2_AxesOfOneLineStartTogetherEachAtItsOwnSpeed) {
  Rig r;
  r.load(1, "N000 G01 X200 FX50 Y200 FY0\nN001 #SF0\n");
  r.a.set_program(1);
  r.a.start();
  r.cycle();
  EXPECT_GT(r.axes.setpoint_mm(0), 0);
  EXPECT_GT(r.axes.setpoint_mm(1), 0);
  double vx = 0, vy = 0;
  long y_done = -1;
  const long n = r.run_until([&] {
    vx = std::max(vx, std::fabs(r.axes.output().velocity_mm_s[0]));
    vy = std::max(vy, std::fabs(r.axes.output().velocity_mm_s[1]));
    if (y_done < 0 && !r.axes.moving(1)) y_done = r.cycles;
    return r.regs.flag(0);
  });
  ASSERT_GT(n, 0);
  EXPECT_NEAR(vx, 250.0, 1e-6);  // 50 % of 500 mm/s
  EXPECT_NEAR(vy, 500.0, 1e-6);
  EXPECT_LT(y_done, n - 100);  // Y finished long before; the line waited for X
  EXPECT_FALSE(r.axes.moving(0));
}

TEST(Spc200, S2_AnAxisMovingUnderTheOtherTaskIsAnError) {
  Rig r;
  r.load(1, "N000 G01 X1000 FX10\nN001 M30\n");
  r.load(2, "N000 G04 5\nN001 G00 X0\nN002 M30\n");
  r.a.set_program(1);
  r.b.set_program(2);
  r.a.start();
  r.b.start();
  r.run_until([&] { return r.b.status().error; }, 200);
  EXPECT_TRUE(r.b.status().error);
  EXPECT_STREQ(r.b.status().message, "axis is moving under the other task");
  EXPECT_EQ(r.b.status().line, 1);
  // Once X is at rest, task B may command it (different times are fine).
  ASSERT_GT(r.run_until([&] { return !r.a.status().running; }), 0);
  r.b.reset();
  r.b.start();
  ASSERT_GT(r.run_until([&] { return !r.b.status().running; }), 0);
  EXPECT_FALSE(r.b.status().error);
  EXPECT_DOUBLE_EQ(r.x(), 0.0);
}

TEST(Spc200, S2_RelativeMoveRefusedAfterStopUntilAnAbsoluteOne) {
  Rig r;
  r.load(1, "N000 G00 G90 X500\nN001 M30\n");
  r.load(2, "N000 G00 G91 X10\nN001 M30\n");
  r.load(3, "N000 G00 G90 X100\nN001 G00 G91 X10\nN002 M30\n");
  r.a.set_program(1);
  r.a.start();
  r.run_until([&] { return r.x() > 50; });
  r.axes.stop_all();  // STOP=0
  r.a.halt();
  const double stopped = r.x();
  r.cycle();
  EXPECT_DOUBLE_EQ(r.x(), stopped);  // no ramp
  r.a.set_program(2);
  r.a.start();
  r.cycle();
  EXPECT_TRUE(r.a.status().error);
  EXPECT_STREQ(r.a.status().message, "relative move refused after a stop: give the axis an absolute one");
  r.a.set_program(3);
  r.a.start();
  ASSERT_GT(r.run_until([&] { return !r.a.status().running; }), 0);
  EXPECT_FALSE(r.a.status().error);
  EXPECT_DOUBLE_EQ(r.x(), 110.0);
}

TEST(Spc200, S8_HaltedMotionIsReissuedOnStart) {
  Rig r;
  r.load(1, "N000 G00 X800\nN001 #SF0\nN002 M30\n");
  r.a.set_program(1);
  r.a.start();
  r.run_until([&] { return r.x() > 100; });
  r.axes.stop_all();
  r.a.halt();
  EXPECT_EQ(r.a.status().line, 0);
  r.a.start();
  ASSERT_GT(r.run_until([&] { return r.regs.flag(0); }), 0);
  EXPECT_DOUBLE_EQ(r.x(), 800.0);
}

TEST(Spc200, S3_G61WindowsWaitForTheActualPosition) {
  Rig r;
  r.load(1, "N000 G61 X5\nN001 G00 X100\nN002 #SF0\n");
  r.a.set_program(1);
  r.a.start();
  r.axes.set_actual_mm(0, 0.0);
  // The setpoint arrives but the drive lags 0.15 mm: outside window of condition 5 (±0.1).
  ASSERT_GT(r.run_until([&] {
    r.axes.set_actual_mm(0, r.x() - 0.15);
    return !r.axes.moving(0);
  }), 0);
  for (int i = 0; i < 200; ++i) r.cycle();
  EXPECT_FALSE(r.regs.flag(0));
  EXPECT_FALSE(r.a.status().motion_done);
  r.axes.set_actual_mm(0, 100.05);  // inside ±0.1 from now on: wait the settling time (50 ms)
  const long n = r.run_until([&] { return r.regs.flag(0); });
  EXPECT_GE(n, 50);
  EXPECT_LE(n, 52);
  EXPECT_TRUE(r.a.status().motion_done);
}

TEST(Spc200, S3_M37ScalesTheMassPublishedForTheDrive) {
  Rig r;
  r.load(1, "N000 M37 X40 Y0\nN001 M30\n");
  r.a.set_program(1);
  r.a.start();
  r.cycle();
  EXPECT_DOUBLE_EQ(r.axes.output().mass_factor[0], 0.40);
  EXPECT_DOUBLE_EQ(r.axes.output().mass_factor[1], 1.0);
}

TEST(Spc200, S3_G08AndG09ScaleAccelerationAndDeceleration) {
  Rig r;
  r.load(1, "N000 G08 X10\nN001 G09 X50\nN002 G00 X500\nN003 M30\n");
  r.a.set_program(1);
  r.a.start();
  double acc = 0, dec = 0, v_prev = 0;
  r.run_until([&] {
    const double v = r.axes.output().velocity_mm_s[0];
    const double dv = (v - v_prev) / 0.001;
    acc = std::max(acc, dv);
    dec = std::max(dec, -dv);
    v_prev = v;
    return !r.a.status().running;
  });
  EXPECT_NEAR(acc, 500.0, 1e-6);   // 10 % of 5000
  EXPECT_NEAR(dec, 2500.0, 1e-6);  // 50 % of 5000 (the landing step included)
}

TEST(Spc200, S2_G02IsSmootherThanG01) {
  auto max_jerk = [](const char* line) {
    Rig r;
    r.load(1, std::string("N000 ") + line + "\nN001 M30\n");
    r.a.set_program(1);
    r.a.start();
    double v_prev = 0, a_prev = 0, j = 0;
    r.run_until([&] {
      const double v = r.axes.output().velocity_mm_s[0];
      const double a = (v - v_prev) / 0.001;
      j = std::max(j, std::fabs(a - a_prev) / 0.001);
      v_prev = v;
      a_prev = a;
      return !r.a.status().running;
    });
    EXPECT_NEAR(r.x(), 400.0, 1e-9);
    return j;
  };
  const double j1 = max_jerk("G01 X400 FX0");
  const double j2 = max_jerk("G02 X400 FX0");
  EXPECT_GT(j1, 1e6);         // a trapezoid steps its acceleration
  EXPECT_LT(j2, 2 * 5000.0 / 0.1 * 1.1);  // sin² kernel: peak jerk ≈ 2·a/T
}

TEST(Spc200, S9_ExecuteRecordRunsOneLineAndReportsDone) {
  Rig r;
  r.load(1, "N000 G01 X100 FX0\nN001 G01 X200 FX0\nN005 G01 X50 FX50\n", true);
  r.a.set_program(1);
  EXPECT_FALSE(r.a.execute_record(3));  // no such line
  EXPECT_FALSE(r.a.execute_record(32));
  ASSERT_TRUE(r.a.execute_record(1));
  EXPECT_FALSE(r.a.status().motion_done);
  EXPECT_FALSE(r.a.execute_record(0));  // busy
  ASSERT_GT(r.run_until([&] { return r.a.status().motion_done; }), 0);
  EXPECT_DOUBLE_EQ(r.x(), 200.0);
  ASSERT_TRUE(r.a.execute_record(5));
  ASSERT_GT(r.run_until([&] { return r.a.status().motion_done; }), 0);
  EXPECT_DOUBLE_EQ(r.x(), 50.0);
}

TEST(Spc200, S9_StopDuringARecordKeepsRcAtZeroUntilReset) {
  Rig r;
  r.load(1, "N000 G01 X1000 FX0\n", true);
  r.a.set_program(1);
  ASSERT_TRUE(r.a.execute_record(0));
  r.run_until([&] { return r.x() > 100; });
  r.axes.stop_all();
  r.a.halt();
  for (int i = 0; i < 10; ++i) r.cycle();
  EXPECT_FALSE(r.a.status().motion_done);
  r.a.reset();
  EXPECT_TRUE(r.a.status().motion_done);
  EXPECT_TRUE(r.a.execute_record(0));
}

TEST(Spc200, S9_ExecuteRecordRefusesRelativeLineAfterStopUpFront) {
  Rig r;
  r.load(1, "N000 G01 X1000 FX0\nN001 G01 G91 X5 FX0\nN002 G01 X20 FX0\nN003 G01 X30 FX0\n", true);
  r.a.set_program(1);
  ASSERT_TRUE(r.a.execute_record(0));
  r.run_until([&] { return r.x() > 100; });
  r.axes.stop_all();
  r.a.halt();
  r.a.reset();
  const double x_stop = r.x();
  // G91 after a stop: refused before anything starts, with the reason.
  EXPECT_FALSE(r.a.execute_record(1));
  EXPECT_NE(std::string(r.a.refusal()).find("absolute"), std::string::npos) << r.a.refusal();
  EXPECT_FALSE(r.a.status().running);
  EXPECT_FALSE(r.a.status().error);
  r.cycle();
  EXPECT_EQ(r.x(), x_stop);
  // An absolute line is accepted; after it the relative one is too.
  ASSERT_TRUE(r.a.execute_record(2));
  EXPECT_STREQ(r.a.refusal(), "");
  ASSERT_GT(r.run_until([&] { return r.a.status().motion_done; }), 0);
  ASSERT_TRUE(r.a.execute_record(1));
  ASSERT_GT(r.run_until([&] { return r.a.status().motion_done; }), 0);
  EXPECT_DOUBLE_EQ(r.x(), 25.0);
}

}  // namespace
}  // namespace softmc::control::spc
