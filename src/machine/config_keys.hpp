// The machine configuration's keys in one table (name, field, rule), shared by loader, overrides, to_toml, validate.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "machine/config.hpp"

namespace softmc::machine {

// What a single value must satisfy on its own; rules across keys live in find_problem().
enum class ConfigRule : std::uint8_t {
  None,
  Finite,        // any finite number
  Positive,      // > 0
  NonNegative,   // >= 0
  UnitInterval,  // in [0, 1]
  AtLeastOne,    // >= 1 (a factor that may only make something stronger)
  Period,        // in [kMinPeriod_s, kMaxPeriod_s]
  Queue,         // integer in [kMinQueue, kMaxQueue]
  NonEmpty,      // a non-empty string
  SpcProgram,    // an SPC program number 0..99, or -1 for none
  SpcMode,       // "start-stop" or "record-select"
  MGroup,        // a P-10 M function group 1..14, or 0 for the function's own
};

inline constexpr double kMinPeriod_s = 1e-5;
inline constexpr double kMaxPeriod_s = 0.1;
inline constexpr std::size_t kMinQueue = 2;
// Guards against a typo allocating gigabytes when the machine is configured.
inline constexpr std::size_t kMaxQueue = 1u << 20;

template <class Owner>
using ConfigField = std::variant<double Owner::*, bool Owner::*, std::string Owner::*, std::size_t Owner::*,
                           HomeSide Owner::*, int Owner::*, std::vector<std::string> Owner::*>;

template <class Owner>
struct ConfigKey {
  std::string_view name;
  ConfigField<Owner> field;
  ConfigRule rule;
};

// Top-level keys, in the order to_toml writes them.
inline const std::array<ConfigKey<MachineConfig>, 4> kMachineKeys{{
    {"name", &MachineConfig::name, ConfigRule::None},
    {"period_s", &MachineConfig::period_s, ConfigRule::Period},
    {"planner_queue", &MachineConfig::planner_queue, ConfigRule::Queue},
    {"tool_output", &MachineConfig::tool_output, ConfigRule::NonEmpty},
}};

// Keys of an [axes.<letter>] table: exactly the AxisConfig fields (name and index come from the letter).
inline const std::array<ConfigKey<AxisConfig>, 17> kAxisKeys{{
    {"enabled", &AxisConfig::enabled, ConfigRule::None},
    {"min_mm", &AxisConfig::min_mm, ConfigRule::Finite},
    {"max_mm", &AxisConfig::max_mm, ConfigRule::Finite},
    {"max_vel_mm_s", &AxisConfig::max_vel_mm_s, ConfigRule::Positive},
    {"max_acc_mm_s2", &AxisConfig::max_acc_mm_s2, ConfigRule::Positive},
    {"max_jerk_mm_s3", &AxisConfig::max_jerk_mm_s3, ConfigRule::NonNegative},
    {"counts_per_rev", &AxisConfig::counts_per_rev, ConfigRule::Positive},
    {"mm_per_rev", &AxisConfig::mm_per_rev, ConfigRule::Positive},
    {"kv_1_s", &AxisConfig::kv_1_s, ConfigRule::Positive},
    {"feedforward", &AxisConfig::feedforward, ConfigRule::UnitInterval},
    {"drive_tau_s", &AxisConfig::drive_tau_s, ConfigRule::Positive},
    {"ferror_limit_mm", &AxisConfig::ferror_limit_mm, ConfigRule::Positive},
    {"limit_switches", &AxisConfig::limit_switches, ConfigRule::None},
    {"switch_overtravel_mm", &AxisConfig::switch_overtravel_mm, ConfigRule::NonNegative},
    {"home_side", &AxisConfig::home_side, ConfigRule::None},
    {"home_backoff_mm", &AxisConfig::home_backoff_mm, ConfigRule::NonNegative},
    {"home_vel_mm_s", &AxisConfig::home_vel_mm_s, ConfigRule::NonNegative},
}};

// Keys of the [spc] table (spc200.md; docs/spc.md).
inline const std::array<ConfigKey<SpcMachineConfig>, 14> kSpcKeys{{
    {"mode", &SpcMachineConfig::mode, ConfigRule::SpcMode},
    {"task_a", &SpcMachineConfig::task_a, ConfigRule::SpcProgram},
    {"task_b", &SpcMachineConfig::task_b, ConfigRule::SpcProgram},
    {"self_test_s", &SpcMachineConfig::self_test_s, ConfigRule::NonNegative},
    {"input_filter_s", &SpcMachineConfig::input_filter_s, ConfigRule::NonNegative},
    {"g61_window2_mm", &SpcMachineConfig::g61_window2_mm, ConfigRule::Positive},
    {"g61_window3_mm", &SpcMachineConfig::g61_window3_mm, ConfigRule::Positive},
    {"g61_window4_mm", &SpcMachineConfig::g61_window4_mm, ConfigRule::Positive},
    {"g61_window5_mm", &SpcMachineConfig::g61_window5_mm, ConfigRule::Positive},
    {"g61_window6_mm", &SpcMachineConfig::g61_window6_mm, ConfigRule::Positive},
    {"g61_settle_s", &SpcMachineConfig::g61_settle_s, ConfigRule::NonNegative},
    {"g02_ramp_s", &SpcMachineConfig::g02_ramp_s, ConfigRule::NonNegative},
    {"g01_s_curve", &SpcMachineConfig::g01_s_curve, ConfigRule::None},
    {"registers_file", &SpcMachineConfig::registers_file, ConfigRule::None},
}};

// Keys of the [planner] table (docs/planner.md).
inline const std::array<ConfigKey<PlannerMachineConfig>, 10> kPlannerKeys{{
    {"tolerance_mm", &PlannerMachineConfig::tolerance_mm, ConfigRule::NonNegative},
    {"lookahead", &PlannerMachineConfig::lookahead, ConfigRule::Queue},
    {"max_feed_override", &PlannerMachineConfig::max_feed_override, ConfigRule::Positive},
    {"emergency_accel_scale", &PlannerMachineConfig::emergency_accel_scale, ConfigRule::AtLeastOne},
    {"merge_share", &PlannerMachineConfig::merge_share, ConfigRule::UnitInterval},
    {"smoothing_turn_deg", &PlannerMachineConfig::smoothing_turn_deg, ConfigRule::NonNegative},
    {"fillet_share", &PlannerMachineConfig::fillet_share, ConfigRule::UnitInterval},
    {"corner_stops", &PlannerMachineConfig::corner_stops, ConfigRule::None},
    {"corner_overlap", &PlannerMachineConfig::corner_overlap, ConfigRule::None},
    {"jerk_guard_simulate", &PlannerMachineConfig::jerk_guard_simulate, ConfigRule::None},
}};

// Keys of the [gcode] table (docs/gcode.md, docs/configuration.md).
inline const std::array<ConfigKey<GcodeMachineConfig>, 2> kGcodeKeys{{
    {"tool_table", &GcodeMachineConfig::tool_table, ConfigRule::None},
    {"subroutine_path", &GcodeMachineConfig::subroutine_path, ConfigRule::None},
}};

// Keys of a [gcode.m.<n>] table (P-10); the number comes from the table's name.
inline const std::array<ConfigKey<MFunctionConfig>, 4> kMFunctionKeys{{
    {"group", &MFunctionConfig::group, ConfigRule::MGroup},
    {"break_path_start", &MFunctionConfig::break_path_start, ConfigRule::None},
    {"break_path_end", &MFunctionConfig::break_path_end, ConfigRule::None},
    {"changes_position", &MFunctionConfig::changes_position, ConfigRule::None},
}};
inline constexpr int kMaxMFunction = 199;

// "axes.x" for axis index 0.
std::string axis_key(std::size_t index);
// The TOML spelling of a home side: "negative" / "positive".
std::string_view home_side_name(HomeSide s);
std::optional<HomeSide> home_side_from(std::string_view s);

// Shortest text that reads back as the same double ("-5", "0.127", "1e-05").
std::string format_number(double v);

// "must be > 0 (got -5)" when the value breaks the rule, else nothing.
std::optional<std::string> rule_violation(ConfigRule rule, double v);
std::optional<std::string> rule_violation(ConfigRule rule, std::size_t v);
std::optional<std::string> rule_violation(ConfigRule rule, const std::string& v);
std::optional<std::string> rule_violation(ConfigRule rule, int v);

// The first thing wrong with a configuration. `keys` are the dotted keys involved, most specific first,
// so that a loader can point at the line that set one of them.
struct ConfigProblem {
  std::vector<std::string> keys;
  std::string message;  // names the key: "axes.x.max_vel_mm_s must be > 0 (got -5)"
};
// Every rule, in a fixed order: top-level keys, the axes list, then each enabled axis key by key.
// With `only` given, checks the single-value rules of just those keys (no rules across keys).
std::optional<ConfigProblem> find_problem(const MachineConfig& cfg, const std::vector<std::string>* only = nullptr);

}  // namespace softmc::machine
