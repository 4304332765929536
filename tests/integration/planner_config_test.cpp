// The [planner] keys reach the planner of a whole run: tolerance, look-ahead window, feed override.
#include <gtest/gtest.h>

#include <utility>

#include "machine/config.hpp"
#include "program/iso/parser.hpp"
#include "report/summary.hpp"
#include "simulation.hpp"

using namespace softmc;

namespace {
program::Program load(const std::string& rel) {
  auto r = program::iso::parse_file(std::string(SOFTMC_SOURCE_DIR) + "/" + rel);
  for (const auto& d : r.diagnostics) ADD_FAILURE() << d.format();
  EXPECT_TRUE(r.program);
  return r.program ? *r.program : program::Program{};
}

struct Outcome {
  double time_s = 0, deviation_mm = 0;
};
Outcome run(const program::Program& prog, const std::vector<std::string>& sets) {
  auto cfg = machine::default_machine();
  for (const auto& s : sets) machine::apply_override(cfg, s);
  machine::validate(cfg);
  const auto res = app::simulate(prog, cfg);
  EXPECT_TRUE(res.ok) << res.result;
  const auto s = report::summarize(prog, cfg, res.trace);
  return {static_cast<double>(res.cycles) * cfg.period_s, s.max_path_deviation_mm};
}
}  // namespace

// planner.tolerance_mm is the P of a program without G64 (the engraving sets no path mode): corners
// are cut within it, and any P > 0 is faster than exact stops. (A larger P is not always faster:
// on 0.4 mm chords the blends are bounded by the segment lengths, not by P.)
TEST(PlannerConfig, ToleranceKeyBoundsTheDeviationOfProgramsWithoutG64) {
  const auto prog = load("examples/gcode/bench/engraving.ngc");
  const std::vector<std::string> table{"axes.x.max_jerk_mm_s3=0", "axes.y.max_jerk_mm_s3=0", "axes.z.max_jerk_mm_s3=0",
                                       "axes.z.min_mm=-10"};
  auto with = [&](const char* tol) {
    auto s = table;
    s.push_back(std::string("planner.tolerance_mm=") + tol);
    return run(prog, s);
  };
  const auto exact = with("0");
  const auto fine = with("0.01");
  const auto coarse = with("0.2");
  EXPECT_LT(exact.deviation_mm, 1e-9);
  EXPECT_LE(fine.deviation_mm, 0.01 + 1e-9);
  EXPECT_GT(coarse.deviation_mm, 0.05);  // the key is used, not the default 0.05
  EXPECT_LE(coarse.deviation_mm, 0.2 + 1e-9);
  EXPECT_LT(fine.time_s, exact.time_s);
  EXPECT_LT(coarse.time_s, exact.time_s);
}

// A look-ahead window too short for the braking distance only slows the path; a long one works.
// (Merging off: merged, the collinear 0.25 mm moves would make a few long lines that 8 blocks cover.)
TEST(PlannerConfig, LookaheadKeySizesTheWindow) {
  const auto prog = load("examples/gcode/bench/surfacing.ngc");
  const std::vector<std::string> trap{"axes.x.max_jerk_mm_s3=0", "axes.y.max_jerk_mm_s3=0", "axes.z.max_jerk_mm_s3=0",
                                      "axes.z.min_mm=-10", "planner_queue=2", "planner.merge_share=0"};
  auto with = [&](const char* n) {
    auto s = trap;
    s.push_back(std::string("planner.lookahead=") + n);
    return run(prog, s);
  };
  const auto short_window = with("8");
  const auto long_window = with("10000");
  EXPECT_LT(long_window.time_s, short_window.time_s * 0.9);
  EXPECT_LE(long_window.deviation_mm, 0.05 + 1e-9);
  EXPECT_LE(short_window.deviation_mm, 0.05 + 1e-9);
}

// A program on the machine of the LinuxCNC comparison (100 mm/s, 1000 mm/s², 10 000 mm/s³ on every
// axis, P 0.05): run with `off` set, then with the defaults.
static std::pair<Outcome, Outcome> jerk_runs_with_and_without(const std::string& rel, const std::string& off) {
  const auto prog = load(rel);
  std::vector<std::string> sets{"axes.z.min_mm=-10", "planner.tolerance_mm=0.05"};
  for (const char* a : {"x", "y", "z"}) {
    sets.push_back(std::string("axes.") + a + ".max_vel_mm_s=100");
    sets.push_back(std::string("axes.") + a + ".max_acc_mm_s2=1000");
    sets.push_back(std::string("axes.") + a + ".max_jerk_mm_s3=10000");
  }
  auto with_off = sets;
  with_off.push_back(off);
  return {run(prog, with_off), run(prog, sets)};
}

// planner.smoothing_turn_deg reaches the channel: on a jerk-limited machine the surfacing program's
// lines run as a C² spline by default (20°), within the same P of the program, faster than as lines
// with corner blends or stops (0 = off), which slow down at every junction: 35.3 s against 57.3 s
// when written (103.3 s before sharp corners became stops and gentle ones quintics).
TEST(PlannerConfig, SmoothingKeyTurnsCamRunsIntoASpline) {
  const auto [blended, smoothed] = jerk_runs_with_and_without("examples/gcode/bench/surfacing.ngc", "planner.smoothing_turn_deg=0");
  EXPECT_LE(blended.deviation_mm, 0.05 + 1e-9);
  EXPECT_LE(smoothed.deviation_mm, 0.05 + 1e-9);
  EXPECT_LT(smoothed.time_s, 0.75 * blended.time_s) << smoothed.time_s << " vs " << blended.time_s;
}

// Without jerk limits the Channel cuts arcs into pieces of at most 45° (each planned with its own
// sweep's axis shares): plasma.ngc's holes and outline run within every axis's speed and
// acceleration limit, on the programmed path, and to the programmed end.
TEST(PlannerConfig, ArcsInPiecesKeepTheLimits) {
  const auto prog = load("examples/gcode/bench/plasma.ngc");
  auto cfg = machine::default_machine();
  for (const char* a : {"x", "y", "z"}) {
    machine::apply_override(cfg, std::string("axes.") + a + ".max_vel_mm_s=100");
    machine::apply_override(cfg, std::string("axes.") + a + ".max_acc_mm_s2=1000");
    machine::apply_override(cfg, std::string("axes.") + a + ".max_jerk_mm_s3=0");
    machine::apply_override(cfg, std::string("axes.") + a + ".ferror_limit_mm=1000");
  }
  machine::validate(cfg);
  const auto res = app::simulate(prog, cfg);
  ASSERT_TRUE(res.ok) << res.result;
  const auto s = report::summarize(prog, cfg, res.trace);
  EXPECT_LE(s.max_path_deviation_mm, 0.05 + 1e-9);  // its line-arc corners are blended within P
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_LE(s.axis[i].max_vel_mm_s, 100 * (1 + 1e-6)) << i;
    EXPECT_LE(s.axis[i].max_acc_mm_s2, 1000 * (1 + 1e-6)) << i;
  }
}

// Collinear rapids on either side of a non-motion instruction (G80 between a canned cycle's retract
// and a G0 up) merge into one line; at rest at its end the machine is where the last of them ends,
// and the report measures it there (it measured 18 mm: the first one's end).
TEST(PlannerConfig, MergedLinesAtRestAreMeasuredAtTheirLastInstruction) {
  const auto prog = load("examples/gcode/drilling.ngc");
  auto cfg = machine::load_machine(std::string(SOFTMC_SOURCE_DIR) + "/examples/machines/router.toml");
  machine::validate(cfg);
  const auto res = app::simulate(prog, cfg);
  ASSERT_TRUE(res.ok) << res.result;
  const auto s = report::summarize(prog, cfg, res.trace);
  EXPECT_LT(s.max_path_deviation_mm, 0.05 + 1e-9);
}

// planner.fillet_share reaches the planner: on a jerk-limited machine pocket.ngc's R0.5 corner arcs
// (each between two lines it is tangent to) run as one quintic from line to line by default,
// within the same P of the program, and the pocket takes a tenth less time than with the arcs
// (0 = off), which a jerk limit enters and leaves through curvature steps at 1–3 mm/s.
TEST(PlannerConfig, FilletKeyRunsCornerArcsAsOneQuintic) {
  const auto [arcs, fillets] = jerk_runs_with_and_without("examples/gcode/bench/pocket.ngc", "planner.fillet_share=0");
  EXPECT_LE(arcs.deviation_mm, 0.05 + 1e-9);
  EXPECT_LE(fillets.deviation_mm, 0.05 + 1e-9);
  EXPECT_LT(fillets.time_s, 0.92 * arcs.time_s) << fillets.time_s << " vs " << arcs.time_s;
}

// planner.corner_stops reaches the planner: on a jerk-limited machine engraving.ngc's sharp corners
// (letters and stars) are stops where that is quicker than their blends, within the same P, and the
// run takes 9 % less time than with every corner blended (false): 55.65 s against 60.99 s when
// written (docs/planner.md, "Blend or stop").
TEST(PlannerConfig, CornerStopsKeyStopsWhereThatIsQuickerThanABlend) {
  const auto [blended, chosen] = jerk_runs_with_and_without("examples/gcode/bench/engraving.ngc", "planner.corner_stops=false");
  EXPECT_LE(blended.deviation_mm, 0.05 + 1e-9);
  EXPECT_LE(chosen.deviation_mm, 0.05 + 1e-9);
  EXPECT_LT(chosen.time_s, 0.95 * blended.time_s) << chosen.time_s << " vs " << blended.time_s;
}
