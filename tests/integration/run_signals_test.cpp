// Whole G-code runs with the PLC's motion signals from a stimulus (P-2, P-5, P-8, feed hold) on the
// built-in jerk-limited cutting table: they act within one cycle, on the path, with every limit kept.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <random>

#include <fmt/format.h>

#include "cli_run.hpp"
#include "control/channel_stimulus.hpp"
#include "machine/config.hpp"
#include "program/iso/parser.hpp"
#include "report/summary.hpp"
#include "simulation.hpp"
#include "temp_dir.hpp"

using namespace softmc;

namespace {
// 200 mm along X at 100 mm/s, 100 mm along Y, back along X: long straight cruises to act on.
constexpr const char* kProgram = "G21 G90 G64 P0.05\nG0 X0 Y0\nG1 X200 F6000\nG1 Y100\nG1 X0\nM30\n";

struct SignalRun {
  program::Program prog;
  app::SimResult res;
  report::Summary sum;
};
SignalRun run(const std::string& stimulus, const machine::MachineConfig& cfg = machine::default_machine(),
              const std::string& program = kProgram) {
  SignalRun out;
  auto p = program::iso::parse(program, "sig.ngc");
  EXPECT_TRUE(p.program);
  out.prog = *p.program;
  auto st = control::parse_channel_stimulus(stimulus, "sig.stim", cfg.axis_mask());
  EXPECT_TRUE(st.stimulus) << (st.diagnostics.empty() ? "" : st.diagnostics.front().format());
  app::SimOptions opt;
  opt.stimulus = &*st.stimulus;
  out.res = app::simulate(out.prog, cfg, opt);
  out.sum = report::summarize(out.prog, cfg, out.res.trace);
  return out;
}

// Every axis within its speed, acceleration (× scale) and jerk (× scale) limits over the whole trace.
void expect_within_limits(const SignalRun& r, const machine::MachineConfig& cfg, double scale = 1) {
  for (const auto& a : cfg.axes) {
    if (!a.enabled) continue;
    EXPECT_LE(r.sum.axis[a.index].max_vel_mm_s, a.max_vel_mm_s * (1 + 1e-9)) << a.name;
    EXPECT_LE(r.sum.axis[a.index].max_acc_mm_s2, scale * a.max_acc_mm_s2 * (1 + 1e-6)) << a.name;
    if (a.max_jerk_mm_s3 > 0) {
      EXPECT_LE(r.sum.axis[a.index].max_jerk_mm_s3, scale * a.max_jerk_mm_s3 * (1 + 1e-4)) << a.name;
    }
  }
}

// The row at time t (rows are one per cycle from t = 0).
const report::TraceRow& at(const SignalRun& r, double t) {
  return r.res.trace.rows.at(static_cast<std::size_t>(std::lround(t / r.res.trace.period_s)));
}
}  // namespace

// P-8 and feed hold: each write changes the path speed in the cycle that starts at its time (the row
// one period later), from a steady cruise; the jerk limit holds throughout, the held path rests on
// the programmed line, and the program still ends exactly on its last point.
TEST(RunSignals, P8_OverrideAndHoldActWithinOneCycleWithTheJerkKept) {
  const auto cfg = machine::default_machine();
  const auto r = run("0.8 feed_override_permille 500\n"
                     "1.6 feed_hold 1\n"
                     "2.2 feed_hold 0\n"
                     "3.0 feed_override_permille 1500\n",
                     cfg);
  ASSERT_TRUE(r.res.ok) << r.res.result;
  EXPECT_FALSE(r.res.stopped);
  const double dt = r.res.trace.period_s;
  const struct {
    double t, v_before;
    int sign;
  } events[] = {{0.8, 100, -1}, {1.6, 50, -1}, {3.0, 50, +1}};
  for (const auto& e : events) {
    EXPECT_NEAR(at(r, e.t - dt).path_v, e.v_before, 1e-9) << e.t;  // cruising before the write
    EXPECT_NEAR(at(r, e.t).path_v, e.v_before, 1e-9) << e.t;
    EXPECT_GT(e.sign * (at(r, e.t + dt).path_v - e.v_before), 0) << e.t;  // and changing in the next cycle
  }
  EXPECT_NEAR(at(r, 1.55).path_v, 50, 1e-9);   // %F 50
  EXPECT_EQ(at(r, 2.15).path_v, 0);            // held at rest ...
  EXPECT_EQ(at(r, 2.15).cmd, at(r, 2.2).cmd);  // ... where it stays
  EXPECT_EQ(at(r, 2.15).cmd[1], 0.0);          // on the programmed line
  EXPECT_GT(at(r, 2.2 + 2 * dt).path_v, 0);    // released: moving again
  expect_within_limits(r, cfg);
  EXPECT_LE(r.sum.max_path_deviation_mm, 0.05);
  const auto& last = r.res.trace.rows.back();
  EXPECT_EQ(last.cmd[0], 0.0);
  EXPECT_EQ(last.cmd[1], 100.0);
}

// P-2: one axis's enable held at 0 (Y, while the path moves X only) brings the path to rest with
// the normal ramps and jerk; back at 1 it resumes on the path without a jump.
TEST(RunSignals, P2_AxisEnableDropHoldsThePathAndResumesWithoutAJump) {
  const auto cfg = machine::default_machine();
  const auto r = run("0.8 axis_enable[Y] 0\n1.5 axis_enable[Y] 1\n", cfg);
  ASSERT_TRUE(r.res.ok) << r.res.result;
  const double dt = r.res.trace.period_s;
  EXPECT_LT(at(r, 0.8 + dt).path_v, 100);
  EXPECT_EQ(at(r, 1.45).path_v, 0);
  EXPECT_EQ(at(r, 1.45).cmd[1], 0.0);
  EXPECT_GT(at(r, 1.5 + 2 * dt).path_v, 0);
  expect_within_limits(r, cfg);
  EXPECT_LE(r.sum.max_path_deviation_mm, 0.05);
  EXPECT_EQ(r.res.trace.rows.back().cmd[1], 100.0);
}

// P-5: a stop request ends the run at rest on the path: reported with where it stopped, nothing
// after it run, every limit kept.
TEST(RunSignals, P5_StopRequestEndsTheRunAtRestOnThePath) {
  const auto cfg = machine::default_machine();
  const auto r = run("1.0 stop_request 1\n", cfg);
  ASSERT_TRUE(r.res.ok) << r.res.result;
  EXPECT_TRUE(r.res.stopped);
  EXPECT_EQ(r.res.result.rfind("stopped (P-5 stop) at sig.ngc:3:1, t = ", 0), 0u) << r.res.result;
  const auto& last = r.res.trace.rows.back();
  EXPECT_EQ(last.path_v, 0);
  EXPECT_EQ(last.cmd[1], 0.0);
  EXPECT_GT(last.cmd[0], 90);
  EXPECT_LT(last.cmd[0], 110);
  EXPECT_LT(r.res.trace.rows.size(), 1500u);  // ended soon after the stop, not at the program's end
  expect_within_limits(r, cfg);
  EXPECT_LT(r.sum.max_path_deviation_mm, 1e-9);  // it rests on the line it was on
}

// P-5: the emergency stop brakes with [planner] emergency_accel_scale × the axes' acceleration and
// jerk, with the acceleration and jerk of that scale and no more. From 100 mm/s with a = 2000 mm/s²
// and j = 50 000 mm/s³ the S-curve brake takes 0.09 s (a²/j = 80 mm/s at each end of the constant
// part): 4.5 mm. At twice both it never reaches 4000 mm/s²: 2·√(v/j) = 0.0632 s, 3.162 mm.
TEST(RunSignals, P5_EmergencyStopBrakesWithTheConfiguredScale) {
  auto cfg = machine::default_machine();
  machine::apply_override(cfg, "planner.emergency_accel_scale=2");
  const auto normal = run("1.0 stop_request 1\n", cfg);
  const auto emergency = run("1.0 emergency_stop_request 1\n", cfg);
  ASSERT_TRUE(normal.res.stopped && emergency.res.stopped);
  EXPECT_EQ(emergency.res.result.rfind("stopped (P-5 emergency stop) at sig.ngc:3:1", 0), 0u) << emergency.res.result;
  const double x0 = at(normal, 1.0).cmd[0];
  ASSERT_EQ(at(emergency, 1.0).cmd[0], x0);
  const double d_n = normal.res.trace.rows.back().cmd[0] - x0, d_e = emergency.res.trace.rows.back().cmd[0] - x0;
  EXPECT_NEAR(d_n, 4.5, 0.01);
  EXPECT_NEAR(d_e, 100 * 2 * std::sqrt(100 / 100000.0) / 2, 0.01);
  expect_within_limits(normal, cfg);
  expect_within_limits(emergency, cfg, 2);
  EXPECT_GT(emergency.sum.axis[0].max_acc_mm_s2, 1.5 * cfg.axes[0].max_acc_mm_s2);
}

// A stop that ends the run in a corner blend, or on a smoothing piece that carries the next line's
// tag over part of the line before (a fuzzer's cases): the summary measures the stopped position as
// it measures a moving one, from the motions around it, and the message names the line the
// machine stands on.
TEST(RunSignals, P5_AStopInABlendOrASmoothedRunIsOnThePathAndNamesItsLine) {
  const auto cfg = machine::default_machine();
  // 0.94 s: just before a 30° corner's G64 P1 blend (it begins at X88.86, 0.935 s), stopped inside it.
  const auto blend = run("0.94 emergency_stop_request 1\n", cfg, "G21 G90 G64 P1\nG1 X100 Y0 F6000\nG1 X200 Y57.735\nM30\n");
  ASSERT_TRUE(blend.res.stopped) << blend.res.result;
  EXPECT_GT(blend.res.trace.rows.back().cmd[1], 0.1);  // past the corner's start: in the blend
  EXPECT_LE(blend.sum.max_path_deviation_mm, 1.0);
  // A long line and a tiny one smoothed together: at X30 the machine is on line 2.
  const auto smooth = run("3 stop_request 1\n", cfg, "G21 G90\nG1 X50 Y0 F600\nG1 X50.05 Y0.005\nM30\n");
  ASSERT_TRUE(smooth.res.stopped) << smooth.res.result;
  EXPECT_EQ(smooth.res.result.rfind("stopped (P-5 stop) at sig.ngc:2:1, t = ", 0), 0u) << smooth.res.result;
  EXPECT_LE(smooth.sum.max_path_deviation_mm, 0.05);
  EXPECT_NEAR(smooth.res.trace.rows.back().cmd[0], 30, 0.1);
}

namespace {
// The LinuxCNC comparison's machine (bench/compare_linuxcnc.py, jerk run): 100 mm/s, 1000 mm/s²,
// 10 000 mm/s³ per axis, P0.05; and its surfacing program (a smoothed CAM run).
machine::MachineConfig comparison_machine() {
  auto cfg = machine::default_machine();
  for (const char* a : {"x", "y", "z"}) {
    machine::apply_override(cfg, fmt::format("axes.{}.max_vel_mm_s=100", a));
    machine::apply_override(cfg, fmt::format("axes.{}.max_acc_mm_s2=1000", a));
    machine::apply_override(cfg, fmt::format("axes.{}.max_jerk_mm_s3=10000", a));
  }
  machine::apply_override(cfg, "axes.z.min_mm=-10");
  machine::apply_override(cfg, "planner.tolerance_mm=0.05");
  machine::validate(cfg);
  return cfg;
}
std::string surfacing() {
  std::ifstream in(std::string(SOFTMC_SOURCE_DIR) + "/examples/gcode/bench/surfacing.ngc");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
}  // namespace

// A stop on a smoothed CAM run (surfacing.ngc on the LinuxCNC comparison's machine: 100 mm/s,
// 1000 mm/s², 10 000 mm/s³ per axis) brakes harder as it slows: each cycle the spline pieces ahead
// get the limits their geometry allows at the speed the path has then (Planner::limit_for_stop),
// instead of the split planned for their top speed. 0.281 s to rest before, 0.189 s now; every
// limit kept, the stopped position on the path. The stop comes at X17.39 on line 921 (the time it
// is asked at follows the program's: 7.3 s before sharp corners became stops where that is quicker,
// "Blend or stop", 6.814 s since, 6.742 s since curves before a stop take the limits of their
// reach, "Blocks at rest", 6.738 s since the smoothing's centripetal knots, 6.597 s since the row
// ends' corner overlaps, "Corner overlap": the same point, 0.141 s sooner; the time to rest depends
// on where).
TEST(RunSignals, P5_AStopOnASmoothedRunBrakesHarderAsItSlows) {
  const auto cfg = comparison_machine();
  const std::string program = surfacing();
  const double t_stop = 6.597;
  const auto r = run(fmt::format("{} stop_request 1\n", t_stop), cfg, program);
  ASSERT_TRUE(r.res.stopped) << r.res.result;
  EXPECT_NEAR(at(r, t_stop).cmd[0], 17.39, 0.05);
  EXPECT_GT(at(r, t_stop).path_v, 40);  // at speed on the spline when the stop came
  EXPECT_LT(r.sum.cycle_time_s - t_stop, 0.2);
  expect_within_limits(r, cfg);
  EXPECT_LE(r.sum.max_path_deviation_mm, 0.05);
}

// P-8: a feed hold on the same smoothed run, at the same place, brakes like the stop above (each
// cycle the spline pieces ahead take the limits their geometry allows at the speed the path has),
// 0.190 s to rest instead of 0.279 with the split planned for their top speed; at rest the pieces
// take back their planned limits and the run goes on from there to the end after the release.
TEST(RunSignals, P8_AFeedHoldOnASmoothedRunBrakesHarderAsItSlowsAndGoesOn) {
  const auto cfg = comparison_machine();
  const std::string program = surfacing();
  const double t_hold = 6.601, t_release = 7.101;  // 6.742 and 7.242 before the corner overlap
  const auto r = run(fmt::format("{} feed_hold 1\n{} feed_hold 0\n", t_hold, t_release), cfg, program);
  ASSERT_TRUE(r.res.ok) << r.res.result;
  EXPECT_GT(at(r, t_hold).path_v, 40);  // at speed on the spline when the hold came
  double t_rest = -1;
  for (const auto& row : r.res.trace.rows)
    if (row.t_s > t_hold && row.path_v == 0) {
      t_rest = row.t_s;
      break;
    }
  ASSERT_GT(t_rest, t_hold);
  EXPECT_LT(t_rest - t_hold, 0.2);
  EXPECT_EQ(at(r, t_release).path_v, 0);
  EXPECT_GT(at(r, t_release + 0.3).path_v, 20);  // going on
  expect_within_limits(r, cfg);
  EXPECT_LE(r.sum.max_path_deviation_mm, 0.05);
  EXPECT_EQ(r.res.trace.rows.back().path_v, 0);
}

// A hold written while the path still accelerates towards a blend brakes at once with the jerk of
// the block it is in: before, the ramp planned with the blend's lower jerk share brought |a| down
// so slowly that the path went on to 13.6 mm/s under F600 (a fuzzer's case).
TEST(RunSignals, AHoldWhileAcceleratingIntoABlendDoesNotOvershootTheFeed) {
  const auto cfg = machine::default_machine();
  const auto r = run("0.04 feed_hold 1\n", cfg, "G21 G90 G17\nG1 Z1.2941 F600\nG1 X0.2885 Y5.1663\nM30\n");
  EXPECT_NEAR(at(r, 0.04).path_v, 7.3, 0.1);  // still accelerating towards 10 mm/s when the hold comes
  EXPECT_LE(r.sum.max_path_speed_mm_s, 10 * (1 + 1e-3));
  expect_within_limits(r, cfg);
  EXPECT_EQ(r.res.trace.rows.back().path_v, 0);
}

// A run held at rest with no event left that could release it ends with an error naming why and
// where, instead of simulating on to the 24 h timeout.
TEST(RunSignals, HeldWithNoEventLeftEndsWithAnError) {
  const auto hold = run("0.5 feed_hold 1\n");
  EXPECT_FALSE(hold.res.ok);
  EXPECT_NE(hold.res.result.find("sig.ngc:3:1: held at rest at t = "), std::string::npos) << hold.res.result;
  EXPECT_NE(hold.res.result.find("(feed_hold is 1) and no stimulus event left to release it"), std::string::npos)
      << hold.res.result;
  EXPECT_LT(hold.res.trace.rows.size(), 1000u);
  const auto zero = run("0.5 feed_override_permille 0\n0.6 axis_enable[X] 0\n");
  EXPECT_FALSE(zero.res.ok);
  EXPECT_NE(zero.res.result.find("(axis_enable[X] is 0, the feed override is 0)"), std::string::npos) << zero.res.result;
  // Released later: the run goes on to the end.
  const auto released = run("0.5 feed_hold 1\n3 feed_hold 0\n");
  EXPECT_TRUE(released.res.ok) << released.res.result;
}

// The command line: `softmc run PROGRAM --stimulus FILE`; a bad file is refused with file:line:col
// before anything moves (no summary), a good one reports the stop.
TEST(RunSignals, CliRunsWithAStimulusAndRefusesABadOne) {
  test::TempDir dir;
  const auto prog = dir.file("sig.ngc", kProgram);
  const auto bad = dir.file("bad.stim", "0.5 feed_hold 1\n1 stop_requets 1\n");
  auto r = test::run_softmc("run " + prog + " --stimulus " + bad + " --json");
  EXPECT_EQ(r.exit, 1);
  EXPECT_EQ(r.out, "");
  EXPECT_NE(r.err.find(bad + ":2:3: error: unknown signal 'stop_requets'"), std::string::npos) << r.err;
  const auto good = dir.file("good.stim", "0.5 feed_override_permille 800\n1 stop_request 1\n");
  r = test::run_softmc("run " + prog + " --stimulus " + good + " --json");
  EXPECT_EQ(r.exit, 0) << r.err;
  EXPECT_NE(r.out.find("\"result\":\"stopped (P-5 stop) at " + prog + ":3:1, t = "), std::string::npos) << r.out;
}

// Seeded property test: random programs of lines, zigzags and arcs under random signal writes
// (override 0 … 250 %, feed and rapid limits, holds, enable drops, sometimes a stop), on the
// jerk-limited table and with
// trapezoids: every axis within its limits, the path within the tolerance, and the run ends either
// stopped at rest or on the program's last point.
TEST(RunSignals, RandomSignalsOnRandomPathsKeepEveryLimit) {
  for (const bool jerk : {true, false}) {
    auto cfg = machine::default_machine();
    if (!jerk)
      for (const char* k : {"axes.x.max_jerk_mm_s3=0", "axes.y.max_jerk_mm_s3=0", "axes.z.max_jerk_mm_s3=0"})
        machine::apply_override(cfg, k);
    for (std::uint32_t seed = 1; seed <= 25; ++seed) {
      std::mt19937 rng(seed);
      const auto uni = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
      // The program: from (100, 100), lines, a zigzag of short segments, arcs, at one of a few feeds.
      std::string text = "G21 G90 G64 P0.05\nG0 X100 Y100\n";
      double x = 100, y = 100;
      for (int k = 0; k < 12; ++k) {
        const int kind = static_cast<int>(rng() % 3);
        const double f = std::array{1200.0, 3000.0, 9000.0}[rng() % 3];
        if (kind == 0) {
          x = uni(20, 500), y = uni(20, 350);
          text += fmt::format("G1 X{:.4f} Y{:.4f} F{}\n", x, y, f);
        } else if (kind == 1) {
          for (int z = 0; z < 40; ++z) {
            x = std::clamp(x + uni(0.05, 0.5), 20.0, 500.0), y = std::clamp(y + (z % 2 ? 0.2 : -0.2), 20.0, 350.0);
            text += fmt::format("G1 X{:.4f} Y{:.4f} F{}\n", x, y, f);
          }
        } else {
          const double r = uni(2, 15);  // a full circle around a centre r to the right
          text += fmt::format("G2 X{:.4f} Y{:.4f} I{:.4f} J0 F{}\n", x, y, r, f);
        }
      }
      text += "M30\n";
      // The signals: a few writes in the first seconds, then everything released (unless stopped).
      std::string stim;
      double t = 0;
      bool stop = false;
      for (int k = 0; k < 8; ++k) {
        t += uni(0.0, 0.6);
        switch (rng() % 10) {
          case 8: stim += fmt::format("{0:.3f} feed_limit_mm_min {1}\n{0:.3f} feed_limit_request {2}\n", t, 60 + rng() % 6000, rng() % 2); break;
          case 9: stim += fmt::format("{0:.3f} rapid_limit_mm_min {1}\n{0:.3f} rapid_limit_request {2}\n", t, 60 + rng() % 12000, rng() % 2); break;
          case 0: case 1: stim += fmt::format("{:.3f} feed_override_permille {}\n", t, rng() % 2501); break;
          case 2: stim += fmt::format("{:.3f} feed_override_multiplier_permille {}\n", t, 500 + rng() % 1000); break;
          case 3: case 4: stim += fmt::format("{:.3f} feed_hold {}\n", t, rng() % 2); break;
          case 5: stim += fmt::format("{:.3f} axis_enable[{}] {}\n", t, "XYZ"[rng() % 3], rng() % 2); break;
          case 6: stim += fmt::format("{:.3f} feed_override_permille 0\n", t); break;
          default:
            if (rng() % 3 == 0 && !stop) {
              stim += fmt::format("{:.3f} {} 1\n", t, rng() % 2 ? "stop_request" : "emergency_stop_request");
              stop = true;
            }
        }
      }
      t += 0.1;
      stim += fmt::format("{0:.3f} feed_override_permille 1000\n{0:.3f} feed_override_multiplier_permille 1000\n"
                          "{0:.3f} feed_hold 0\n{0:.3f} axis_enable[X] 1\n{0:.3f} axis_enable[Y] 1\n"
                          "{0:.3f} axis_enable[Z] 1\n{0:.3f} feed_limit_request 0\n{0:.3f} rapid_limit_request 0\n",
                          t);
      SCOPED_TRACE(fmt::format("jerk {} seed {}\n{}{}", jerk, seed, text, stim));
      auto p = program::iso::parse(text, "rnd.ngc");
      ASSERT_TRUE(p.program);
      auto st = control::parse_channel_stimulus(stim, "rnd.stim", cfg.axis_mask());
      ASSERT_TRUE(st.stimulus);
      app::SimOptions opt;
      opt.stimulus = &*st.stimulus;
      opt.record = true;
      opt.max_time_s = 600;
      const auto res = app::simulate(*p.program, cfg, opt);
      ASSERT_TRUE(res.ok) << res.result;
      EXPECT_EQ(res.stopped, stop);
      SignalRun r{*p.program, res, report::summarize(*p.program, cfg, res.trace)};
      expect_within_limits(r, cfg);
      EXPECT_LE(r.sum.max_path_deviation_mm, 0.05 + 1e-9);
      const auto& last = res.trace.rows.back();
      EXPECT_EQ(last.path_v, 0);
      if (!stop) {
        EXPECT_EQ(last.cmd[0], std::stod(text.substr(text.rfind(" X") + 2)));
      }
    }
  }
}
