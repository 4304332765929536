// Channel sequencing: motions planned ahead, non-motion instructions wait for the motion before them;
// the PLC's motion signals (P-2, P-5, P-8) acting on the path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

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
  explicit Rig(const motion::InterpolatorConfig& ic = {}) : interp{planner.queue(), core::Vec{}, ic} {}
  motion::Planner planner{limits(), 16};
  motion::Interpolator interp;
  control::Channel ch{planner, interp};
  control::MotionSignals sig;  // what the PLC writes, applied at every cycle's start
  int cycles = 0;
  void cycle() {
    ch.apply(sig);
    ch.update(0.001);
    interp.step(0.001);
    ch.sync_outputs();
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

// A cycle executes at most kMaxInstructionsPerCycle instructions and stops pushing once the planner
// has committed kMaxBlocksPerCycle blocks (a push commits at most a line and its corner's blend, so
// the check before each push keeps a cycle within 2 of the bound): 1 µm collinear lines merge 16 to
// a block and a cycle runs several hundred of them (1024 at 1 m/s); a zigzag of 0.05 mm lines at
// right angles merges none and a cycle runs at most about 64.
TEST(Channel, InstructionsAndBlocksPerCycleAreBounded) {
  for (const bool zigzag : {false, true}) {
    std::vector<program::Op> ops;
    const int n = zigzag ? 2000 : 20000;
    const double dx = zigzag ? 0.05 : 0.001;
    for (int k = 1; k <= n; ++k) ops.push_back(program::Linear{xy(dx * k, zigzag ? 0.05 * (k % 2) : 0.0), 50});
    ops.push_back(program::ProgramEnd{});
    auto p = prog(ops);
    motion::Planner planner{limits(), 4096};
    motion::Interpolator interp{planner.queue(), core::Vec{}};
    control::Channel ch{planner, interp};
    ch.load(p);
    ASSERT_TRUE(ch.start({}));
    std::uint64_t most_blocks = 0;
    std::uint32_t most_ins = 0;
    int cycles = 0;
    while (ch.state() == control::ChannelState::Running && cycles < 200000) {
      const auto blocks = planner.blocks_committed();
      const auto pc = ch.pc();
      ch.update(0.001);
      most_blocks = std::max(most_blocks, planner.blocks_committed() - blocks);
      most_ins = std::max(most_ins, ch.pc() - pc);
      interp.step(0.001);
      ++cycles;
    }
    SCOPED_TRACE(zigzag ? "zigzag" : "collinear");
    EXPECT_EQ(ch.state(), control::ChannelState::Finished);
    EXPECT_LE(most_ins, static_cast<std::uint32_t>(control::Channel::kMaxInstructionsPerCycle));
    EXPECT_LE(most_blocks, control::Channel::kMaxBlocksPerCycle + 2);
    if (zigzag) {
      EXPECT_LE(most_ins, control::Channel::kMaxBlocksPerCycle + 2);  // each commits a block
    } else {
      EXPECT_GE(most_ins, 15 * most_blocks);  // merged 16 to a block
      EXPECT_GE(most_ins, 16 * control::Channel::kFillBlocksPerCycle);
      EXPECT_LE(most_blocks, control::Channel::kMaxInstructionsPerCycle / 16 + 1);
    }
    EXPECT_EQ(interp.setpoint().pos, xy(dx * n, 0));
  }
}

// A window filling while the path is at rest fills over several cycles: the first cycle commits at
// most kFillBlocksPerCycle blocks (the worst cycle of a run was the first, committing 64). A path
// that passes many blocks a cycle (here 0.05 mm chords of a circle at 1 m/s, unmerged: about 40
// blocks a cycle with their blends) is given up to kMaxBlocksPerCycle again and runs at its feed.
TEST(Channel, AWindowFillingAtRestFillsOverSeveralCycles) {
  constexpr double kR = 20, kChord = 0.05, kFeed = 1000;
  const int n = static_cast<int>(2 * std::numbers::pi * kR / kChord);
  std::vector<program::Op> ops;
  for (int k = 1; k <= n; ++k) {
    const double th = 2 * std::numbers::pi * k / n;
    ops.push_back(program::Linear{xy(kR * std::sin(th), kR - kR * std::cos(th)), kFeed});
  }
  ops.push_back(program::ProgramEnd{});
  auto p = prog(ops);
  motion::MachineLimits lim;
  for (int i = 0; i < 2; ++i) lim.axis[i] = {2000, 200000, 0, -100, 100};
  motion::PlannerConfig pc;
  pc.merge_share = 0;  // every chord a block of its own
  motion::Planner planner{lim, 4096, pc};
  motion::Interpolator interp{planner.queue(), core::Vec{}};
  control::Channel ch{planner, interp};
  ch.load(p);
  ASSERT_TRUE(ch.start({}));
  std::vector<std::uint64_t> per_cycle;
  while (ch.state() == control::ChannelState::Running && per_cycle.size() < 100000) {
    const auto blocks = planner.blocks_committed();
    ch.update(0.001);
    per_cycle.push_back(planner.blocks_committed() - blocks);
    interp.step(0.001);
  }
  ASSERT_EQ(ch.state(), control::ChannelState::Finished);
  ASSERT_GT(per_cycle.size(), 20u);
  // a push commits at most a line and its blend past the check before it
  EXPECT_LE(per_cycle[0], control::Channel::kFillBlocksPerCycle + 2);
  EXPECT_GT(per_cycle[0], 0u);
  const std::uint64_t most = *std::max_element(per_cycle.begin(), per_cycle.end());
  EXPECT_GT(most, 2 * control::Channel::kFillBlocksPerCycle);
  EXPECT_LE(most, control::Channel::kMaxBlocksPerCycle + 2);
  int cycles = static_cast<int>(per_cycle.size());
  while (!interp.idle() && cycles < 200000) {
    interp.step(0.001);
    ++cycles;
  }
  EXPECT_EQ(interp.setpoint().pos, std::get<program::Linear>(ops[ops.size() - 2]).end);
  // The circle's 125.7 mm at 1 m/s (its centripetal limit √(a·R) = 2 m/s) with the ramps at
  // 200 000 mm/s² at both ends: the window never held the path back.
  const double ideal_s = n * kChord / kFeed + kFeed / 200000.0;
  EXPECT_LT(cycles * 0.001, 1.05 * ideal_s);
}

// The same after a stop: the blocks the path passed while it braked are not the next program's
// pace, so the first cycle of the program started where it stopped commits at most
// kFillBlocksPerCycle (it took the whole 64 before start() forgot them; a review's case).
TEST(Channel, AWindowFillingAfterAStopFillsOverSeveralCycles) {
  constexpr double kR = 20, kChord = 0.05, kFeed = 1000;
  const int n = static_cast<int>(2 * std::numbers::pi * kR / kChord);
  const auto circle = [&](const core::Vec& start) {
    std::vector<program::Op> ops;
    for (int k = 1; k <= n; ++k) {
      const double th = 2 * std::numbers::pi * k / n;
      ops.push_back(program::Linear{start + xy(kR * std::sin(th), kR - kR * std::cos(th)), kFeed});
    }
    ops.push_back(program::ProgramEnd{});
    auto p = prog(ops);
    p.start = start;
    return p;
  };
  motion::MachineLimits lim;
  for (int i = 0; i < 2; ++i) lim.axis[i] = {2000, 200000, 0, -1000, 1000};
  motion::PlannerConfig pc;
  pc.merge_share = 0;
  motion::Planner planner{lim, 4096, pc};
  motion::Interpolator interp{planner.queue(), core::Vec{}};
  control::Channel ch{planner, interp};
  control::MotionSignals sig;
  const auto cycle = [&] {
    ch.apply(sig);
    ch.update(0.001);
    interp.step(0.001);
  };
  const auto first = circle({});
  ch.load(first);
  ASSERT_TRUE(ch.start({}));
  for (int k = 0; k < 60; ++k) cycle();
  EXPECT_GT(interp.setpoint().path_v, 500);  // passing tens of chords a cycle
  sig.stop_request = true;
  for (int k = 0; k < 2000 && ch.state() != control::ChannelState::Stopped; ++k) cycle();
  ASSERT_EQ(ch.state(), control::ChannelState::Stopped);
  sig.stop_request = false;
  for (int k = 0; k < 10; ++k) cycle();
  const core::Vec at = interp.setpoint().pos;
  const auto second = circle(at);
  ch.load(second);
  ASSERT_TRUE(ch.start(at));
  const auto before = planner.blocks_committed();
  cycle();
  EXPECT_LE(planner.blocks_committed() - before, control::Channel::kFillBlocksPerCycle + 2);
  EXPECT_GT(planner.blocks_committed() - before, 0u);
}

// load() smooths the stretches of a run of lines (up to its sharp turns) on several threads at once
// and takes their pieces in program order: runs of many sizes (one line, a few, hundreds with sharp
// turns) between G5 curves, arcs, feed changes and exact stops run to the same setpoints, bit for
// bit, on 1, 2 and 5 threads.
TEST(Channel, RunsSmoothedOnSeveralThreadsRunTheSame) {
  std::mt19937_64 rng(2905);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<program::Op> ops;
  core::Vec p;
  double heading = 0;
  for (int run = 0; run < 40; ++run) {
    const int lines = run % 7 == 0 ? 1 : run % 5 == 0 ? 300 : 3 + run;
    const double feed = run % 3 == 0 ? 40 : 60;
    for (int k = 0; k < lines; ++k) {
      heading += k % 40 == 39 ? 1.2 : 0.08 * u(rng);  // a sharp turn ends a stretch
      p[0] += 0.2 * std::cos(heading);
      p[1] += 0.2 * std::sin(heading);
      ops.push_back(program::Linear{p, feed});
    }
    if (run % 4 == 1) {  // a G5 curve closes the run
      program::Bezier b;
      b.ctrl1 = p + xy(0.5, 0.2);
      b.ctrl2 = p + xy(1.0, -0.2);
      b.end = p + xy(1.5, 0.1);
      b.feed_mm_s = feed;
      ops.push_back(b);
      p = b.end;
    } else if (run % 4 == 2) {  // an arc
      program::Arc a;
      a.end = p + xy(2, 0);
      a.center0 = p[0] + 1;
      a.center1 = p[1];
      a.turns = -1;
      a.feed_mm_s = feed;
      ops.push_back(a);
      p = a.end;
    } else if (run % 4 == 3) {
      ops.push_back(program::Dwell{0.01});
    }
  }
  ops.push_back(program::ProgramEnd{});
  auto prog_ = prog(ops);
  motion::MachineLimits lim;
  for (int i = 0; i < 2; ++i) lim.axis[i] = {100, 1000, 10000, -500, 500};
  std::vector<std::vector<core::Vec>> runs;
  for (const std::size_t threads : {1u, 2u, 5u}) {
    motion::Planner planner{lim, 256};
    motion::Interpolator interp{planner.queue(), core::Vec{}};
    control::Channel ch{planner, interp};
    ch.set_load_threads(threads);
    ch.load(prog_);
    ASSERT_TRUE(ch.start({}));
    std::vector<core::Vec> pos;
    while ((ch.state() == control::ChannelState::Running || !interp.idle()) && pos.size() < 400000) {
      ch.update(0.001);
      interp.step(0.001);
      pos.push_back(interp.setpoint().pos);
    }
    ASSERT_EQ(ch.state(), control::ChannelState::Finished) << threads;
    EXPECT_EQ(interp.setpoint().pos, p);
    runs.push_back(std::move(pos));
  }
  ASSERT_GT(runs[0].size(), 1000u);
  for (std::size_t r = 1; r < runs.size(); ++r) {
    ASSERT_EQ(runs[r].size(), runs[0].size()) << r;
    for (std::size_t k = 0; k < runs[0].size(); ++k) ASSERT_EQ(runs[r][k], runs[0][k]) << r << " cycle " << k;
  }
}

// The planning work of a cycle is bounded: a staircase of 90° corners on a jerk-limited machine
// makes a quintic blend at every corner (60–190 µs each to build). 64 instructions a cycle would
// build 64 of them; the channel stops a cycle's planning once kMaxCurvesPerCycle curves have been
// tried (checked before each push, one of which may try up to four) and goes on in the next, and
// the program still runs to its end, on its last point.
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
    before = planner.curves_tried();
    ch.update(0.001);
    most = std::max(most, planner.curves_tried() - before);
    interp.step(0.001);
    ++cycles;
  }
  EXPECT_EQ(ch.state(), control::ChannelState::Finished);
  EXPECT_GT(planner.curves_tried(), 40u);  // the corners this is about were blended by quintics
  EXPECT_LE(most, control::Channel::kMaxCurvesPerCycle + 3);
  EXPECT_GE(most, 2u);  // and a cycle does plan several
  while (!interp.idle() && cycles < 200000) {
    interp.step(0.001);
    ++cycles;
  }
  EXPECT_EQ(interp.setpoint().pos, xy(60, 60));
}

namespace {
// A 150 mm line along X at 50 mm/s, then M7, then back: the rig cycled until it cruises.
Rig& cruising(Rig& r, const program::Program& p) {
  r.ch.load(p);
  EXPECT_TRUE(r.ch.start({}));
  while (r.cycles < 1000) r.cycle();  // 50 mm/s reached after 50 ms; at X ≈ 48.7 mm after 1 s
  EXPECT_NEAR(r.interp.setpoint().path_v, 50, 1e-9);
  return r;
}
program::Program line_m_line() {
  return prog({program::Linear{xy(150, 0), 50}, program::MFunction{7}, program::Linear{xy(0, 0), 50},
               program::ProgramEnd{}});
}
// Cycles until the path is at rest (at most `max` cycles); returns the largest speed drop per cycle.
double brake(Rig& r, int max = 5000) {
  double most = 0;
  for (int k = 0; k < max && r.interp.setpoint().path_v > 0; ++k) {
    const double v = r.interp.setpoint().path_v;
    r.cycle();
    most = std::max(most, v - r.interp.setpoint().path_v);
  }
  return most;
}
}  // namespace

// P-8: an override change acts on the next cycle, with the acceleration limit, and the path then
// runs at the programmed feed × %F × multiplier.
TEST(Channel, P8_OverrideActsOnTheNextCycleWithinTheRamp) {
  const auto p = line_m_line();
  Rig r;
  cruising(r, p);
  r.sig.feed_override_permille = 500;
  r.cycle();
  EXPECT_LT(r.interp.setpoint().path_v, 50 - 0.5);  // the first cycle after the write already slows
  double most_drop = 50 - r.interp.setpoint().path_v;
  for (int k = 0; k < 100; ++k) {
    const double v = r.interp.setpoint().path_v;
    r.cycle();
    most_drop = std::max(most_drop, v - r.interp.setpoint().path_v);
  }
  EXPECT_LE(most_drop, 1000 * 0.001 + 1e-9);  // never more than a·dt a cycle
  EXPECT_NEAR(r.interp.setpoint().path_v, 25, 1e-9);
  r.sig.feed_override_multiplier_permille = 1500;  // 500 ‰ × 1.5 = 75 %
  for (int k = 0; k < 100; ++k) r.cycle();
  EXPECT_NEAR(r.interp.setpoint().path_v, 37.5, 1e-9);
  EXPECT_EQ(r.interp.setpoint().pos[1], 0.0);
}

// Feed hold: brakes to rest on the path from the next cycle, stays there, and goes on from there.
TEST(Channel, FeedHoldStopsOnThePathAndResumesFromThere) {
  const auto p = line_m_line();
  Rig r;
  cruising(r, p);
  r.sig.feed_hold = true;
  r.cycle();
  EXPECT_LT(r.interp.setpoint().path_v, 50);
  EXPECT_LE(brake(r), 1000 * 0.001 + 1e-9);
  const double x = r.interp.setpoint().pos[0];
  EXPECT_GT(x, 48);
  for (int k = 0; k < 300; ++k) r.cycle();
  EXPECT_EQ(r.interp.setpoint().pos[0], x);  // held
  EXPECT_EQ(r.ch.state(), control::ChannelState::Running);
  EXPECT_EQ(r.ch.last_m(), -1);
  r.sig.feed_hold = false;
  r.cycle();
  EXPECT_GT(r.interp.setpoint().pos[0], x);
  r.run();
  EXPECT_EQ(r.ch.state(), control::ChannelState::Finished);
  EXPECT_EQ(r.ch.last_m(), 7);
  EXPECT_EQ(r.interp.setpoint().pos, xy(0, 0));
}

// P-2: dropping the enable of any axis of the channel holds the whole path, even one that does not
// move that axis; restoring it resumes on the path.
TEST(Channel, P2_AnyAxisDisabledHoldsThePathOnIt) {
  const auto p = line_m_line();
  Rig r;
  cruising(r, p);
  r.sig.axis_enable[1] = false;  // Y, which this line does not move
  EXPECT_LE(brake(r), 1000 * 0.001 + 1e-9);
  const double x = r.interp.setpoint().pos[0];
  for (int k = 0; k < 300; ++k) r.cycle();
  EXPECT_EQ(r.interp.setpoint().pos[0], x);
  EXPECT_EQ(r.interp.setpoint().pos[1], 0.0);
  r.sig.axis_enable[5] = false;  // an axis the machine does not have holds nothing
  r.sig.axis_enable[1] = true;
  r.run();
  EXPECT_EQ(r.ch.state(), control::ChannelState::Finished);
  EXPECT_EQ(r.interp.setpoint().pos, xy(0, 0));
}

// P-5: stop_request is acknowledged (the channel clears it), the path brakes to rest on itself with
// the normal ramp, nothing after the stop is executed, and the program cannot be restarted as is.
TEST(Channel, P5_StopRequestIsAcknowledgedAndEndsTheProgramOnThePath) {
  const auto p = line_m_line();
  Rig r;
  cruising(r, p);
  r.sig.stop_request = true;
  r.cycle();
  EXPECT_FALSE(r.sig.stop_request);  // taken
  EXPECT_EQ(r.ch.state(), control::ChannelState::Stopping);
  EXPECT_FALSE(r.ch.stop_confirmed());
  EXPECT_LE(brake(r), 1000 * 0.001 + 1e-9);
  r.cycle();
  EXPECT_EQ(r.ch.state(), control::ChannelState::Stopped);
  EXPECT_TRUE(r.ch.stop_confirmed());
  EXPECT_EQ(r.ch.stop_kind(), motion::StopKind::Normal);
  EXPECT_EQ(r.ch.stop_instruction(), 0u);
  EXPECT_TRUE(r.interp.idle());  // everything planned dropped
  const auto at = r.interp.setpoint().pos;
  EXPECT_NEAR(at[0], 48.7 + 1.25, 0.1);  // 1 s at 50 mm/s after the ramp, plus v²/2a
  EXPECT_EQ(at[1], 0.0);
  for (int k = 0; k < 500; ++k) r.cycle();
  EXPECT_EQ(r.interp.setpoint().pos, at);
  EXPECT_EQ(r.ch.last_m(), -1);  // M7 after the stopped line never ran
  EXPECT_FALSE(r.ch.start(at));
  r.sig.stop_request = true;  // a request with nothing running is taken and does nothing
  r.cycle();
  EXPECT_FALSE(r.sig.stop_request);
  EXPECT_EQ(r.ch.state(), control::ChannelState::Stopped);
}

// P-5: stop_pulse stops on its rising edge; a pulse already high when the program starts does not.
TEST(Channel, P5_StopPulseStopsOnItsRisingEdgeOnly) {
  const auto p = line_m_line();
  Rig r;
  r.sig.stop_pulse = true;
  r.cycle();  // idle: nothing to stop
  cruising(r, p);
  EXPECT_EQ(r.ch.state(), control::ChannelState::Running);
  r.sig.stop_pulse = false;
  r.cycle();
  EXPECT_EQ(r.ch.state(), control::ChannelState::Running);
  r.sig.stop_pulse = true;
  r.cycle();
  EXPECT_EQ(r.ch.state(), control::ChannelState::Stopping);
  brake(r);
  r.cycle();
  EXPECT_EQ(r.ch.state(), control::ChannelState::Stopped);
}

// P-5: the emergency stop brakes with emergency_accel_scale × the normal ramp (here twice: half the
// distance), and a later normal request does not weaken it.
TEST(Channel, P5_EmergencyStopBrakesWithTheEmergencyRamp) {
  const auto p = line_m_line();
  motion::InterpolatorConfig ic;
  ic.emergency_accel_scale = 2;
  Rig normal(ic), emergency(ic);
  cruising(normal, p);
  cruising(emergency, p);
  const double x0 = normal.interp.setpoint().pos[0];
  ASSERT_EQ(emergency.interp.setpoint().pos[0], x0);
  normal.sig.stop_request = true;
  emergency.sig.emergency_stop_request = true;
  emergency.cycle();
  emergency.sig.stop_request = true;
  const double drop_n = brake(normal), drop_e = brake(emergency);
  EXPECT_NEAR(drop_n, 1.0, 1e-9);
  EXPECT_NEAR(drop_e, 2.0, 1e-9);
  normal.cycle();
  emergency.cycle();
  EXPECT_EQ(emergency.ch.state(), control::ChannelState::Stopped);
  EXPECT_EQ(emergency.ch.stop_kind(), motion::StopKind::Emergency);
  const double d_n = normal.interp.setpoint().pos[0] - x0, d_e = emergency.interp.setpoint().pos[0] - x0;
  EXPECT_NEAR(d_n, 50.0 * 50 / 2000, 0.06);  // v²/2a, within a cycle's travel
  EXPECT_NEAR(d_e, 50.0 * 50 / 4000, 0.06);
}

// P-5: a stop during a dwell ends the dwell and the program at once.
TEST(Channel, P5_StopDuringADwellEndsItAtOnce) {
  auto p = prog({program::Dwell{1.0}, program::MFunction{8}, program::ProgramEnd{}});
  Rig r;
  r.ch.load(p);
  r.ch.start({});
  for (int k = 0; k < 100; ++k) r.cycle();
  ASSERT_TRUE(r.ch.dwelling());
  r.sig.stop_request = true;
  r.cycle();
  EXPECT_EQ(r.ch.state(), control::ChannelState::Stopped);
  EXPECT_FALSE(r.ch.dwelling());
  EXPECT_EQ(r.ch.last_m(), -1);
}

// M49 runs the following moves at the programmed feed whatever the PLC's override, M48 gives the
// override back (both act at their exact stop, so from the next move's first cycle). P-10 lists
// M48/M49 as override off/on; softmc follows RS274/LinuxCNC (M48 on), as CAM programs mean it.
TEST(Channel, P10_M49DisablesTheOverrideAndM48EnablesIt) {
  auto p = prog({program::Linear{xy(60, 0), 50}, program::MFunction{49}, program::Linear{xy(120, 0), 50},
                 program::MFunction{48}, program::Linear{xy(180, 0), 50}, program::ProgramEnd{}});
  Rig r;
  r.sig.feed_override_permille = 500;
  r.ch.load(p);
  ASSERT_TRUE(r.ch.start({}));
  double top[3] = {0, 0, 0};
  while (r.ch.state() == control::ChannelState::Running && r.cycles < 100000) {
    r.cycle();
    const auto& sp = r.interp.setpoint();
    const int k = sp.pos[0] <= 60 && sp.tag == 0 ? 0 : sp.tag <= 2 ? 1 : 2;
    top[k] = std::max(top[k], sp.path_v);
  }
  EXPECT_EQ(r.ch.state(), control::ChannelState::Finished);
  EXPECT_NEAR(top[0], 25, 1e-9);
  EXPECT_NEAR(top[1], 50, 1e-9);
  EXPECT_NEAR(top[2], 25, 1e-9);
  EXPECT_EQ(r.interp.setpoint().pos, xy(180, 0));
}

// The channel's states and every transition between them, as a table: from a state, an event,
// the state after it.
TEST(Channel, StateTransitionsTable) {
  using S = control::ChannelState;
  enum class Ev { Load, Start, Stop, EStop, Fault, RunOut };
  const auto p = prog({program::Linear{xy(100, 0), 50}, program::ProgramEnd{}});
  // Brings a fresh rig into state s.
  const auto reach = [&](Rig& r, S s) {
    r.ch.load(p);
    if (s == S::Idle) return;
    if (s == S::Fault) return r.ch.fault("drive");
    ASSERT_TRUE(r.ch.start({}));
    if (s == S::Running) return r.cycle();
    if (s == S::Finished) return r.run();
    for (int k = 0; k < 500; ++k) r.cycle();  // moving at speed
    r.sig.stop_request = true;
    r.cycle();
    if (s == S::Stopping) return;
    while (r.ch.state() == S::Stopping && r.cycles < 100000) r.cycle();
  };
  // Applies ev; for RunOut, cycles until the state changes (at most 20 s).
  const auto act = [&](Rig& r, Ev ev) {
    switch (ev) {
      case Ev::Load: r.ch.load(p); break;
      case Ev::Start: r.ch.start({}); break;
      case Ev::Stop: r.sig.stop_request = true; r.cycle(); break;
      case Ev::EStop: r.sig.emergency_stop_request = true; r.cycle(); break;
      case Ev::Fault: r.ch.fault("drive"); break;
      case Ev::RunOut: {
        const S from = r.ch.state();
        for (int k = 0; k < 20000 && r.ch.state() == from; ++k) r.cycle();
        break;
      }
    }
  };
  const struct {
    S from;
    Ev ev;
    S to;
  } table[] = {
      {S::Idle, Ev::Start, S::Running},       {S::Idle, Ev::Stop, S::Idle},          {S::Idle, Ev::Fault, S::Fault},
      {S::Running, Ev::RunOut, S::Finished},  {S::Running, Ev::Stop, S::Stopping},  {S::Running, Ev::EStop, S::Stopping},
      {S::Running, Ev::Fault, S::Fault},      {S::Running, Ev::Start, S::Running},  {S::Stopping, Ev::RunOut, S::Stopped},
      {S::Stopping, Ev::EStop, S::Stopping},  {S::Stopping, Ev::Stop, S::Stopping},  {S::Stopping, Ev::Fault, S::Fault},   {S::Stopping, Ev::Start, S::Stopping},
      {S::Stopped, Ev::Start, S::Stopped},    {S::Stopped, Ev::Stop, S::Stopped},   {S::Stopped, Ev::Load, S::Idle},
      {S::Finished, Ev::Start, S::Running},   {S::Finished, Ev::Stop, S::Finished}, {S::Fault, Ev::Start, S::Fault},
      {S::Fault, Ev::Stop, S::Fault},         {S::Fault, Ev::Load, S::Idle},
  };
  for (const auto& t : table) {
    Rig r;
    reach(r, t.from);
    ASSERT_EQ(r.ch.state(), t.from) << control::to_string(t.from);
    act(r, t.ev);
    EXPECT_EQ(r.ch.state(), t.to) << control::to_string(t.from) << " event " << static_cast<int>(t.ev);
  }
}

// A fault during Stopping leaves the interpolator's stop unacknowledged; the next program must not
// see it: loaded and started again, it runs until a stop of its own.
TEST(Channel, P5_AStopCutShortByAFaultDoesNotEndTheNextRun) {
  const auto p = line_m_line();
  Rig r;
  cruising(r, p);
  r.sig.stop_request = true;
  r.cycle();
  ASSERT_EQ(r.ch.state(), control::ChannelState::Stopping);
  r.ch.fault("drive");
  r.planner.queue().clear();  // as the application does on a fault
  for (int k = 0; k < 5; ++k) r.interp.step(0.001);
  r.ch.load(p);
  ASSERT_TRUE(r.ch.start(r.interp.setpoint().pos));
  for (int k = 0; k < 300; ++k) r.cycle();
  EXPECT_EQ(r.ch.state(), control::ChannelState::Running);
  EXPECT_GT(r.interp.setpoint().path_v, 10);
  // Its own stop brakes first: Stopped only at rest (a stale `stopped` would end it at once).
  r.sig.stop_request = true;
  r.cycle();
  r.cycle();
  EXPECT_EQ(r.ch.state(), control::ChannelState::Stopping);
  brake(r);
  r.cycle();
  EXPECT_EQ(r.ch.state(), control::ChannelState::Stopped);
  EXPECT_EQ(r.interp.setpoint().path_v, 0);
}

// With nothing in motion the stop names the instruction the program waits at: the dwell here.
TEST(Channel, P5_AStopDuringADwellNamesTheDwell) {
  auto p = prog({program::Linear{xy(10, 0), 50}, program::Dwell{2.0}, program::Linear{xy(20, 0), 50},
                 program::ProgramEnd{}});
  Rig r;
  r.ch.load(p);
  r.ch.start({});
  while (!r.ch.dwelling() && r.cycles < 10000) r.cycle();
  for (int k = 0; k < 100; ++k) r.cycle();
  r.sig.stop_request = true;
  r.cycle();
  EXPECT_EQ(r.ch.state(), control::ChannelState::Stopped);
  EXPECT_FALSE(r.ch.stopped_in_motion());
  EXPECT_EQ(r.ch.stop_instruction(), 1u);
}

// P-7 stop_confirmed: 0 while the path still brakes, 1 once a running program has actually
// stopped, and 0 again when a program is loaded to be started.
TEST(Channel, P7_StopConfirmedOnceStoppedUntilTheNextProgram) {
  const auto p = line_m_line();
  Rig r;
  cruising(r, p);
  EXPECT_FALSE(r.ch.stop_confirmed());
  r.sig.stop_request = true;
  r.cycle();
  EXPECT_FALSE(r.ch.stop_confirmed());  // braking
  brake(r);
  r.cycle();
  EXPECT_TRUE(r.ch.stop_confirmed());
  for (int k = 0; k < 100; ++k) r.cycle();
  EXPECT_TRUE(r.ch.stop_confirmed());
  r.ch.load(p);
  EXPECT_FALSE(r.ch.stop_confirmed());
}

// P-8 feed limits: with its request bit the PLC caps the path speed of feed moves (and of rapids
// with the other), whatever the override and M49; the caps act on the moving path like an override.
TEST(Channel, P8_FeedAndRapidLimitsCapThePathSpeed) {
  auto p = prog({program::Rapid{xy(150, 0)}, program::Linear{xy(0, 0), 50}, program::MFunction{49},
                 program::Linear{xy(150, 0), 50}, program::ProgramEnd{}});
  Rig r;
  r.sig.feed_override_permille = 2000;  // 200 %: 100 mm/s asked for on the feed moves
  r.sig.feed_limit_mm_min = 1200;       // 20 mm/s
  r.sig.feed_limit_request = true;
  r.sig.rapid_limit_mm_min = 3000;      // 50 mm/s
  r.sig.rapid_limit_request = true;
  r.ch.load(p);
  ASSERT_TRUE(r.ch.start({}));
  double top[3] = {0, 0, 0};
  while (r.ch.state() == control::ChannelState::Running && r.cycles < 100000) {
    r.cycle();
    const auto& sp = r.interp.setpoint();
    const int k = sp.tag == 0 ? 0 : sp.tag == 1 ? 1 : 2;
    top[k] = std::max(top[k], sp.path_v);
  }
  EXPECT_EQ(r.ch.state(), control::ChannelState::Finished);
  EXPECT_NEAR(top[0], 50, 1e-9);  // the rapid (100 mm/s axes) at its limit
  EXPECT_NEAR(top[1], 20, 1e-9);  // the feed move at its limit, not at 200 %
  EXPECT_NEAR(top[2], 20, 1e-9);  // M49: the programmed 50 mm/s, still capped
  // Dropped while moving: the path speeds up within its ramp.
  auto q = prog({program::Linear{xy(150, 0), 50}, program::ProgramEnd{}});
  Rig s;
  s.sig.feed_limit_mm_min = 600;
  s.sig.feed_limit_request = true;
  s.ch.load(q);
  s.ch.start({});
  for (int k = 0; k < 500; ++k) s.cycle();
  EXPECT_NEAR(s.interp.setpoint().path_v, 10, 1e-9);
  s.sig.feed_limit_request = false;
  s.cycle();
  EXPECT_GT(s.interp.setpoint().path_v, 10);
  EXPECT_LE(s.interp.setpoint().path_v, 10 + 1000 * 0.001 + 1e-9);
}

// M62/M63 (P-10 group 14, LinuxCNC's outputs synchronised with motion): the path goes on through
// them at its feed, and each output switches in the cycle whose setpoint is the first on the motion
// after it; an M62 with no motion after it never switches.
TEST(Channel, P10_M62SwitchesWhereTheNextMoveBeginsWithoutAStop) {
  auto p = prog({program::Linear{xy(10, 0), 50}, program::MFunction{62, 14}, program::DigitalOutput{3, true, true},
                 program::Linear{xy(20, 0), 50}, program::MFunction{63, 14}, program::DigitalOutput{3, false, true},
                 program::DigitalOutput{5, true, true}, program::Linear{xy(30, 0), 50},
                 program::DigitalOutput{7, true, true}, program::ProgramEnd{}});
  Rig r;
  r.ch.load(p);
  ASSERT_TRUE(r.ch.start({}));
  double x_before = 0, slowest = 1e9;
  std::vector<std::pair<double, std::uint64_t>> switches;  // (x before the cycle, x after), outputs
  std::vector<double> at;
  while (r.ch.state() == control::ChannelState::Running && r.cycles < 100000) {
    const std::uint64_t before = r.ch.digital_outputs();
    r.cycle();
    const double x = r.interp.setpoint().pos[0];
    if (x > 2 && x < 28) slowest = std::min(slowest, r.interp.setpoint().path_v);
    if (r.ch.digital_outputs() != before) {
      switches.push_back({x, r.ch.digital_outputs()});
      at.push_back(x_before);
    }
    x_before = x;
  }
  EXPECT_EQ(r.ch.state(), control::ChannelState::Finished);
  EXPECT_NEAR(slowest, 50, 1e-9);  // collinear lines at their feed: no stop at either M62/M63
  ASSERT_EQ(switches.size(), 2u);
  // Output 3 on in the first cycle past X10, off with 5 on in the first cycle past X20; 7 never.
  EXPECT_LE(at[0], 10.0);
  EXPECT_GT(switches[0].first, 10.0);
  EXPECT_EQ(switches[0].second, std::uint64_t{1} << 3);
  EXPECT_LE(at[1], 20.0);
  EXPECT_GT(switches[1].first, 20.0);
  EXPECT_EQ(switches[1].second, std::uint64_t{1} << 5);
  EXPECT_EQ(r.ch.digital_outputs(), std::uint64_t{1} << 5);
}

// M64/M65 switch at once, so the motion before them ends first (LinuxCNC: they break blending).
TEST(Channel, P10_M64SwitchesAtOnceAfterThePrecedingMotion) {
  auto p = prog({program::Linear{xy(10, 0), 50}, program::DigitalOutput{1, true, false}, program::Linear{xy(20, 0), 50},
                 program::ProgramEnd{}});
  Rig r;
  r.ch.load(p);
  ASSERT_TRUE(r.ch.start({}));
  bool switched = false;
  while (r.ch.state() == control::ChannelState::Running && r.cycles < 100000) {
    const motion::Setpoint before = r.interp.setpoint();
    r.cycle();
    if (r.ch.digital_outputs() == 2 && !switched) {
      switched = true;
      // The path had come to rest at X10 in the cycle before (the next move may begin in this one).
      EXPECT_EQ(before.pos[0], 10.0);
      EXPECT_EQ(before.path_v, 0.0);
    }
  }
  EXPECT_TRUE(switched);
}

// M67 sets its analog output where the next move begins, without a stop; M68 at once after the
// motion before it (a laser's power: LinuxCNC's M67 E0 Q…).
TEST(Channel, P10_M67SetsItsAnalogOutputWhereTheNextMoveBegins) {
  auto p = prog({program::AnalogOutput{0, 40, true}, program::Linear{xy(10, 0), 50}, program::MFunction{67, 14},
                 program::AnalogOutput{0, 80.5, true}, program::Linear{xy(20, 0), 50}, program::AnalogOutput{2, -1, false},
                 program::Linear{xy(30, 0), 50}, program::ProgramEnd{}});
  Rig r;
  r.ch.load(p);
  ASSERT_TRUE(r.ch.start({}));
  double slowest_first_two = 1e9, x_before = 0;
  std::vector<std::pair<double, double>> power;  // (x before the cycle it changed in, the new value)
  while (r.ch.state() == control::ChannelState::Running && r.cycles < 100000) {
    const double before = r.ch.analog_outputs()[0];
    r.cycle();
    const double x = r.interp.setpoint().pos[0];
    if (x > 2 && x < 18) slowest_first_two = std::min(slowest_first_two, r.interp.setpoint().path_v);
    if (r.ch.analog_outputs()[0] != before) power.push_back({x_before, r.ch.analog_outputs()[0]});
    x_before = x;
  }
  EXPECT_NEAR(slowest_first_two, 50, 1e-9);  // no stop at the M67
  ASSERT_EQ(power.size(), 2u);
  EXPECT_EQ(power[0], (std::pair<double, double>{0.0, 40.0}));  // the first move's first cycle
  EXPECT_LE(power[1].first, 10.0);
  EXPECT_EQ(power[1].second, 80.5);
  EXPECT_EQ(r.ch.analog_outputs()[2], -1.0);  // M68
  EXPECT_EQ(r.interp.setpoint().pos[0], 30.0);
}

// An output on every short line (a laser's power at each segment, hundreds in the window at once):
// the path flows at the feed as without them (which merges the lines the outputs keep apart), the
// outputs between two moves take their last values together, a zero-length move after an M62 does
// not lose it, and none switches while the path stands.
TEST(Channel, P10_OutputsOnEveryMoveFlowAndSwitchInOrder) {
  std::vector<program::Op> with, without;
  with.push_back(program::Linear{xy(0, 0), 50});  // zero length: the output waits for a real move
  for (int i = 1; i <= 300; ++i) {
    with.push_back(program::AnalogOutput{0, static_cast<double>(i), true});
    with.push_back(program::AnalogOutput{0, static_cast<double>(i) + 0.5, true});  // the last one counts
    if (i == 150) with.push_back(program::DigitalOutput{2, true, true});
    if (i == 1) with.push_back(program::Linear{xy(0, 0), 50});
    with.push_back(program::Linear{xy(0.1 * i, 0.001 * (i % 2)), 50});
    without.push_back(program::Linear{xy(0.1 * i, 0.001 * (i % 2)), 50});
  }
  with.push_back(program::ProgramEnd{});
  without.push_back(program::ProgramEnd{});
  const auto pw = prog(with), po = prog(without);
  Rig a, b;
  a.ch.load(pw);
  b.ch.load(po);
  ASSERT_TRUE(a.ch.start({}));
  ASSERT_TRUE(b.ch.start({}));
  a.sig.feed_override_permille = 0;  // held at rest on the first move: nothing switches yet
  for (int k = 0; k < 50; ++k) a.cycle();
  EXPECT_EQ(a.ch.analog_outputs()[0], 0.0);
  a.sig.feed_override_permille = 1000;
  a.cycles = 0;
  double last = 0, slowest = 1e9;
  bool in_order = true;
  b.run();
  while (a.ch.state() == control::ChannelState::Running && a.cycles < 100000) {
    a.cycle();
    const double x = a.interp.setpoint().pos[0];
    if (x > 2 && x < 28) slowest = std::min(slowest, a.interp.setpoint().path_v);
    const double v = a.ch.analog_outputs()[0];
    in_order = in_order && v >= last && (v == 0 || v == std::floor(v) + 0.5);
    // The power of segment i is set once the setpoint is on it: x beyond 0.1·(i − 1).
    if (v > 0) EXPECT_GT(a.interp.setpoint().pos[0], 0.1 * (std::floor(v) - 1) - 1e-12) << "power " << v;
    last = v;
  }
  EXPECT_TRUE(in_order);
  EXPECT_GT(slowest, 49.0);              // at its feed: no stop, no slow-down at the outputs
  EXPECT_LE(a.cycles, b.cycles + 2);     // as long as the run without them
  EXPECT_EQ(a.ch.analog_outputs()[0], 300.5);
  EXPECT_EQ(a.ch.digital_outputs(), std::uint64_t{1} << 2);
}
