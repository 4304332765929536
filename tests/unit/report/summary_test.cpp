// Run summary: programmed lengths, path deviation, per-axis finite differences, text and JSON forms.
#include "report/summary.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "synthetic_trace.hpp"

using namespace softmc;
using namespace softmc::report;
using namespace softmc::report::testing;

namespace {
constexpr double kPi = std::numbers::pi;
const double kSqrt2 = std::sqrt(2.0);
}  // namespace

TEST(Summary, LengthsAreTheProgrammedOnes) {
  const auto prog = rounded_square();
  const auto s = summarize(prog, test_table(), sample_program(prog));
  EXPECT_NEAR(s.cut_mm, 120 + 5 * kPi, 1e-12);
  EXPECT_NEAR(s.feed_mm, 120 + 5 * kPi + 10 * kSqrt2, 1e-12);
  EXPECT_NEAR(s.rapid_mm, 30 * kSqrt2, 1e-12);
}

TEST(Summary, LengthsDoNotDependOnTheTrace) {
  const auto prog = rounded_square();
  const auto s = summarize(prog, test_table(), Trace{});
  EXPECT_NEAR(s.cut_mm, 120 + 5 * kPi, 1e-12);
  EXPECT_EQ(s.cycles, 0u);
  EXPECT_EQ(s.cycle_time_s, 0.0);
}

TEST(Summary, CyclesAndCycleTimeFromTheLastRow) {
  const auto prog = rounded_square();
  const auto tr = sample_program(prog);
  const auto s = summarize(prog, test_table(), tr);
  EXPECT_EQ(s.cycles, tr.rows.size());
  EXPECT_DOUBLE_EQ(s.cycle_time_s, tr.rows.back().t_s);
  EXPECT_DOUBLE_EQ(s.period_s, 0.001);
  EXPECT_EQ(s.program, "rounded_square.ngc");
  EXPECT_EQ(s.machine, "test_table");
  EXPECT_EQ(s.axes, core::axis_bit(0) | core::axis_bit(1));
}

TEST(Summary, TheInitialStateRowIsNotACycle) {
  const auto prog = rounded_square();
  auto tr = sample_program(prog);
  TraceRow initial;
  initial.cmd = initial.act = prog.start;
  tr.rows.insert(tr.rows.begin(), initial);  // t = 0, as the simulation records it
  const auto s = summarize(prog, test_table(), tr);
  EXPECT_EQ(s.cycles, tr.rows.size() - 1);
  EXPECT_DOUBLE_EQ(s.cycle_time_s, s.cycles * 0.001);
  EXPECT_LT(s.max_path_deviation_mm, 1e-9);
}

TEST(Summary, DeviationIsZeroOnThePath) {
  const auto prog = rounded_square();
  const auto s = summarize(prog, test_table(), sample_program(prog));
  EXPECT_LT(s.max_path_deviation_mm, 1e-9);
}

TEST(Summary, DeviationOfOneShiftedSampleOnALine) {
  const auto prog = rounded_square();
  auto tr = sample_program(prog);
  // The middle sample of the top edge (instruction 5, y = 40), pushed 0.1 mm outwards.
  std::vector<std::size_t> edge;
  for (std::size_t i = 0; i < tr.rows.size(); ++i)
    if (tr.rows[i].tag == 5 && tr.rows[i].moving) edge.push_back(i);
  ASSERT_FALSE(edge.empty());
  tr.rows[edge[edge.size() / 2]].cmd[1] += 0.1;
  const auto s = summarize(prog, test_table(), tr);
  EXPECT_NEAR(s.max_path_deviation_mm, 0.1, 1e-9);
}

TEST(Summary, DeviationOfOneShiftedSampleOnTheArc) {
  const auto prog = rounded_square();
  auto tr = sample_program(prog);
  std::vector<std::size_t> arc;
  for (std::size_t i = 0; i < tr.rows.size(); ++i)
    if (tr.rows[i].tag == 3) arc.push_back(i);
  ASSERT_FALSE(arc.empty());
  // Radially inwards by 0.1 mm towards the centre (40, 20).
  auto& p = tr.rows[arc[arc.size() / 2]].cmd;
  const double dx = p[0] - 40, dy = p[1] - 20, r = std::hypot(dx, dy);
  p[0] -= 0.1 * dx / r;
  p[1] -= 0.1 * dy / r;
  const auto s = summarize(prog, test_table(), tr);
  EXPECT_NEAR(s.max_path_deviation_mm, 0.1, 1e-9);
}

TEST(Summary, DeviationOfTheWholeTraceShifted) {
  const auto prog = rounded_square();
  auto tr = sample_program(prog);
  for (auto& r : tr.rows) r.cmd[1] += 0.1;  // horizontal edges and standstills are off by exactly 0.1
  const auto s = summarize(prog, test_table(), tr);
  EXPECT_NEAR(s.max_path_deviation_mm, 0.1, 1e-9);
}

TEST(Summary, StandstillIsMeasuredFromWhereTheMachineShouldStand) {
  const auto prog = rounded_square();
  auto tr = sample_program(prog);
  for (auto& r : tr.rows)
    if (r.tag == 9) r.cmd[0] += 0.25;  // creeping during the dwell at (20, 20)
  const auto s = summarize(prog, test_table(), tr);
  EXPECT_NEAR(s.max_path_deviation_mm, 0.25, 1e-9);
}

// A straight motion along X from (0, 5) sampled at t = k·dt, k = 0..n: cmd(t) and path_v(t) given,
// the program one line to where it ends (X and Y axes).
struct SampledMotion {
  program::Program prog;
  Trace trace;
};
template <typename Cmd, typename PathV>
SampledMotion sampled_motion(int n, double dt, Cmd cmd, PathV path_v) {
  SampledMotion m;
  m.prog.start = xy(0, 5);
  m.prog.instructions = {ins(program::Linear{xy(cmd(n * dt)[0], 5), 100})};
  m.trace.period_s = dt;
  m.trace.axes = core::axis_bit(0) | core::axis_bit(1);
  for (int k = 0; k <= n; ++k) {
    TraceRow r;
    r.t_s = k * dt;
    r.cmd = cmd(k * dt);
    r.act = r.cmd;
    r.path_v = path_v(k * dt);
    r.moving = true;
    m.trace.rows.push_back(r);
  }
  return m;
}

// x(t) = j·t³/6 sampled at t = k·dt: every third difference is j·dt³, so the summary's jerk is j
// (and no jerk on an axis that does not move, nor from a parabola: its third differences are 0).
TEST(Summary, JerkFromACubicMotion) {
  constexpr double j = 30'000, dt = 0.001;
  const auto m = sampled_motion(
      300, dt, [&](double t) { return xy(j * t * t * t / 6, 5 + 100 * t * t); }, [&](double t) { return j * t * t / 2; });
  const auto s = summarize(m.prog, test_table(), m.trace);
  EXPECT_NEAR(s.axis[0].max_jerk_mm_s3, j, 1e-3);
  EXPECT_LT(s.axis[1].max_jerk_mm_s3, 1e-3);
  EXPECT_NE(to_text(s).find("max jerk mm/s³"), std::string::npos);
}

// x(t) = a·t²/2 sampled at t = k·dt, k = 0..n: the last step has speed a·dt·(n − ½) and every
// second difference is a·dt².
TEST(Summary, VelocityAndAccelerationFromAQuadraticMotion) {
  constexpr double a = 200, dt = 0.001;
  constexpr int n = 500;
  const auto m = sampled_motion(n, dt, [&](double t) { return xy(0.5 * a * t * t, 5); }, [&](double t) { return a * t; });
  const auto s = summarize(m.prog, test_table(), m.trace);
  EXPECT_NEAR(s.axis[0].max_vel_mm_s, a * dt * (n - 0.5), 1e-6);
  EXPECT_NEAR(s.axis[0].max_acc_mm_s2, a, 1e-4);
  EXPECT_EQ(s.axis[1].max_vel_mm_s, 0.0);
  EXPECT_EQ(s.axis[1].max_acc_mm_s2, 0.0);
  EXPECT_NEAR(s.max_path_speed_mm_s, a * n * dt, 1e-9);
  EXPECT_LT(s.max_path_deviation_mm, 1e-9);
}

TEST(Summary, FollowingErrorPerAxisAndOverall) {
  const auto prog = rounded_square();
  auto tr = sample_program(prog);
  tr.rows[100].act[0] = tr.rows[100].cmd[0] - 0.05;
  tr.rows[200].act[1] = tr.rows[200].cmd[1] + 0.2;
  tr.rows[300].act[2] = tr.rows[300].cmd[2] + 7;  // Z is not in the trace's axes: ignored
  const auto s = summarize(prog, test_table(), tr);
  EXPECT_NEAR(s.axis[0].max_following_error_mm, 0.05, 1e-12);
  EXPECT_NEAR(s.axis[1].max_following_error_mm, 0.2, 1e-12);
  EXPECT_EQ(s.axis[2].max_following_error_mm, 0.0);
  EXPECT_NEAR(s.max_following_error_mm, 0.2, 1e-12);
}

TEST(Summary, FollowingErrorOfALaggingQuantisedDrive) {
  const auto prog = rounded_square();
  const auto s =
      summarize(prog, test_table(), sample_program(prog, {.acc_mm_s2 = 1000, .lag_tau_s = 0.01, .quantum_mm = 0.127}));
  // Lag v·τ at the 20 mm/s feed is 0.2 mm; rapids at 300 mm/s lag more; quantisation adds ≤ half a count.
  EXPECT_GT(s.max_following_error_mm, 0.2);
  EXPECT_LT(s.max_following_error_mm, 300 * 0.01 + 0.0635 + 1e-9);
  EXPECT_LT(s.max_path_deviation_mm, 1e-9);  // deviation is of the command, not the encoder
}

TEST(Summary, JsonHasEveryFieldWithItsValue) {
  const auto prog = rounded_square();
  auto tr = sample_program(prog);
  tr.rows[10].act[0] += 0.03;
  auto s = summarize(prog, test_table(), tr);
  s.program = "examples/square.ngc";
  s.machine = "cutting_table (built-in)";
  const auto j = nlohmann::json::parse(to_json(s));
  ASSERT_TRUE(j.is_object());
  for (const char* k : {"program", "machine", "result", "period_s", "cycles", "cycle_time_s", "cut_mm", "feed_mm",
                        "rapid_mm", "max_path_deviation_mm", "max_following_error_mm", "max_path_speed_mm_s", "axes",
                        "max_path_deviation_at"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_EQ(j.size(), 14u);  // and max_path_deviation_at (rounded_square has no source lines: null)
  EXPECT_EQ(j["program"], "examples/square.ngc");
  EXPECT_EQ(j["machine"], "cutting_table (built-in)");
  EXPECT_EQ(j["result"], "ok");
  EXPECT_TRUE(j["cycles"].is_number_unsigned());
  EXPECT_EQ(j["cycles"].get<std::uint64_t>(), tr.rows.size());
  EXPECT_TRUE(j["cut_mm"].is_number_float());
  EXPECT_DOUBLE_EQ(j["period_s"].get<double>(), s.period_s);
  EXPECT_DOUBLE_EQ(j["cycle_time_s"].get<double>(), s.cycle_time_s);
  EXPECT_DOUBLE_EQ(j["cut_mm"].get<double>(), 120 + 5 * kPi);
  EXPECT_DOUBLE_EQ(j["feed_mm"].get<double>(), s.feed_mm);
  EXPECT_DOUBLE_EQ(j["rapid_mm"].get<double>(), 30 * kSqrt2);
  EXPECT_DOUBLE_EQ(j["max_path_deviation_mm"].get<double>(), s.max_path_deviation_mm);
  EXPECT_DOUBLE_EQ(j["max_following_error_mm"].get<double>(), s.max_following_error_mm);
  EXPECT_DOUBLE_EQ(j["max_path_speed_mm_s"].get<double>(), s.max_path_speed_mm_s);
  const auto& axes = j["axes"];
  ASSERT_TRUE(axes.is_object());
  EXPECT_EQ(axes.size(), 2u);
  for (const char* a : {"x", "y"}) {
    ASSERT_TRUE(axes.contains(a)) << a;
    const std::size_t i = a[0] == 'x' ? 0 : 1;
    EXPECT_DOUBLE_EQ(axes[a]["max_vel_mm_s"].get<double>(), s.axis[i].max_vel_mm_s);
    EXPECT_DOUBLE_EQ(axes[a]["max_acc_mm_s2"].get<double>(), s.axis[i].max_acc_mm_s2);
    EXPECT_DOUBLE_EQ(axes[a]["max_following_error_mm"].get<double>(), s.axis[i].max_following_error_mm);
    EXPECT_DOUBLE_EQ(axes[a]["max_jerk_mm_s3"].get<double>(), s.axis[i].max_jerk_mm_s3);
    EXPECT_EQ(axes[a].size(), 7u);  // and max_vel_at, max_acc_at, max_jerk_at
  }
  EXPECT_NEAR(axes["x"]["max_following_error_mm"].get<double>(), 0.03, 1e-12);
}

TEST(Summary, JsonFieldOrderIsTheDocumentedOne) {
  const std::string js = to_json(Summary{});
  EXPECT_EQ(js.rfind("{\"program\":", 0), 0u) << js;
  EXPECT_LT(js.find("\"cycles\""), js.find("\"cut_mm\""));
  EXPECT_LT(js.find("\"max_path_speed_mm_s\""), js.find("\"axes\""));
  EXPECT_NE(js.find("\"axes\":{}"), std::string::npos) << js;
  // Within an axis too: max_jerk_mm_s3, added later, comes last (new fields go at the end).
  Summary one;
  one.axes = core::axis_bit(0);
  const std::string ja = to_json(one);
  EXPECT_LT(ja.find("\"max_vel_mm_s\""), ja.find("\"max_acc_mm_s2\""));
  EXPECT_LT(ja.find("\"max_following_error_mm\""), ja.find("\"max_jerk_mm_s3\""));
  EXPECT_LT(ja.find("\"max_jerk_mm_s3\""), ja.find("\"max_vel_at\""));
  EXPECT_NE(ja.find("\"max_jerk_at\":null}},\"max_path_deviation_at\":null}"), std::string::npos) << ja;
}

TEST(Summary, JsonSurvivesAFaultMessageThatIsNotUtf8) {
  Summary s;
  s.result = "bad byte \xff here";
  nlohmann::json j;
  EXPECT_NO_THROW(j = nlohmann::json::parse(to_json(s)));
  EXPECT_TRUE(j["result"].is_string());
}

TEST(Summary, TextHasTheFiguresAndOneLinePerAxis) {
  const auto prog = rounded_square();
  const auto s = summarize(prog, test_table(), sample_program(prog));
  const std::string t = to_text(s);
  EXPECT_NE(t.find("cycle time"), std::string::npos) << t;
  EXPECT_NE(t.find(fmt::format("{:.3f} s", s.cycle_time_s)), std::string::npos) << t;
  EXPECT_NE(t.find(fmt::format("{:.3f} mm", s.cut_mm)), std::string::npos) << t;
  EXPECT_NE(t.find("\n  X "), std::string::npos) << t;
  EXPECT_NE(t.find("\n  Y "), std::string::npos) << t;
  EXPECT_EQ(t.find("\n  Z "), std::string::npos) << t;
  EXPECT_EQ(t.back(), '\n');
}

// Each largest value says where it was first reached: the row's time and the line of the
// instruction the row was tagged with (a difference: its newest row), as JSON and, for the deviation,
// in the text. A 1 mm spike of X in the middle of the dwell (instruction 9, on line 10 of a
// subroutine file): the speed is first largest at the spike's row, the acceleration and jerk one
// row later (δ, −2δ, δ and δ, −3δ, 3δ, −δ); a shifted sample on line 6 makes the deviation.
TEST(Summary, EachLargestValueSaysWhereItWasFirstReached) {
  auto prog = rounded_square();
  prog.files.push_back("sub.ngc");
  for (std::size_t i = 0; i < prog.instructions.size(); ++i) prog.instructions[i].loc.line = static_cast<std::uint32_t>(i + 1);
  prog.instructions[9].loc.file = 1;
  auto tr = sample_program(prog);
  std::vector<std::size_t> dwell, edge;
  for (std::size_t i = 0; i < tr.rows.size(); ++i) {
    if (tr.rows[i].tag == 9) dwell.push_back(i);
    if (tr.rows[i].tag == 5 && tr.rows[i].moving) edge.push_back(i);
  }
  ASSERT_GT(dwell.size(), 10u);
  ASSERT_FALSE(edge.empty());
  const std::size_t k = dwell[dwell.size() / 2], e = edge[edge.size() / 2];
  tr.rows[k].cmd[0] += 1.0;
  tr.rows[e].cmd[1] += 2.0;  // far more than the spike's 1 mm off the path
  const auto s = summarize(prog, test_table(), tr);
  EXPECT_EQ(s.axis[0].vel_at.t_s, tr.rows[k].t_s);
  EXPECT_EQ(s.axis[0].acc_at.t_s, tr.rows[k + 1].t_s);
  EXPECT_EQ(s.axis[0].jerk_at.t_s, tr.rows[k + 1].t_s);
  for (const Where* w : {&s.axis[0].vel_at, &s.axis[0].acc_at, &s.axis[0].jerk_at}) {
    EXPECT_EQ(w->line, 10u);
    EXPECT_EQ(w->file, 1u);
  }
  EXPECT_NEAR(s.max_path_deviation_mm, 2.0, 1e-9);
  EXPECT_EQ(s.deviation_at.t_s, tr.rows[e].t_s);
  EXPECT_EQ(s.deviation_at.line, 6u);
  EXPECT_EQ(s.deviation_at.file, 0u);
  const auto j = nlohmann::json::parse(to_json(s));
  EXPECT_EQ(j["max_path_deviation_at"]["line"], 6);
  EXPECT_DOUBLE_EQ(j["max_path_deviation_at"]["t_s"].get<double>(), tr.rows[e].t_s);
  EXPECT_FALSE(j["max_path_deviation_at"].contains("file"));
  EXPECT_EQ(j["axes"]["x"]["max_jerk_at"]["line"], 10);
  EXPECT_EQ(j["axes"]["x"]["max_jerk_at"]["file"], "sub.ngc");
  EXPECT_NE(to_text(s).find(fmt::format("(setpoints from the programmed path), line 6 at {:.3f} s", tr.rows[e].t_s)),
            std::string::npos)
      << to_text(s);
  // Nothing reached (no rows): null, and the text says nothing of where.
  const auto none = summarize(prog, test_table(), Trace{});
  EXPECT_TRUE(nlohmann::json::parse(to_json(none))["max_path_deviation_at"].is_null());
  EXPECT_NE(to_text(none).find("(setpoints from the programmed path)\n"), std::string::npos);
}
