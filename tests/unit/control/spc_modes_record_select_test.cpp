// S-9 Record Select on the real controller, driven signal by signal (no PLC client): ACK/RC timing,
// stops, reset and acknowledge, refused orders, ENABLE.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "spc_modes_rig.hpp"

namespace softmc::control::spc {
namespace {

using modes_testing::ModesRig;

double line_pos(int line) { return 10.0 + 20.0 * line; }

// 32 absolute positions per task: task A on X (P1), task B on Y (P2); P1's N031 is relative.
void load_record_programs(ModesRig& r) {
  std::string a, b;
  for (int n = 0; n < 32; ++n) {
    char buf[64];
    if (n == 31)
      std::snprintf(buf, sizeof buf, "N031 G01 G91 X5 FX0\n");
    else
      std::snprintf(buf, sizeof buf, "N%03d G01 G90 X%.1f FX0\n", n, line_pos(n));
    a += buf;
    std::snprintf(buf, sizeof buf, "N%03d G01 Y%.1f FY0\n", n, line_pos(n));
    b += buf;
  }
  r.load(1, a, true);
  r.load(2, b, true);
}

ControllerConfig record_cfg() {
  ControllerConfig c;
  c.mode = SpcMode::RecordSelect;
  c.program_a = 1;
  c.program_b = 2;
  c.self_test_s = 0.1;
  return c;
}

// Powered, self-tested, READY.
void ready_rig(ModesRig& r) {
  load_record_programs(r);
  r.power_up(record_cfg());
  r.run(0.11);
  ASSERT_TRUE(r.out(sig::kReady));
}

// Line bits, 10 ms, CLK=1 (S-10 steps 2..4).
void raise_order(ModesRig& r, IoAddress clk, int line) {
  r.wires().set_line_bits(line);
  r.run(0.010);
  r.set(clk, true);
}

TEST(Spc200, S9_PowerUpReadyRcAck) {
  ModesRig r;
  load_record_programs(r);
  r.power_up(record_cfg());
  r.run(0.05);
  EXPECT_FALSE(r.out(sig::kReady));
  EXPECT_FALSE(r.out(sig::kRcA));
  r.run(0.06);
  EXPECT_TRUE(r.out(sig::kReady));
  EXPECT_TRUE(r.out(sig::kRcA));
  EXPECT_TRUE(r.out(sig::kRcB));
  EXPECT_FALSE(r.out(sig::kAckA));
  EXPECT_FALSE(r.out(sig::kAckB));
}

TEST(Spc200, S9_ClkRiseLatchesLineSetsAckClearsRcAndStartsLine) {
  ModesRig r;
  ready_rig(r);
  raise_order(r, sig::kClkA, 7);
  // The 5 ms filter: nothing for 4 cycles, then ACK=1 and RC=0 together, and the axis moves.
  r.run(0.004);
  EXPECT_FALSE(r.out(sig::kAckA));
  r.cycle();
  EXPECT_TRUE(r.out(sig::kAckA));
  EXPECT_FALSE(r.out(sig::kRcA));
  EXPECT_TRUE(r.out(sig::kRcB));  // the other task is untouched
  EXPECT_EQ(r.ctl->status().last_record_line[0], 7);
  // The line bits may change once ACK is seen: the line was latched on the edge.
  r.wires().set_line_bits(30);
  ASSERT_GT(r.run_until([&] { return !r.axes.moving(0) && r.out(sig::kRcA); }, 2.0), 0);
  EXPECT_NEAR(r.x(), line_pos(7), 1e-9);
}

TEST(Spc200, S9_AckFallsWithClk) {
  ModesRig r;
  ready_rig(r);
  raise_order(r, sig::kClkA, 20);
  ASSERT_GT(r.run_until([&] { return r.out(sig::kAckA); }, 0.02), 0);
  r.run(0.02);
  EXPECT_TRUE(r.out(sig::kAckA));  // ACK holds while CLK is 1
  r.set(sig::kClkA, false);
  EXPECT_EQ(r.run_until([&] { return !r.out(sig::kAckA); }, 0.02), 5);
  EXPECT_FALSE(r.out(sig::kRcA));  // still moving
  EXPECT_TRUE(r.axes.moving(0));
  // RC=1 when the motion is finished (G61 condition 1: setpoint at the target).
  ASSERT_GT(r.run_until([&] { return r.out(sig::kRcA); }, 2.0), 0);
  EXPECT_FALSE(r.axes.moving(0));
  EXPECT_NEAR(r.x(), line_pos(20), 1e-9);
}

TEST(Spc200, S9_RcWhileClkStillHighThenAckFalls) {
  ModesRig r;
  ready_rig(r);
  raise_order(r, sig::kClkB, 0);  // Y to 10 mm: a short move
  ASSERT_GT(r.run_until([&] { return r.out(sig::kRcB) && r.out(sig::kAckB); }, 1.0), 0);
  EXPECT_EQ(r.ctl->status().record_task[1], RecordTaskState::Finished);
  r.set(sig::kClkB, false);
  ASSERT_GT(r.run_until([&] { return !r.out(sig::kAckB); }, 0.02), 0);
  EXPECT_TRUE(r.out(sig::kRcB));
}

TEST(Spc200, S9_TwoTasksRunTheirOrdersInParallel) {
  ModesRig r;
  ready_rig(r);
  raise_order(r, sig::kClkA, 25);
  r.run(0.006);
  r.set(sig::kClkA, false);
  raise_order(r, sig::kClkB, 12);
  r.run(0.006);
  r.set(sig::kClkB, false);
  EXPECT_TRUE(r.axes.moving(0));
  EXPECT_TRUE(r.axes.moving(1));
  ASSERT_GT(r.run_until([&] { return r.out(sig::kRcA) && r.out(sig::kRcB); }, 2.0), 0);
  EXPECT_NEAR(r.x(), line_pos(25), 1e-9);
  EXPECT_NEAR(r.y(), line_pos(12), 1e-9);
  EXPECT_EQ(r.ctl->status().records_executed[0], 1u);
  EXPECT_EQ(r.ctl->status().records_executed[1], 1u);
}

TEST(Spc200, S9_StopDuringMotionStopsAllAxesRcStaysLowNewOrderAccepted) {
  ModesRig r;
  ready_rig(r);
  raise_order(r, sig::kClkA, 30);
  r.run(0.006);
  r.set(sig::kClkA, false);
  raise_order(r, sig::kClkB, 30);
  r.run(0.006);
  r.set(sig::kClkB, false);
  r.run(0.2);
  ASSERT_TRUE(r.axes.moving(0) && r.axes.moving(1));
  r.set(sig::kStop, false);
  ASSERT_GT(r.run_until([&] { return !r.axes.moving(0); }, 0.01), 0);
  EXPECT_FALSE(r.axes.moving(1));  // all axes, at once
  const double x_stop = r.x(), y_stop = r.y();
  r.run(0.1);
  EXPECT_EQ(r.x(), x_stop);
  EXPECT_EQ(r.y(), y_stop);
  EXPECT_FALSE(r.out(sig::kRcA));  // RC stays 0
  EXPECT_FALSE(r.out(sig::kRcB));
  EXPECT_TRUE(r.out(sig::kReady));  // a stop is not an error
  // The PLC remembers the stop and orders again (absolute line): accepted.
  r.set(sig::kStop, true);
  r.run(0.01);
  raise_order(r, sig::kClkA, 3);
  ASSERT_GT(r.run_until([&] { return r.out(sig::kAckA); }, 0.02), 0);
  r.set(sig::kClkA, false);
  ASSERT_GT(r.run_until([&] { return r.out(sig::kRcA); }, 2.0), 0);
  EXPECT_NEAR(r.x(), line_pos(3), 1e-9);
  EXPECT_TRUE(r.out(sig::kReady));
}

TEST(Spc200, S9_AfterStopRelativeMoveIsRefused) {
  ModesRig r;
  ready_rig(r);
  raise_order(r, sig::kClkA, 30);
  r.run(0.05);
  r.set(sig::kClkA, false);
  r.set(sig::kStop, false);
  r.run(0.02);
  r.set(sig::kStop, true);
  r.run(0.01);
  const double x_stop = r.x();
  const auto executed = r.ctl->status().records_executed[0];
  raise_order(r, sig::kClkA, 31);  // G91 X5
  // The task refuses the line up front (Task::execute_record checks the axes): ACK never rises,
  // READY=0 and the axis does not move.
  bool acked = false;
  for (int i = 0; i < 20; ++i) {
    r.cycle();
    acked = acked || r.out(sig::kAckA);
  }
  EXPECT_FALSE(acked);
  EXPECT_EQ(r.ctl->status().records_executed[0], executed);
  EXPECT_FALSE(r.out(sig::kReady));
  EXPECT_EQ(r.x(), x_stop);
  EXPECT_NE(std::string(r.ctl->status().message).find("absolute"), std::string::npos) << r.ctl->status().message;
  EXPECT_FALSE(r.out(sig::kRcA));
}

TEST(Spc200, S9_ResetPulseWithStopLowClearsErrorsRcAck) {
  ModesRig r;
  ready_rig(r);
  raise_order(r, sig::kClkA, 30);
  r.run(0.05);  // ACK=1, RC=0, moving; CLK still 1
  r.ctl->raise_fault("X cannot reach its target");
  r.cycle();
  EXPECT_FALSE(r.out(sig::kReady));
  EXPECT_FALSE(r.axes.moving(0));
  r.set(sig::kClkA, false);
  r.set(sig::kStop, false);
  r.run(0.03);
  // A 7 ms pulse passes the 5 ms filter but is shorter than the 10 ms a reset needs.
  r.pulse(sig::kReset, 0.007);
  r.run(0.02);
  EXPECT_FALSE(r.out(sig::kReady));
  r.pulse(sig::kReset, 0.010);
  r.run(0.006);
  EXPECT_TRUE(r.out(sig::kReady));
  EXPECT_TRUE(r.out(sig::kRcA));
  EXPECT_TRUE(r.out(sig::kRcB));
  EXPECT_FALSE(r.out(sig::kAckA));
  EXPECT_FALSE(r.ctl->status().error);
}

TEST(Spc200, S9_ResetPulseWithStopHighAcknowledgesError) {
  ModesRig r;
  ready_rig(r);
  raise_order(r, sig::kClkA, 40 % 32);  // line 8
  r.run(0.006);
  r.set(sig::kClkA, false);
  r.run(0.006);
  // A second CLK while task A is still moving (RC=0): a refused order.
  raise_order(r, sig::kClkA, 2);
  r.run(0.006);
  EXPECT_FALSE(r.out(sig::kReady));
  EXPECT_FALSE(r.out(sig::kAckA));
  EXPECT_NE(std::string(r.ctl->status().message).find("refused"), std::string::npos);
  EXPECT_TRUE(r.axes.moving(0));  // a refused order does not stop the motion under way
  r.set(sig::kClkA, false);
  r.pulse(sig::kReset, 0.012);  // STOP=1: acknowledge
  r.run(0.006);
  EXPECT_TRUE(r.out(sig::kReady));
  ASSERT_GT(r.run_until([&] { return r.out(sig::kRcA); }, 2.0), 0);
  EXPECT_NEAR(r.x(), line_pos(8), 1e-9);
}

TEST(Spc200, S9_OrderForMissingLineOrUnassignedTaskIsRefused) {
  ModesRig r;
  r.load(1, "N000 G01 X100 FX0\nN001 G01 X200 FX0\n", true);
  auto cfg = record_cfg();
  cfg.program_b = -1;
  r.power_up(cfg);
  r.run(0.11);
  raise_order(r, sig::kClkA, 5);
  r.run(0.01);
  EXPECT_FALSE(r.out(sig::kReady));
  EXPECT_FALSE(r.out(sig::kAckA));
  r.set(sig::kClkA, false);
  r.pulse(sig::kReset, 0.012);
  r.run(0.01);
  ASSERT_TRUE(r.out(sig::kReady));
  raise_order(r, sig::kClkB, 0);
  r.run(0.01);
  EXPECT_FALSE(r.out(sig::kReady));
  EXPECT_FALSE(r.out(sig::kAckB));
}

TEST(Spc200, S9_OrderBeforeSelfTestOrWithStopLowIsRefused) {
  ModesRig r;
  ready_rig(r);
  r.set(sig::kStop, false);
  r.run(0.01);
  raise_order(r, sig::kClkA, 1);
  r.run(0.01);
  EXPECT_FALSE(r.out(sig::kAckA));
  EXPECT_FALSE(r.out(sig::kReady));
  EXPECT_DOUBLE_EQ(r.x(), 0.0);
}

TEST(Spc200, S9_EnableLowStopsAndDropsReady) {
  ModesRig r;
  ready_rig(r);
  raise_order(r, sig::kClkA, 30);
  r.run(0.05);
  r.set(sig::kClkA, false);
  r.set(sig::kEnable, false);
  r.run(0.01);
  EXPECT_FALSE(r.out(sig::kReady));
  EXPECT_FALSE(r.ctl->status().drives_enabled);
  EXPECT_FALSE(r.axes.moving(0));
  r.set(sig::kEnable, true);
  r.run(0.01);
  EXPECT_TRUE(r.out(sig::kReady));
  EXPECT_TRUE(r.ctl->status().drives_enabled);
  EXPECT_FALSE(r.out(sig::kRcA));  // the cut motion did not finish
}

}  // namespace
}  // namespace softmc::control::spc
