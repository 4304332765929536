// Channel sequencing: motions planned ahead, non-motion instructions wait for the motion before them.
#include <gtest/gtest.h>

#include "control/channel.hpp"

using namespace softmc;

namespace {
motion::MachineLimits limits() {
  motion::MachineLimits m;
  for (int i = 0; i < 2; ++i) {
    m.axis[i] = {100, 1000, 0, -10, 200};
  }
  return m;
}
core::Vec xy(double x, double y) {
  core::Vec v;
  v[0] = x;
  v[1] = y;
  return v;
}
program::Program prog(std::vector<program::Op> ops) {
  program::Program p;
  p.files = {"t.ngc"};
  std::uint32_t line = 1;
  for (auto& o : ops) p.instructions.push_back({{0, line++, 1}, o});
  return p;
}
struct Rig {
  motion::Planner planner{limits(), 16};
  motion::Interpolator interp{planner.queue(), core::Vec{}};
  control::Channel ch{planner, interp};
  int cycles = 0;
  void cycle() {
    ch.update(0.001);
    interp.step(0.001);
    ++cycles;
  }
  void run(int max = 1000000) {
    while (ch.state() == control::ChannelState::Running && cycles < max) cycle();
  }
};
}  // namespace

TEST(Channel, ToolSwitchWaitsForThePrecedingMotion) {
  auto p = prog({program::Linear{xy(10, 0), 10}, program::ToolSwitch{true}, program::Linear{xy(20, 0), 10},
                 program::ProgramEnd{}});
  Rig r;
  r.ch.load(p);
  ASSERT_TRUE(r.ch.start({}));
  bool seen_on_while_first_move = false;
  while (r.ch.state() == control::ChannelState::Running) {
    r.cycle();
    if (r.ch.tool_on() && r.interp.setpoint().pos[0] < 10 - 1e-9) seen_on_while_first_move = true;
    if (r.cycles > 100000) break;
  }
  EXPECT_FALSE(seen_on_while_first_move);
  EXPECT_EQ(r.ch.state(), control::ChannelState::Finished);
  EXPECT_FALSE(r.ch.tool_on());  // program end switches the tool off
  EXPECT_EQ(r.interp.setpoint().pos, xy(20, 0));
}

TEST(Channel, DwellLastsItsTimeToTheCycle) {
  auto p = prog({program::Dwell{0.5}, program::ProgramEnd{}});
  Rig r;
  r.ch.load(p);
  r.ch.start({});
  r.run();
  EXPECT_EQ(r.ch.state(), control::ChannelState::Finished);
  EXPECT_NEAR(r.cycles, 501, 1);  // 500 cycles of dwell plus the cycle that started it
}

TEST(Channel, PlanningFaultNamesTheInstruction) {
  auto p = prog({program::Linear{xy(10, 0), 10}, program::Linear{xy(500, 0), 10}, program::ProgramEnd{}});
  Rig r;
  r.ch.load(p);
  r.ch.start({});
  r.run();
  EXPECT_EQ(r.ch.state(), control::ChannelState::Fault);
  EXPECT_EQ(r.ch.fault_instruction(), 1u);
  EXPECT_EQ(r.ch.plan_error(), motion::PlanResult::OutsideTravel);
}

TEST(Channel, LongProgramsStreamThroughASmallQueue) {
  std::vector<program::Op> ops;
  for (int i = 1; i <= 100; ++i) ops.push_back(program::Linear{xy(i, (i % 2) * 1.0), 50});
  ops.push_back(program::ProgramEnd{});
  auto p = prog(ops);
  Rig r;
  r.ch.load(p);
  r.ch.start({});
  r.run();
  EXPECT_EQ(r.ch.state(), control::ChannelState::Finished);
  EXPECT_EQ(r.interp.setpoint().pos, xy(100, 0));
}

// The planning work of a cycle is bounded: a staircase of 90° corners on a jerk-limited machine
// makes a quintic blend at every corner (60–190 µs each to build). 64 instructions a cycle would
// build 64 of them; the channel stops a cycle's planning after kMaxCurvesPerCycle curves and goes
// on in the next, and the program still runs to its end, on its last point.
TEST(Channel, PlanningWorkPerCycleIsBounded) {
  std::vector<program::Op> ops;
  for (int k = 1; k <= 60; ++k) ops.push_back(program::Linear{xy(2.0 * ((k + 1) / 2), 2.0 * (k / 2)), 100});
  ops.push_back(program::ProgramEnd{});
  auto p = prog(ops);
  motion::MachineLimits lim = limits();
  for (int i = 0; i < 2; ++i) lim.axis[i].j_max_mm_s3 = 10000;
  motion::Planner planner{lim, 512};
  motion::Interpolator interp{planner.queue(), core::Vec{}};
  control::Channel ch{planner, interp};
  ch.load(p);
  ASSERT_TRUE(ch.start({}));
  std::uint64_t most = 0, before = 0;
  int cycles = 0;
  while (ch.state() == control::ChannelState::Running && cycles < 100000) {
    before = planner.curves_built();
    ch.update(0.001);
    most = std::max(most, planner.curves_built() - before);
    interp.step(0.001);
    ++cycles;
  }
  EXPECT_EQ(ch.state(), control::ChannelState::Finished);
  EXPECT_GT(planner.curves_built(), 40u);  // the corners this is about were blended by quintics
  EXPECT_LE(most, control::Channel::kMaxCurvesPerCycle);
  EXPECT_GE(most, 2u);  // and a cycle does plan several
  while (!interp.idle() && cycles < 200000) {
    interp.step(0.001);
    ++cycles;
  }
  EXPECT_EQ(interp.setpoint().pos, xy(60, 60));
}
