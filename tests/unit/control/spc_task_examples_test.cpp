// The configuration examples of S-11, loaded from examples/spc/, executed and checked.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "spc_task_rig.hpp"

namespace softmc::control::spc {
namespace {

using testing::Rig;

std::string example(const char* name) { return std::string(SOFTMC_SOURCE_DIR) + "/examples/spc/" + name; }

// S-9 style: order line `line` to task `t` and wait for the end of its motion.
void order(Rig& r, Task& t, int line) {
  ASSERT_TRUE(t.execute_record(line)) << "line " << line;
  ASSERT_GT(r.run_until([&] { return t.status().motion_done; }), 0) << "line " << line;
  ASSERT_FALSE(t.status().error) << t.status().message;
}

TEST(Spc200, S11_OneAxis32PositionsInTaskA) {
  Rig r;
  r.load_folder(example("one_axis_32_positions"), true);
  r.a.set_program(1);
  const double expect[] = {100.0, 1000.0, 130.0, 160.0};
  for (int line = 0; line < 4; ++line) {
    order(r, r.a, line);
    EXPECT_DOUBLE_EQ(r.x(), expect[line]);
  }
  order(r, r.a, 31);
  EXPECT_DOUBLE_EQ(r.x(), 980.0);
}

TEST(Spc200, S11_OneAxis64PositionsWithTwoTasks) {
  Rig r;
  r.load_folder(example("one_axis_64_positions_two_tasks"), true);
  r.a.set_program(1);
  r.b.set_program(2);
  order(r, r.a, 1);
  EXPECT_DOUBLE_EQ(r.x(), 1000.0);
  order(r, r.b, 0);  // the same axis from task B, after task A's motion ended
  EXPECT_DOUBLE_EQ(r.x(), 145.0);
  order(r, r.b, 31);
  EXPECT_DOUBLE_EQ(r.x(), 985.0);
}

TEST(Spc200, S11_TwoAxesTogetherOneAfterAnotherIndependently) {
  Rig r;
  r.load_folder(example("two_axes_together"), true);
  r.a.set_program(1);
  order(r, r.a, 1);
  EXPECT_DOUBLE_EQ(r.axes.setpoint_mm(0), 50.5);
  EXPECT_DOUBLE_EQ(r.axes.setpoint_mm(1), 100.6);
  Rig s;
  s.load_folder(example("two_axes_one_after_another"), true);
  s.a.set_program(1);
  order(s, s.a, 1);
  order(s, s.a, 16);
  EXPECT_DOUBLE_EQ(s.axes.setpoint_mm(0), 50.5);
  EXPECT_DOUBLE_EQ(s.axes.setpoint_mm(1), 100.6);
  Rig t;
  t.load_folder(example("two_axes_independent"), true);
  t.a.set_program(1);
  t.b.set_program(10);
  ASSERT_TRUE(t.a.execute_record(31));
  ASSERT_TRUE(t.b.execute_record(31));  // both tasks move at the same time
  t.cycle();
  EXPECT_TRUE(t.axes.moving(0) && t.axes.moving(1));
  ASSERT_GT(t.run_until([&] { return t.a.status().motion_done && t.b.status().motion_done; }), 0);
  EXPECT_DOUBLE_EQ(t.axes.setpoint_mm(0), 500.0);
  EXPECT_DOUBLE_EQ(t.axes.setpoint_mm(1), 700.0);
}

TEST(Spc200, S11_ThreeAndFourAxes) {
  Rig r;
  r.load_folder(example("three_axes_xy_and_z"), true);
  r.a.set_program(5);
  r.b.set_program(15);
  ASSERT_TRUE(r.a.execute_record(31));
  ASSERT_TRUE(r.b.execute_record(31));
  ASSERT_GT(r.run_until([&] { return r.a.status().motion_done && r.b.status().motion_done; }), 0);
  EXPECT_DOUBLE_EQ(r.axes.setpoint_mm(0), 500.0);
  EXPECT_DOUBLE_EQ(r.axes.setpoint_mm(1), 300.0);
  EXPECT_DOUBLE_EQ(r.axes.setpoint_mm(2), 250.0);
  Rig q;
  q.load_folder(example("four_axes_xy_and_zu"), true);
  q.a.set_program(1);
  q.b.set_program(2);
  order(q, q.a, 31);
  order(q, q.b, 31);
  EXPECT_DOUBLE_EQ(q.axes.setpoint_mm(1), 500.0);
  EXPECT_DOUBLE_EQ(q.axes.setpoint_mm(3), 200.0);
  Rig u;
  u.load_folder(example("four_axes_xyz_and_u"), true);
  u.a.set_program(1);
  u.b.set_program(2);
  order(u, u.a, 31);
  order(u, u.b, 31);
  EXPECT_DOUBLE_EQ(u.axes.setpoint_mm(2), 300.0);
  EXPECT_DOUBLE_EQ(u.axes.setpoint_mm(3), 200.0);
  for (const char* ex : {"three_axes_one_after_another", "four_axes_one_after_another"}) {
    Rig s;
    s.load_folder(example(ex), true);
    EXPECT_EQ(s.store.numbers().size(), 1u) << ex;
  }
}

TEST(Spc200, S11_Application2RelativeStepsAtHalfSpeed) {
  Rig r;
  r.load_folder(example("app2_rest_extreme_steps"), true);
  r.a.set_program(1);
  order(r, r.a, 0);
  order(r, r.a, 1);
  double vmax = 0;
  for (int k = 1; k <= 3; ++k) {
    ASSERT_TRUE(r.a.execute_record(2));
    r.run_until([&] {
      vmax = std::max(vmax, std::fabs(r.axes.output().velocity_mm_s[0]));
      return r.a.status().motion_done;
    });
    EXPECT_DOUBLE_EQ(r.x(), 1000.0 - 50.0 * k);
  }
  EXPECT_LE(vmax, 250.0 + 1e-9);  // 50 % of 500 mm/s
  order(r, r.a, 0);
  EXPECT_DOUBLE_EQ(r.x(), 0.0);
}

TEST(Spc200, S11_Application1And3FixedAndRegisterPositions) {
  Rig r;
  r.load_folder(example("app1_five_positions"), true);
  r.a.set_program(1);
  const double pos[] = {0, 100, 150, 200, 270, 300};
  for (int line : {4, 2, 5, 0}) {
    order(r, r.a, line);
    EXPECT_DOUBLE_EQ(r.x(), pos[line]);
  }
  Rig s;
  s.load_folder(example("app3_fixed_and_register"), true);
  s.a.set_program(1);
  ASSERT_EQ(s.regs.set_position_centi(0, 0, 72033), RegResult::Ok);  // 720.33 from the panel
  order(s, s.a, 0);
  EXPECT_DOUBLE_EQ(s.x(), 154.5);
  order(s, s.a, 1);
  EXPECT_DOUBLE_EQ(s.x(), 720.33);
}

TEST(Spc200, S11_Application4GridWithG91InTwoTasks) {
  Rig r;
  r.load_folder(example("app4_grid_g91"), true);
  r.a.set_program(1);
  r.b.set_program(10);
  order(r, r.a, 0);
  order(r, r.b, 0);
  for (int i = 0; i < 3; ++i) order(r, r.a, 1);
  for (int j = 0; j < 2; ++j) order(r, r.b, 1);
  EXPECT_NEAR(r.axes.setpoint_mm(0), 3 * 40.5, 1e-9);
  EXPECT_NEAR(r.axes.setpoint_mm(1), 2 * 63.8, 1e-9);
}

TEST(Spc200, S11_Application5PickAndPlaceFromRegisters) {
  Rig r;
  r.load_folder(example("app5_pick_place_one_task"), true);
  r.a.set_program(1);
  for (int i = 0; i < 6; ++i) {
    r.regs.set_position_centi(0, i, 10000 + 2500 * i);  // X columns 100, 125, ...
    r.regs.set_position_centi(1, i, 5000 + 3000 * i);   // Y rows 50, 80, ...
  }
  for (int k : {1, 7, 30}) {
    order(r, r.a, 0);
    EXPECT_DOUBLE_EQ(r.x(), 0.0);
    order(r, r.a, k);
    EXPECT_DOUBLE_EQ(r.x(), 100.0 + 25.0 * ((k - 1) % 5));
    EXPECT_DOUBLE_EQ(r.axes.setpoint_mm(1), 50.0 + 30.0 * ((k - 1) / 5));
  }
  Rig s;
  s.load_folder(example("app5_pick_place_two_tasks"), true);
  s.a.set_program(1);
  s.b.set_program(2);
  s.regs.set_position_centi(0, 30, 123456);
  s.regs.set_position_centi(1, 4, 777);
  order(s, s.a, 31);
  order(s, s.b, 5);
  EXPECT_DOUBLE_EQ(s.x(), 1234.56);
  EXPECT_DOUBLE_EQ(s.axes.setpoint_mm(1), 7.77);
}

// Inputs I2.0..I2.9 then I0.0..I0.4 carry bits 0..14 of the position in 0.1 mm.
void set_pattern(IoImage& io, int tenths) {
  for (int k = 0; k < 15; ++k) {
    const bool v = (tenths >> k) & 1;
    if (k < 10)
      io.set_input(2, k, v);
    else
      io.set_input(0, k - 10, v);
  }
}

TEST(Spc200, S11_BinaryPositionDecoderSubroutine) {
  for (int tenths : {0, 1, 5, 1000, 1234, 4096, 9999, 19999, 32767}) {
    Rig r;
    r.load_folder(example("binary_position_decoder"));
    r.regs.set_position_centi(0, 0, 55555);  // stale value: G28 clears it first
    set_pattern(r.io, tenths);
    r.a.set_program(1);
    r.a.start();
    if (tenths / 10.0 > 2000.0) {
      // Beyond the rig's 2000 mm travel: the decoded value is right, the move is refused.
      r.run_until([&] { return !r.a.status().running; });
      EXPECT_EQ(r.regs.position_centi(0, 0), tenths * 10) << tenths;
      EXPECT_TRUE(r.a.status().error);
      EXPECT_STREQ(r.a.status().message, "target outside the axis travel");
      continue;
    }
    ASSERT_GT(r.run_until([&] { return !r.a.status().running; }), 0);
    ASSERT_FALSE(r.a.status().error) << r.a.status().message;
    EXPECT_EQ(r.regs.position_centi(0, 0), tenths * 10) << tenths;
    EXPECT_DOUBLE_EQ(r.x(), tenths / 10.0);
  }
}

}  // namespace
}  // namespace softmc::control::spc
