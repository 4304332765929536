// Machine configuration: the built-in table (T-1), TOML load/write round trip, --set overrides, validation.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <set>
#include <sstream>
#include <toml++/toml.h>

#include "machine/config.hpp"
#include "motion/limits.hpp"

using namespace softmc;
using namespace softmc::machine;
using ::testing::HasSubstr;
using ::testing::StartsWith;

namespace {

constexpr std::size_t kX = 0, kY = 1, kZ = 2, kA = 3;

std::string source_path(const std::string& rel) { return std::string(SOFTMC_SOURCE_DIR) + "/" + rel; }

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The message of the ConfigError `f` throws, or "no error".
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

// Every dotted leaf key of a TOML table.
void collect_keys(const toml::table& t, const std::string& prefix, std::set<std::string>& out) {
  for (auto&& [k, v] : t) {
    const std::string key = prefix + std::string(k.str());
    if (const auto* sub = v.as_table())
      collect_keys(*sub, key + ".", out);
    else
      out.insert(key);
  }
}

AxisConfig& axis_of(MachineConfig& cfg, std::size_t index) {
  for (auto& a : cfg.axes)
    if (a.index == index) return a;
  throw std::logic_error("no such axis");
}

}  // namespace

// ---- the built-in machine (T-1) ----

TEST(MachineConfig, T1_EncoderCountIs0127mm) {
  const auto cfg = default_machine();
  for (std::size_t i : {kX, kY}) {
    const auto* a = cfg.axis(i);
    ASSERT_NE(a, nullptr);
    EXPECT_EQ(a->counts_per_rev, 512);
    EXPECT_EQ(a->mm_per_rev, 65);
    EXPECT_DOUBLE_EQ(a->mm_per_count(), 65.0 / 512.0);
    EXPECT_NEAR(a->mm_per_count(), 0.127, 0.0005);
  }
}

TEST(MachineConfig, T1_DefaultIsTheCuttingTableWithXYAndTorchHeightZ) {
  const auto cfg = default_machine();
  EXPECT_EQ(cfg.name, "cutting_table");
  EXPECT_EQ(cfg.period_s, 0.001);
  EXPECT_EQ(cfg.tool_output, "torch");
  EXPECT_EQ(cfg.planner_queue, 256u);
  ASSERT_EQ(cfg.axes.size(), 3u);
  EXPECT_EQ(cfg.axes[0].name, "x");
  EXPECT_EQ(cfg.axes[1].name, "y");
  EXPECT_EQ(cfg.axes[2].name, "z");
  EXPECT_EQ(cfg.axis_mask(), core::axis_bit(kX) | core::axis_bit(kY) | core::axis_bit(kZ));
  for (const auto& a : cfg.axes) {
    EXPECT_TRUE(a.limit_switches) << a.name;  // T-1: switches at both ends of X and Y
    EXPECT_EQ(a.feedforward, 1.0);
  }
  EXPECT_EQ(cfg.axis(kZ)->home_side, HomeSide::Positive);  // the torch homes away from the work
  EXPECT_NO_THROW(validate(cfg));
}

TEST(MachineConfig, T3_ThesisPartsFitBesideTheHomingBackoff) {
  // T-3 parts lie within 0..50 mm; T-4 homing backs off 30 mm from the switch.
  const auto cfg = default_machine();
  for (std::size_t i : {kX, kY}) {
    const auto* a = cfg.axis(i);
    EXPECT_EQ(a->home_side, HomeSide::Negative);
    EXPECT_EQ(a->home_backoff_mm, 30.0);  // T-4
    EXPECT_LE(a->min_mm, 0.0);
    EXPECT_GE(a->max_mm, a->min_mm + a->home_backoff_mm + 50.0);
  }
}

TEST(MachineConfig, DefaultFollowingErrorLimitAllowsFullAcceleration) {
  // With full feed-forward the following error while accelerating is about a·τ/Kv; keep a wide margin.
  for (const auto& a : default_machine().axes)
    EXPECT_LT(a.max_acc_mm_s2 * a.drive_tau_s / a.kv_1_s + a.mm_per_count(), a.ferror_limit_mm / 2) << a.name;
}

// ---- the machine's view of its axes ----

TEST(MachineConfig, AxisLooksUpEnabledAxesOnly) {
  auto cfg = default_machine();
  EXPECT_EQ(cfg.axis(kY)->name, "y");
  EXPECT_EQ(cfg.axis(kA), nullptr);
  axis_of(cfg, kZ).enabled = false;
  EXPECT_EQ(cfg.axis(kZ), nullptr);
  EXPECT_EQ(cfg.axis_mask(), core::axis_bit(kX) | core::axis_bit(kY));
}

TEST(MachineConfig, LimitsMapEachAxisAndThePeriod) {
  auto cfg = default_machine();
  cfg.period_s = 0.002;
  auto& x = axis_of(cfg, kX);
  x.min_mm = -10;
  x.max_mm = 590;
  x.max_vel_mm_s = 123;
  x.max_acc_mm_s2 = 456;
  x.max_jerk_mm_s3 = 7890;
  axis_of(cfg, kZ).enabled = false;
  const auto l = cfg.limits();
  EXPECT_EQ(l.period_s, 0.002);
  EXPECT_EQ(l.axis[kX].v_max_mm_s, 123);
  EXPECT_EQ(l.axis[kX].a_max_mm_s2, 456);
  EXPECT_EQ(l.axis[kX].j_max_mm_s3, 7890);
  EXPECT_EQ(l.axis[kX].min_mm, -10);
  EXPECT_EQ(l.axis[kX].max_mm, 590);
  EXPECT_EQ(l.axis[kY].v_max_mm_s, 250);
  EXPECT_EQ(l.axis[kY].max_mm, 400);
  EXPECT_TRUE(l.present(kX));
  EXPECT_TRUE(l.present(kY));
  EXPECT_FALSE(l.present(kZ));  // disabled
  for (std::size_t i = kA; i < core::kMaxAxes; ++i) EXPECT_FALSE(l.present(i));
}

// ---- TOML out and back ----

TEST(MachineConfig, RoundTripOfTheDefault) {
  const auto cfg = default_machine();
  const auto text = to_toml(cfg);
  EXPECT_EQ(parse_machine(text, "effective.toml"), cfg);
  EXPECT_EQ(to_toml(parse_machine(text, "effective.toml")), text);  // deterministic
}

TEST(MachineConfig, RoundTripKeepsEveryFieldExactly) {
  auto cfg = default_machine();
  cfg.name = "table \"B\" \\ ü\ttab";
  cfg.period_s = 1.0 / 3000.0;
  cfg.planner_queue = 17;
  cfg.tool_output = "spindle";
  auto& x = axis_of(cfg, kX);
  x.min_mm = -0.1 - 0.2;  // not exactly representable in short decimal
  x.max_mm = 1e7;
  x.max_vel_mm_s = 123.456789012345678;
  x.max_jerk_mm_s3 = 0;
  x.counts_per_rev = 4096;
  x.mm_per_rev = 1.0 / 7.0;
  x.feedforward = 0;
  x.limit_switches = false;
  x.home_side = HomeSide::Positive;
  x.home_backoff_mm = 0;
  axis_of(cfg, kZ).enabled = false;
  axis_of(cfg, kZ).max_vel_mm_s = -1;  // a disabled axis keeps whatever it holds
  AxisConfig a = axis_of(cfg, kY);
  a.name = "a";
  a.index = kA;
  a.min_mm = -180;
  a.max_mm = 180;
  cfg.axes.push_back(a);
  const auto back = parse_machine(to_toml(cfg), "rt.toml");
  EXPECT_EQ(back, cfg);
  EXPECT_EQ(to_toml(back), to_toml(cfg));
}

TEST(MachineConfig, ToTomlWritesEveryKeyInAFixedOrder) {
  const auto text = to_toml(default_machine());
  const auto name = text.find("\nname = ");
  const auto period = text.find("\nperiod_s = ");
  const auto x = text.find("\n[axes.x]\n");
  const auto y = text.find("\n[axes.y]\n");
  const auto z = text.find("\n[axes.z]\n");
  ASSERT_NE(name, std::string::npos);
  EXPECT_LT(name, period);
  EXPECT_LT(period, x);
  EXPECT_LT(x, y);
  EXPECT_LT(y, z);
  EXPECT_THAT(text, HasSubstr("\nmax_vel_mm_s = 250.0\n"));  // floats stay floats
  EXPECT_THAT(text, HasSubstr("\nhome_side = \"negative\"\n"));
  EXPECT_THAT(text, HasSubstr("\nplanner_queue = 256\n"));
}

TEST(MachineConfig, ExampleFileEqualsTheDefault) {
  const auto path = source_path("examples/machines/cutting_table.toml");
  EXPECT_EQ(load_machine(path), default_machine());
  // ... and writes out every key, so the file alone describes the machine.
  std::set<std::string> example, effective;
  collect_keys(toml::parse_file(path), "", example);
  collect_keys(toml::parse(to_toml(default_machine())), "", effective);
  EXPECT_EQ(example, effective);
}

TEST(MachineConfig, DocsDescribeEveryKey) {
  const auto docs = read_text(source_path("docs/configuration.md"));
  ASSERT_FALSE(docs.empty());
  std::set<std::string> keys;
  collect_keys(toml::parse(to_toml(default_machine())), "", keys);
  for (const auto& k : keys) {
    const auto leaf = k.substr(k.rfind('.') + 1);
    EXPECT_THAT(docs, HasSubstr("`" + leaf + "`")) << k;
  }
}

TEST(MachineConfig, ParseKeepsBaseValuesForKeysNotGiven) {
  const auto cfg = parse_machine("[axes.x]\nmax_vel_mm_s = 100\n", "m.toml");
  auto expected = default_machine();
  axis_of(expected, kX).max_vel_mm_s = 100;  // an integer is a number too
  EXPECT_EQ(cfg, expected);
}

TEST(MachineConfig, DisabledZRemovesTheAxis) {
  const auto cfg = parse_machine("[axes.z]\nenabled = false\n", "m.toml");
  EXPECT_EQ(cfg.axis(kZ), nullptr);
  EXPECT_FALSE(cfg.limits().present(kZ));
  EXPECT_EQ(cfg.axis_mask(), core::axis_bit(kX) | core::axis_bit(kY));
}

TEST(MachineConfig, DottedAndInlineTablesAreTheSameKeys) {
  const auto a = parse_machine("axes.x.max_vel_mm_s = 100.0\naxes.y = { max_acc_mm_s2 = 900 }\n", "m.toml");
  EXPECT_EQ(a.axis(kX)->max_vel_mm_s, 100);
  EXPECT_EQ(a.axis(kY)->max_acc_mm_s2, 900);
}

TEST(MachineConfig, UnknownKeyIsAnErrorWithLineAndColumn) {
  const std::string text = "name = \"t\"\n\n[axes.x]\n  max_vel = 5\n";
  EXPECT_THAT(error_of([&] { parse_machine(text, "m.toml"); }),
              StartsWith("m.toml:4:3: error: unknown key axes.x.max_vel (did you mean max_vel_mm_s?)"));
  EXPECT_THAT(error_of([&] { parse_machine("feedrate = 1\n", "m.toml"); }),
              StartsWith("m.toml:1:1: error: unknown key feedrate"));
  EXPECT_THAT(error_of([&] { parse_machine("[axes.x.limits]\nmax = 1\n", "m.toml"); }),
              HasSubstr("error: unknown key axes.x.limits"));
  EXPECT_THAT(error_of([&] { parse_machine("[axes.q]\nmax_mm = 1\n", "m.toml"); }),
              HasSubstr("m.toml:1:7: error: unknown axis axes.q"));
  EXPECT_THAT(error_of([&] { parse_machine("[axes.X]\nmax_mm = 1\n", "m.toml"); }),
              HasSubstr("error: unknown axis axes.X"));  // keys are lower case, as written out
}

TEST(MachineConfig, WrongTypeIsAnError) {
  EXPECT_EQ(error_of([] { parse_machine("period_s = \"fast\"\n", "m.toml"); }),
            "m.toml:1:1: error: period_s must be a number (got string \"fast\")");
  EXPECT_EQ(error_of([] { parse_machine("[axes.x]\nenabled = 1\n", "m.toml"); }),
            "m.toml:2:1: error: axes.x.enabled must be true or false (got integer 1)");
  EXPECT_EQ(error_of([] { parse_machine("planner_queue = 2.5\n", "m.toml"); }),
            "m.toml:1:1: error: planner_queue must be an integer (got float 2.5)");
  EXPECT_EQ(error_of([] { parse_machine("tool_output = 3\n", "m.toml"); }),
            "m.toml:1:1: error: tool_output must be a string (got integer 3)");
  EXPECT_EQ(error_of([] { parse_machine("[axes.y]\nhome_side = \"left\"\n", "m.toml"); }),
            "m.toml:2:1: error: axes.y.home_side must be \"negative\" or \"positive\" (got string \"left\")");
  EXPECT_THAT(error_of([] { parse_machine("axes = 3\n", "m.toml"); }), HasSubstr("axes must be a table"));
  EXPECT_THAT(error_of([] { parse_machine("[axes]\nx = [1, 2]\n", "m.toml"); }),
              HasSubstr("m.toml:2:1: error: axes.x must be a table (got an array)"));
}

TEST(MachineConfig, BadValuePointsAtItsLine) {
  std::string text = "# a machine\nname = \"t\"\n";
  for (int i = 3; i < 11; ++i) text += "\n";
  text += "[axes.x]\nmax_vel_mm_s = -5\n";  // line 12
  EXPECT_EQ(error_of([&] { parse_machine(text, "machine.toml"); }),
            "machine.toml:12:1: error: axes.x.max_vel_mm_s must be > 0 (got -5)");
}

TEST(MachineConfig, RuleAcrossKeysPointsAtALineThatSetIt) {
  EXPECT_EQ(error_of([] { parse_machine("[axes.y]\nmin_mm = 500\n", "m.toml"); }),
            "m.toml:2:1: error: axes.y.min_mm must be < axes.y.max_mm (got 500 >= 400)");
  EXPECT_THAT(error_of([] { parse_machine("[axes.y]\nmax_mm = -1\n", "m.toml"); }),
              StartsWith("m.toml:2:1: error: axes.y.min_mm must be < axes.y.max_mm"));
  // j·dt³ below the jerk follower's floor: the jerk's line, or the period's where only it was set.
  EXPECT_THAT(error_of([] { parse_machine("period_s = 0.0001\n[axes.x]\nmax_jerk_mm_s3 = 100\n", "m.toml"); }),
              StartsWith("m.toml:3:1: error: axes.x.max_jerk_mm_s3 100 mm/s³ moves 1e-10 mm in a cycle of 0.0001 s"));
  EXPECT_THAT(error_of([] { parse_machine("name = \"t\"\nperiod_s = 0.00001\n", "m.toml"); }),
              StartsWith("m.toml:2:1: error: axes.x.max_jerk_mm_s3 50000 mm/s³ moves 5e-11 mm"));
}

TEST(MachineConfig, TomlSyntaxErrorHasLineAndColumn) {
  EXPECT_THAT(error_of([] { parse_machine("name = \"t\"\nperiod_s = = 1\n", "m.toml"); }),
              StartsWith("m.toml:2:"));
  EXPECT_THAT(error_of([] { parse_machine("name = 1\nname = 2\n", "m.toml"); }), StartsWith("m.toml:2:"));
}

TEST(MachineConfig, MissingFileIsAConfigError) {
  EXPECT_THAT(error_of([] { load_machine("/nonexistent/m.toml"); }),
              StartsWith("/nonexistent/m.toml: error: cannot open"));
}

// ---- --set overrides ----

TEST(MachineConfig, OverrideNumbers) {
  auto cfg = default_machine();
  apply_override(cfg, "axes.x.max_vel_mm_s=100");
  apply_override(cfg, "axes.y.max_acc_mm_s2 = 1500.5");
  apply_override(cfg, "period_s=5e-4");
  apply_override(cfg, "planner_queue=64");
  EXPECT_EQ(cfg.axis(kX)->max_vel_mm_s, 100);
  EXPECT_EQ(cfg.axis(kY)->max_acc_mm_s2, 1500.5);
  EXPECT_EQ(cfg.period_s, 5e-4);
  EXPECT_EQ(cfg.planner_queue, 64u);
  EXPECT_NO_THROW(validate(cfg));
}

TEST(MachineConfig, OverrideBoolsAndStrings) {
  auto cfg = default_machine();
  apply_override(cfg, "axes.x.limit_switches=false");
  apply_override(cfg, "tool_output=spindle");                // bare string
  apply_override(cfg, "name=\"table # 2\"");                 // TOML string
  apply_override(cfg, "axes.y.home_side=positive");
  EXPECT_FALSE(cfg.axis(kX)->limit_switches);
  EXPECT_EQ(cfg.tool_output, "spindle");
  EXPECT_EQ(cfg.name, "table # 2");
  EXPECT_EQ(cfg.axis(kY)->home_side, HomeSide::Positive);
}

TEST(MachineConfig, OverrideDisablesZ) {
  auto cfg = default_machine();
  apply_override(cfg, "axes.z.enabled=false");
  EXPECT_EQ(cfg.axis(kZ), nullptr);
  EXPECT_EQ(cfg.axis_mask(), core::axis_bit(kX) | core::axis_bit(kY));
  EXPECT_NO_THROW(validate(cfg));
  apply_override(cfg, "axes.z.enabled=true");
  EXPECT_EQ(cfg, default_machine());
}

TEST(MachineConfig, OverrideWithInlineTable) {
  auto cfg = default_machine();
  apply_override(cfg, "axes.x={ max_vel_mm_s = 100, kv_1_s = 40 }");
  EXPECT_EQ(cfg.axis(kX)->max_vel_mm_s, 100);
  EXPECT_EQ(cfg.axis(kX)->kv_1_s, 40);
}

TEST(MachineConfig, OverrideAndFileAgree) {
  const auto from_file = parse_machine("[axes.y]\nferror_limit_mm = 0.5\nhome_side = \"positive\"\n", "m.toml");
  auto from_set = default_machine();
  apply_override(from_set, "axes.y.ferror_limit_mm=0.5");
  apply_override(from_set, "axes.y.home_side=\"positive\"");
  EXPECT_EQ(from_set, from_file);
}

TEST(MachineConfig, OverrideUnknownKeyNamesIt) {
  auto cfg = default_machine();
  EXPECT_EQ(error_of([&] { apply_override(cfg, "axes.x.max_velocity=100"); }),
            "--set axes.x.max_velocity=100: error: unknown key axes.x.max_velocity (did you mean max_vel_mm_s?)");
  EXPECT_THAT(error_of([&] { apply_override(cfg, "period=0.002"); }),
              HasSubstr("unknown key period (did you mean period_s?)"));
  EXPECT_THAT(error_of([&] { apply_override(cfg, "axes.k.max_mm=1"); }), HasSubstr("unknown axis axes.k"));
  EXPECT_THAT(error_of([&] { apply_override(cfg, "axes.x.max_vel_mm_s"); }), HasSubstr("expected KEY=VALUE"));
  EXPECT_THAT(error_of([&] { apply_override(cfg, "axes..max_mm=1"); }), HasSubstr("bad key"));
  EXPECT_EQ(cfg, default_machine());
}

TEST(MachineConfig, OverrideChecksTypeAndValue) {
  auto cfg = default_machine();
  EXPECT_EQ(error_of([&] { apply_override(cfg, "axes.x.max_vel_mm_s=-5"); }),
            "--set axes.x.max_vel_mm_s=-5: error: axes.x.max_vel_mm_s must be > 0 (got -5)");
  EXPECT_THAT(error_of([&] { apply_override(cfg, "axes.x.max_vel_mm_s=fast"); }),
              HasSubstr("axes.x.max_vel_mm_s must be a number (got string \"fast\")"));
  EXPECT_THAT(error_of([&] { apply_override(cfg, "axes.z.enabled=1"); }), HasSubstr("must be true or false"));
  EXPECT_THAT(error_of([&] { apply_override(cfg, "planner_queue=-3"); }), HasSubstr("planner_queue must be >= 0"));
  EXPECT_THAT(error_of([&] { apply_override(cfg, "planner_queue=1"); }), HasSubstr("planner_queue must be"));
  EXPECT_THAT(error_of([&] { apply_override(cfg, "tool_output="); }), HasSubstr("tool_output must not be empty"));
  EXPECT_EQ(cfg, default_machine());  // a failed override changes nothing
}

TEST(MachineConfig, OverridesMayPassThroughRulesAcrossKeys) {
  // Moving X's travel to 700..900 crosses min_mm >= max_mm on the way; validate() judges the end.
  auto cfg = default_machine();
  apply_override(cfg, "axes.x.min_mm=700");
  EXPECT_THAT(error_of([&] { validate(cfg); }), HasSubstr("axes.x.min_mm must be < axes.x.max_mm"));
  apply_override(cfg, "axes.x.max_mm=900");
  EXPECT_NO_THROW(validate(cfg));
}

TEST(MachineConfig, OverrideOfANewAxisCreatesItFromDefaults) {
  auto cfg = default_machine();
  apply_override(cfg, "axes.a.max_mm=360");
  ASSERT_NE(cfg.axis(kA), nullptr);
  EXPECT_EQ(cfg.axes.back().name, "a");
  EXPECT_EQ(cfg.axis(kA)->counts_per_rev, AxisConfig{}.counts_per_rev);
  // No speed is invented for a new axis: validation asks for one.
  EXPECT_THAT(error_of([&] { validate(cfg); }), HasSubstr("axes.a.max_vel_mm_s must be > 0 (got 0)"));
  apply_override(cfg, "axes.a.max_vel_mm_s=90");
  apply_override(cfg, "axes.a.max_acc_mm_s2=900");
  EXPECT_NO_THROW(validate(cfg));
  EXPECT_EQ(cfg.axis_mask(), 0b1111);
  EXPECT_EQ(parse_machine(to_toml(cfg), "rt.toml"), cfg);
  // A new axis is inserted in axis order.
  apply_override(cfg, "axes.w.enabled=false");
  apply_override(cfg, "axes.u.enabled=false");
  ASSERT_EQ(cfg.axes.size(), 6u);
  for (std::size_t i = 1; i < cfg.axes.size(); ++i) EXPECT_LT(cfg.axes[i - 1].index, cfg.axes[i].index);
  EXPECT_NO_THROW(validate(cfg));
}

// ---- validation, rule by rule ----

struct RuleCase {
  const char* what;
  std::function<void(MachineConfig&)> change;
  const char* message;
};

TEST(MachineConfig, ValidateChecksEveryRule) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<RuleCase> cases{
      {"min >= max", [](auto& c) { axis_of(c, kX).min_mm = 600; }, "axes.x.min_mm must be < axes.x.max_mm (got 600 >= 600)"},
      {"min not finite", [&](auto& c) { axis_of(c, kX).min_mm = -inf; }, "axes.x.min_mm must be a finite number"},
      {"max NaN", [&](auto& c) { axis_of(c, kY).max_mm = nan; }, "axes.y.max_mm must be a finite number"},
      {"vel 0", [](auto& c) { axis_of(c, kX).max_vel_mm_s = 0; }, "axes.x.max_vel_mm_s must be > 0 (got 0)"},
      {"vel inf", [&](auto& c) { axis_of(c, kX).max_vel_mm_s = inf; }, "axes.x.max_vel_mm_s must be > 0 (got inf)"},
      {"acc < 0", [](auto& c) { axis_of(c, kY).max_acc_mm_s2 = -1; }, "axes.y.max_acc_mm_s2 must be > 0 (got -1)"},
      {"jerk < 0", [](auto& c) { axis_of(c, kZ).max_jerk_mm_s3 = -1; }, "axes.z.max_jerk_mm_s3 must be >= 0 (got -1)"},
      {"counts 0", [](auto& c) { axis_of(c, kX).counts_per_rev = 0; }, "axes.x.counts_per_rev must be > 0 (got 0)"},
      {"mm/rev < 0", [](auto& c) { axis_of(c, kX).mm_per_rev = -65; }, "axes.x.mm_per_rev must be > 0 (got -65)"},
      {"kv 0", [](auto& c) { axis_of(c, kX).kv_1_s = 0; }, "axes.x.kv_1_s must be > 0 (got 0)"},
      {"ff < 0", [](auto& c) { axis_of(c, kX).feedforward = -0.1; }, "axes.x.feedforward must be between 0 and 1 (got -0.1)"},
      {"ff > 1", [](auto& c) { axis_of(c, kX).feedforward = 1.5; }, "axes.x.feedforward must be between 0 and 1 (got 1.5)"},
      {"emergency scale < 1", [](auto& c) { c.planner.emergency_accel_scale = 0.3; }, "planner.emergency_accel_scale must be >= 1 (got 0.3)"},
      {"tau 0", [](auto& c) { axis_of(c, kX).drive_tau_s = 0; }, "axes.x.drive_tau_s must be > 0 (got 0)"},
      {"ferror 0", [](auto& c) { axis_of(c, kX).ferror_limit_mm = 0; }, "axes.x.ferror_limit_mm must be > 0 (got 0)"},
      {"overtravel < 0", [](auto& c) { axis_of(c, kX).switch_overtravel_mm = -2; }, "axes.x.switch_overtravel_mm must be >= 0 (got -2)"},
      {"backoff < 0", [](auto& c) { axis_of(c, kX).home_backoff_mm = -1; }, "axes.x.home_backoff_mm must be >= 0 (got -1)"},
      {"backoff >= travel", [](auto& c) { axis_of(c, kZ).home_backoff_mm = 100; }, "axes.z.home_backoff_mm must be < the travel"},
      {"jerk per cycle below the follower's floor", [](auto& c) { c.period_s = 1e-4; axis_of(c, kX).max_jerk_mm_s3 = 100; },
       "axes.x.max_jerk_mm_s3 100 mm/s³ moves 1e-10 mm in a cycle of 0.0001 s; the jerk follower needs at least 2e-09 mm "
       "(max_jerk_mm_s3 >= 2000, a longer period_s, or 0 for no jerk limit)"},
      {"period small", [](auto& c) { c.period_s = 1e-6; }, "period_s must be between 1e-05 and 0.1 s (got 1e-06)"},
      {"period large", [](auto& c) { c.period_s = 0.2; }, "period_s must be between 1e-05 and 0.1 s (got 0.2)"},
      {"queue < 2", [](auto& c) { c.planner_queue = 1; }, "planner_queue must be an integer between 2 and 1048576 (got 1)"},
      {"queue huge", [](auto& c) { c.planner_queue = std::size_t{1} << 30; }, "planner_queue must be an integer between 2"},
      {"tool empty", [](auto& c) { c.tool_output.clear(); }, "tool_output must not be empty"},
      {"no axis", [](auto& c) { c.axes.clear(); }, "axes: at least one axis must be enabled"},
      {"all disabled", [](auto& c) { for (auto& a : c.axes) a.enabled = false; }, "axes: at least one axis must be enabled"},
      {"out of order", [](auto& c) { std::swap(c.axes[0], c.axes[1]); }, "axes must be in axis order without duplicates"},
      {"bad name", [](auto& c) { c.axes[0].name = "q"; }, "axes.x: axis name \"q\" does not match its index"},
  };
  for (const auto& rc : cases) {
    auto cfg = default_machine();
    rc.change(cfg);
    EXPECT_THAT(error_of([&] { validate(cfg); }), StartsWith(std::string("cutting_table: error: ") + rc.message))
        << rc.what;
  }
}

TEST(MachineConfig, ValidateAcceptsTheEdgesOfEachRange) {
  auto cfg = default_machine();
  cfg.period_s = 1e-5;
  cfg.planner_queue = 2;
  auto& x = axis_of(cfg, kX);
  x.max_jerk_mm_s3 = 0;  // no jerk limit
  axis_of(cfg, kY).max_jerk_mm_s3 = 2e6;  // j·dt³ = 2e-9 mm: the follower's floor
  axis_of(cfg, kZ).max_jerk_mm_s3 = 2e6;
  x.feedforward = 0;
  x.switch_overtravel_mm = 0;
  x.home_backoff_mm = 0.25;  // > the overtravel (homing ends inside the travel), < the travel
  x.min_mm = -1;
  x.max_mm = -0.5;
  EXPECT_NO_THROW(validate(cfg));
  cfg.period_s = 0.1;
  axis_of(cfg, kY).feedforward = 1;
  EXPECT_NO_THROW(validate(cfg));
}

// The jerk floor (motion::kMinJerkStep_mm, 2e-9 mm of one cycle's jerk j·dt³), a rule of softmc's own
// and no spec's: below it the jerk follower's landings are coarser than a cycle of jerk (a fuzzer's
// axes 1.2–6× over their jerk between 2e-10 and 2e-9 mm, docs/planner.md "Tiny jerk per cycle").
// At each period a jerk just below the floor is refused with the jerk it needs, the floor is accepted.
TEST(MachineConfig, JerkPerCycleBelowTheFloorIsRefusedWithTheJerkItNeeds) {
  struct Edge {
    double period_s, floor_jerk, below;
    const char* message;
  };
  for (const Edge& e : {Edge{0.0001, 2000, 1990, "axes.y.max_jerk_mm_s3 1990 mm/s³ moves 1.99e-09 mm in a cycle of 0.0001 s; "
                                                 "the jerk follower needs at least 2e-09 mm (max_jerk_mm_s3 >= 2000"},
                        Edge{0.00025, 128, 127, "axes.y.max_jerk_mm_s3 127 mm/s³ moves 1.98e-09 mm in a cycle of 0.00025 s; "
                                                  "the jerk follower needs at least 2e-09 mm (max_jerk_mm_s3 >= 128"},
                        Edge{0.0005, 16, 15.9, "axes.y.max_jerk_mm_s3 15.9 mm/s³ moves 1.99e-09 mm in a cycle of 0.0005 s; "
                                               "the jerk follower needs at least 2e-09 mm (max_jerk_mm_s3 >= 16"},
                        Edge{0.001, 2, 1.99, "axes.y.max_jerk_mm_s3 1.99 mm/s³ moves 1.99e-09 mm in a cycle of 0.001 s; "
                                             "the jerk follower needs at least 2e-09 mm (max_jerk_mm_s3 >= 2"}}) {
    auto cfg = default_machine();
    cfg.period_s = e.period_s;
    EXPECT_EQ(e.floor_jerk * e.period_s * e.period_s * e.period_s, motion::kMinJerkStep_mm);
    axis_of(cfg, kY).max_jerk_mm_s3 = e.below;
    EXPECT_THAT(error_of([&] { validate(cfg); }), StartsWith(std::string("cutting_table: error: ") + e.message))
        << e.period_s;
    axis_of(cfg, kY).max_jerk_mm_s3 = e.floor_jerk;
    EXPECT_NO_THROW(validate(cfg)) << e.period_s;
    axis_of(cfg, kY).max_jerk_mm_s3 = 0;  // no jerk limit: no floor
    EXPECT_NO_THROW(validate(cfg)) << e.period_s;
  }
}

TEST(MachineConfig, DisabledAxisIsNotChecked) {
  auto cfg = default_machine();
  axis_of(cfg, kZ).enabled = false;
  axis_of(cfg, kZ).max_vel_mm_s = -5;
  EXPECT_NO_THROW(validate(cfg));
}

// [gcode]: the interpreter's tool table, subroutine folders and P-10 M functions (docs/configuration.md).
TEST(MachineConfig, GcodeTableRoundTrips) {
  const std::string text =
      "[gcode]\ntool_table = \"/opt/tools.tbl\"\nsubroutine_path = [\"/opt/subs\", \"/opt/more subs\"]\n"
      "[gcode.m.100]\ngroup = 4\nbreak_path_start = true\n"
      "[gcode.m.6]\nbreak_path_end = true\nchanges_position = true\n";
  const auto cfg = parse_machine(text, "m.toml");
  EXPECT_EQ(cfg.gcode.tool_table, "/opt/tools.tbl");
  EXPECT_EQ(cfg.gcode.subroutine_path, (std::vector<std::string>{"/opt/subs", "/opt/more subs"}));
  ASSERT_EQ(cfg.gcode.m.size(), 2u);
  EXPECT_EQ(cfg.gcode.m[0], (MFunctionConfig{6, 0, false, true, true}));  // kept in number order
  EXPECT_EQ(cfg.gcode.m[1], (MFunctionConfig{100, 4, true, false, false}));
  const auto written = to_toml(cfg);
  EXPECT_THAT(written, HasSubstr("\n[gcode.m.100]\ngroup = 4\nbreak_path_start = true\n"));
  EXPECT_EQ(parse_machine(written, "out.toml"), cfg);
  // --set reaches the same keys.
  auto over = cfg;
  apply_override(over, "gcode.m.101.group=12");
  apply_override(over, "gcode.subroutine_path=[\"a\"]");
  ASSERT_EQ(over.gcode.m.size(), 3u);
  EXPECT_EQ(over.gcode.m[2].group, 12);
  EXPECT_EQ(over.gcode.subroutine_path, std::vector<std::string>{"a"});
}

TEST(MachineConfig, GcodeErrorsNameTheKey) {
  EXPECT_THAT(error_of([] { parse_machine("[gcode.m.100]\ngroup = 15\n", "m.toml"); }),
              StartsWith("m.toml:2:1: error: gcode.m.100.group must be an M function group 1..14, or 0 for the "
                         "function's own (got 15)"));
  EXPECT_THAT(error_of([] { parse_machine("[gcode.m.100]\nbreak_path = true\n", "m.toml"); }),
              StartsWith("m.toml:2:1: error: unknown key gcode.m.100.break_path (did you mean break_path_start?)"));
  EXPECT_THAT(error_of([] { parse_machine("[gcode.m.x]\ngroup = 4\n", "m.toml"); }),
              HasSubstr("error: unknown M function gcode.m.x (M functions are numbered 0..199)"));
  EXPECT_THAT(error_of([] { parse_machine("[gcode.m.200]\ngroup = 4\n", "m.toml"); }),
              HasSubstr("error: unknown M function gcode.m.200"));
  EXPECT_THAT(error_of([] { parse_machine("[gcode]\nsubroutine_path = \"subs\"\n", "m.toml"); }),
              StartsWith("m.toml:2:1: error: gcode.subroutine_path must be an array of strings (got string \"subs\")"));
  EXPECT_THAT(error_of([] { parse_machine("[gcode]\nsubroutine_path = [\"a\", 1]\n", "m.toml"); }),
              HasSubstr("gcode.subroutine_path must be an array of strings (got integer 1 in it)"));
  EXPECT_THAT(error_of([] { parse_machine("[gcode]\ntooltable = \"t.tbl\"\n", "m.toml"); }),
              HasSubstr("unknown key gcode.tooltable (did you mean tool_table?)"));
}

TEST(MachineConfig, GcodePathsAreRelativeToTheConfigurationFile) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("softmc_cfg_" + std::to_string(::getpid()));
  fs::create_directories(dir / "machines");
  const fs::path file = dir / "machines" / "m.toml";
  std::ofstream(file) << "[gcode]\ntool_table = \"tools/t.tbl\"\nsubroutine_path = [\"../subs\", \"/abs\"]\n";
  const auto cfg = load_machine(file.string());
  EXPECT_EQ(cfg.gcode.tool_table, (dir / "machines" / "tools" / "t.tbl").string());
  EXPECT_EQ(cfg.gcode.subroutine_path, (std::vector<std::string>{(dir / "subs").string(), "/abs"}));
  fs::remove_all(dir);
}

// The simulated fallback brake broke axis limits in short look-ahead windows (stop 23's review:
// 680× the jerk in a window of 8 blocks): not offered, with the reason, in a file and in a --set;
// the default (false) is accepted as before.
TEST(MachineConfig, TheSimulatedJerkGuardIsRefusedWithItsReason) {
  EXPECT_THAT(error_of([&] { parse_machine("[planner]\njerk_guard_simulate = true\n", "m.toml"); }),
              ::testing::HasSubstr("m.toml:2:1: error: planner.jerk_guard_simulate = true is not available"));
  auto cfg = default_machine();
  EXPECT_THAT(error_of([&] { apply_override(cfg, "planner.jerk_guard_simulate=true"); }),
              ::testing::HasSubstr("broke axis limits in short look-ahead windows"));
  EXPECT_FALSE(cfg.planner.jerk_guard_simulate);  // the refused override changed nothing
  EXPECT_EQ(error_of([&] { parse_machine("[planner]\njerk_guard_simulate = false\n", "m.toml"); }), "no error");
}

// T-4: homing backs off home_backoff_mm from a switch that sits switch_overtravel_mm beyond the
// travel; a back-off no longer than that ends outside the travel (or on the switch).
TEST(MachineConfig, T4_HomingMustEndInsideTheTravel) {
  auto cfg = default_machine();
  axis_of(cfg, kX).home_backoff_mm = 2.0;  // = the 2 mm overtravel: homing would end on the travel's end
  try {
    validate(cfg);
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("axes.x.home_backoff_mm must be > axes.x.switch_overtravel_mm"), std::string::npos)
        << e.what();
  }
  axis_of(cfg, kX).limit_switches = false;  // no switch, no homing: any back-off
  EXPECT_NO_THROW(validate(cfg));
}
