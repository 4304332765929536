// The [spc] table of the machine configuration: keys, rules, and what the controller and axes take from it.
#include <gtest/gtest.h>

#include <string>

#include "control/spc/controller.hpp"
#include "machine/config.hpp"

namespace softmc::control::spc {
namespace {

TEST(Spc200, S8_ConfigSpcTableSetsModeProgramsAndTimes) {
  const auto m = machine::parse_machine(
      "[spc]\nmode = \"record-select\"\ntask_a = 3\ntask_b = 12\nself_test_s = 0.5\ninput_filter_s = 0.002\n"
      "g61_window4_mm = 0.25\ng61_settle_s = 0.02\ng02_ramp_s = 0.2\ng01_s_curve = true\n",
      "m.toml");
  const auto c = controller_config_from(m.spc);
  EXPECT_EQ(c.mode, SpcMode::RecordSelect);
  EXPECT_EQ(c.program_a, 3);
  EXPECT_EQ(c.program_b, 12);
  EXPECT_DOUBLE_EQ(c.self_test_s, 0.5);
  EXPECT_DOUBLE_EQ(c.input_filter_s, 0.002);
  const auto a = spc_axes_from(m);
  EXPECT_DOUBLE_EQ(a.windows_mm[2], 0.25);  // condition 4
  EXPECT_DOUBLE_EQ(a.windows_mm[0], 1.0);   // untouched default
  EXPECT_DOUBLE_EQ(a.settle_s, 0.02);
  EXPECT_DOUBLE_EQ(a.sine_squared_s, 0.2);
  EXPECT_TRUE(a.s_curve);
  EXPECT_TRUE(a.axis[0].present);
  EXPECT_FALSE(a.axis[3].present);  // the built-in table has no U
  EXPECT_DOUBLE_EQ(a.axis[0].j_max_mm_s3, 50000.0);
  // Round trip through the effective TOML.
  EXPECT_EQ(machine::parse_machine(machine::to_toml(m), "rt.toml"), m);
}

TEST(Spc200, S8_ConfigSpcRulesNameTheKey) {
  auto expect_error = [](const std::string& toml, const std::string& what) {
    try {
      machine::parse_machine(toml, "m.toml");
      ADD_FAILURE() << "accepted: " << toml;
    } catch (const machine::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_error("[spc]\nmode = \"fast\"\n", "spc.mode must be \"start-stop\" or \"record-select\"");
  expect_error("[spc]\ntask_a = 100\n", "spc.task_a must be a program number 0..99");
  expect_error("[spc]\ntask_b = 1.5\n", "spc.task_b must be an integer");
  expect_error("[spc]\ng61_window6_mm = 0\n", "spc.g61_window6_mm must be > 0");
  expect_error("[spc]\nself_test = 1\n", "unknown key spc.self_test (did you mean self_test_s?)");
  auto m = machine::default_machine();
  machine::apply_override(m, "spc.task_a=-1");
  machine::apply_override(m, "spc.mode=record-select");
  EXPECT_EQ(m.spc.mode, "record-select");
  EXPECT_THROW(machine::apply_override(m, "spc.task_a=-2"), machine::ConfigError);
}

}  // namespace
}  // namespace softmc::control::spc
