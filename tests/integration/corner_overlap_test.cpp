// The corner overlap (jerk mode, docs/planner.md "Corner overlap"): at a corner between two lines
// that is a stop, the second line begins while the first still brakes, every setpoint within P of
// the program and every axis within its limits, feed hold and stops acting on it as anywhere.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>

#include <fmt/format.h>

#include "control/channel_stimulus.hpp"
#include "machine/config.hpp"
#include "program/iso/parser.hpp"
#include "report/summary.hpp"
#include "simulation.hpp"

using namespace softmc;

namespace {

// The comparison machine of bench/compare_linuxcnc.py: 100 mm/s, 1 000 mm/s², 10 000 mm/s³ per axis.
machine::MachineConfig machine_for(bool overlap) {
  auto cfg = machine::default_machine();
  for (const char* a : {"x", "y", "z"}) {
    const std::string ax = std::string("axes.") + a;
    machine::apply_override(cfg, ax + ".max_vel_mm_s=100");
    machine::apply_override(cfg, ax + ".max_acc_mm_s2=1000");
    machine::apply_override(cfg, ax + ".max_jerk_mm_s3=10000");
    machine::apply_override(cfg, ax + ".min_mm=-1000");
    machine::apply_override(cfg, ax + ".max_mm=1000");
  }
  machine::apply_override(cfg, fmt::format("planner.corner_overlap={}", overlap));
  machine::validate(cfg);
  return cfg;
}

// A square wave of 10 mm rows and 2 mm steps: right-angle corners, each axis alone on its line.
std::string square_wave(int rows, double turn_deg = 90) {
  std::string s = "G21 G90 G64 P0.05\nG0 X0 Y0 Z0\nF6000\n";
  const double c = std::cos(turn_deg * M_PI / 180), d = std::sin(turn_deg * M_PI / 180);
  double x = 0, y = 0;
  for (int k = 0; k < rows; ++k) {
    x += (k % 2 ? -10.0 : 10.0);
    s += fmt::format("G1 X{:.6f} Y{:.6f}\n", x, y);
    // The step: 2 mm turning turn_deg from the row's direction.
    const double dir = k % 2 ? -1.0 : 1.0;
    x += 2 * c * dir;
    y += 2 * d;
    s += fmt::format("G1 X{:.6f} Y{:.6f}\n", x, y);
  }
  return s + "M2\n";
}

struct Run {
  program::Program prog;
  app::SimResult res;
  report::Summary sum;
};
Run run(const std::string& text, const machine::MachineConfig& cfg, const std::string& stimulus = "") {
  Run out;
  auto p = program::iso::parse(text, "overlap.ngc");
  EXPECT_TRUE(p.program);
  out.prog = *p.program;
  app::SimOptions opt;
  std::optional<control::ChannelStimulus> st;
  if (!stimulus.empty()) {
    auto s = control::parse_channel_stimulus(stimulus, "overlap.stim", cfg.axis_mask());
    EXPECT_TRUE(s.stimulus);
    st = *s.stimulus;
    opt.stimulus = &*st;
  }
  out.res = app::simulate(out.prog, cfg, opt);
  out.sum = report::summarize(out.prog, cfg, out.res.trace);
  return out;
}

void expect_within_limits(const Run& r, const machine::MachineConfig& cfg, double p_mm) {
  for (const auto& a : cfg.axes) {
    if (!a.enabled) continue;
    EXPECT_LE(r.sum.axis[a.index].max_vel_mm_s, a.max_vel_mm_s * (1 + 1e-9)) << a.name;
    EXPECT_LE(r.sum.axis[a.index].max_acc_mm_s2, a.max_acc_mm_s2 * (1 + 1e-6)) << a.name;
    EXPECT_LE(r.sum.axis[a.index].max_jerk_mm_s3, a.max_jerk_mm_s3 * (1 + 1e-6)) << a.name;
  }
  EXPECT_LE(r.sum.max_path_deviation_mm, p_mm + 1e-9);
}

// Cycles in which X and Y both move (the rows and steps never move both: only an overlap does).
int both_moving(const Run& r) {
  int n = 0;
  for (const auto& row : r.res.trace.rows)
    if (std::abs(row.vel[0]) > 1e-9 && std::abs(row.vel[1]) > 1e-9) ++n;
  return n;
}

double first_overlap_s(const Run& r) {
  for (const auto& row : r.res.trace.rows)
    if (std::abs(row.vel[0]) > 1e-9 && std::abs(row.vel[1]) > 1e-9) return row.t_s;
  return -1;
}

}  // namespace

TEST(CornerOverlap, RightAngleStopsOverlapWithinPAndTheLimits) {
  const std::string prog = square_wave(12);
  const auto on = machine_for(true), off = machine_for(false);
  const auto a = run(prog, on), b = run(prog, off);
  ASSERT_TRUE(a.res.ok) << a.res.result;
  ASSERT_TRUE(b.res.ok) << b.res.result;
  expect_within_limits(a, on, 0.05);
  expect_within_limits(b, off, 0.05);
  // Without the overlap the corners are passed at rest: never both axes at once.
  EXPECT_EQ(both_moving(b), 0);
  // With it, both move at every corner for a while, and the run is quicker.
  EXPECT_GT(both_moving(a), 20 * 23);
  EXPECT_LT(a.sum.cycle_time_s, b.sum.cycle_time_s - 23 * 0.01) << a.sum.cycle_time_s << " vs " << b.sum.cycle_time_s;
  // The path leaves the corners (it did not with stops) but stays within P, and ends on the program's end.
  EXPECT_GT(a.sum.max_path_deviation_mm, 1e-3);
  EXPECT_LT(b.sum.max_path_deviation_mm, 1e-9);
  const auto& end_a = a.res.trace.rows.back().cmd;
  const auto& end_b = b.res.trace.rows.back().cmd;
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(end_a[i], end_b[i]);
}

TEST(CornerOverlap, ATighterToleranceOverlapsLessAndStaysWithinIt) {
  std::string prog = square_wave(6);
  prog.replace(prog.find("P0.05"), 5, "P0.005");
  const auto cfg = machine_for(true);
  const auto a = run(prog, cfg);
  ASSERT_TRUE(a.res.ok) << a.res.result;
  expect_within_limits(a, cfg, 0.005);
  EXPECT_GT(both_moving(a), 0);
}

TEST(CornerOverlap, SharpTurnsThatShareTheirAxisAtFullJerkStayStops) {
  // 150° turns: the step runs back along X. The braking row's last jerk phase is X's whole jerk,
  // so the step could not start beside it: the corner stays a stop.
  const auto cfg = machine_for(true);
  const auto a = run(square_wave(6, 150), cfg);
  ASSERT_TRUE(a.res.ok) << a.res.result;
  expect_within_limits(a, cfg, 0.05);
  const auto b = run(square_wave(6, 150), machine_for(false));
  EXPECT_EQ(a.sum.cycle_time_s, b.sum.cycle_time_s);
}

TEST(CornerOverlap, P8_AFeedHoldDuringAnOverlapHoldsOnThePathAndGoesOn) {
  const std::string prog = square_wave(6);
  const auto cfg = machine_for(true);
  const auto free = run(prog, cfg);
  const double t = first_overlap_s(free);
  ASSERT_GT(t, 0);
  // The hold written in the overlap's second cycle, released 0.3 s later.
  const auto held = run(prog, cfg, fmt::format("{:.4f} feed_hold 1\n{:.4f} feed_hold 0\n", t + 0.0005, t + 0.3005));
  ASSERT_TRUE(held.res.ok) << held.res.result;
  expect_within_limits(held, cfg, 0.05);
  // Held: a stretch at rest on the path inside the hold, and the run ends where it would have.
  int rest = 0;
  for (const auto& row : held.res.trace.rows)
    if (row.t_s > t + 0.1 && row.t_s < t + 0.3 && row.path_v == 0 && row.vel[0] == 0 && row.vel[1] == 0) ++rest;
  EXPECT_GT(rest, 50);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(held.res.trace.rows.back().cmd[i], free.res.trace.rows.back().cmd[i]);
}

TEST(CornerOverlap, P5_AStopDuringAnOverlapEndsAtRestAfterTheTail) {
  const std::string prog = square_wave(6);
  const auto cfg = machine_for(true);
  const double t = first_overlap_s(run(prog, cfg));  // the first overlap of the run without the stop
  ASSERT_GT(t, 0);
  const auto stopped = run(prog, cfg, fmt::format("{:.4f} stop_request 1\n", t + 0.0005));
  ASSERT_TRUE(stopped.res.stopped) << stopped.res.result;
  expect_within_limits(stopped, cfg, 0.05);
  // The run ends at rest: the last two setpoints are the same point.
  const auto& rows = stopped.res.trace.rows;
  ASSERT_GE(rows.size(), 2u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(rows[rows.size() - 1].cmd[i], rows[rows.size() - 2].cmd[i]);
}

// bench/fuzz_run.py, seed 3302: a tail 0.36 mm long on a merged line (its 4 CAM lines), the next line
// barely moving beside it. Every setpoint lay within P of the program (within the next line's
// progress of the tail's point), but the rows were tagged with the next line, whose instructions
// the summary measures against: 0.135 mm on P0.1. A setpoint now belongs to the braking line while
// the tail has more left than the next line has gone, and the deviation is 0.0995 mm, as without
// the overlap.
TEST(CornerOverlap, ALongTailBelongsToTheBrakingLineUntilTheNextHasGoneFurther) {
  auto cfg = machine::default_machine();
  for (const char* kv :
       {"axes.x.max_vel_mm_s=500", "axes.x.max_acc_mm_s2=10000", "axes.x.max_jerk_mm_s3=100000", "axes.x.max_mm=100",
        "axes.x.ferror_limit_mm=1000", "axes.y.max_vel_mm_s=50", "axes.y.max_acc_mm_s2=3000",
        "axes.y.max_jerk_mm_s3=100000", "axes.y.max_mm=100", "axes.y.ferror_limit_mm=1000",
        "axes.z.max_vel_mm_s=500", "axes.z.max_acc_mm_s2=3000", "axes.z.max_jerk_mm_s3=100000", "axes.z.max_mm=100",
        "axes.z.ferror_limit_mm=1000", "planner.lookahead=4", "period_s=0.00025", "planner.smoothing_turn_deg=0"})
    machine::apply_override(cfg, kv);
  machine::validate(cfg);
  std::ifstream in(std::string(SOFTMC_SOURCE_DIR) + "/tests/integration/programs/overlap_far_tail.ngc");
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const auto r = run(text, cfg);
  ASSERT_TRUE(r.res.ok) << r.res.result;
  expect_within_limits(r, cfg, 0.1);
}

// A review's cases: an override of 0 written during an overlap holds the next line at once while
// the tail still ends on the corner, and the run (held for good) is reported only once it has;
// an emergency stop re-plans the tail with the emergency ramp too.
TEST(CornerOverlap, P8_AZeroOverrideDuringAnOverlapIsHeldForGoodOnlyOnceTheTailEnds) {
  const std::string prog = square_wave(6);
  const auto cfg = machine_for(true);
  const double t = first_overlap_s(run(prog, cfg));
  ASSERT_GT(t, 0);
  const auto held = run(prog, cfg, fmt::format("{:.4f} feed_override_permille 0\n", t + 0.0005));
  EXPECT_FALSE(held.res.ok);
  EXPECT_NE(held.res.result.find("held at rest"), std::string::npos) << held.res.result;
  const auto& last = held.res.trace.rows.back();
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(last.vel[i], 0.0) << i;
  expect_within_limits(held, cfg, 0.05);
}

TEST(CornerOverlap, P5_AnEmergencyStopBrakesTheTailWithTheEmergencyRamp) {
  const std::string prog = square_wave(6);
  auto cfg = machine_for(true);
  const double t = first_overlap_s(run(prog, cfg));
  ASSERT_GT(t, 0);
  const std::string stim = fmt::format("{:.4f} emergency_stop_request 1\n", t + 0.0015);
  const auto normal = run(prog, cfg, stim);
  machine::apply_override(cfg, "planner.emergency_accel_scale=3");
  machine::validate(cfg);
  const auto hard = run(prog, cfg, stim);
  ASSERT_TRUE(normal.res.stopped) << normal.res.result;
  ASSERT_TRUE(hard.res.stopped) << hard.res.result;
  EXPECT_LT(hard.sum.cycle_time_s, normal.sum.cycle_time_s);
  EXPECT_LE(hard.sum.max_path_deviation_mm, 0.05 + 1e-9);
}
