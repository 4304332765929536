// Machine configuration: axes, drives, switches, interpolation period; loaded from TOML (toml++).
#pragma once

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/axes.hpp"
#include "motion/limits.hpp"

namespace softmc::machine {

enum class HomeSide : std::uint8_t { Negative, Positive };

struct AxisConfig {
  std::string name;             // "x", "y", "z", ... (lower case in TOML keys, letter on screen)
  std::size_t index = 0;        // core::Axis index
  bool enabled = true;
  double min_mm = 0, max_mm = 0;      // travel
  double max_vel_mm_s = 0;
  double max_acc_mm_s2 = 0;
  double max_jerk_mm_s3 = 0;          // 0 = no jerk limit
  double counts_per_rev = 512;        // encoder resolution
  double mm_per_rev = 65;             // travel per motor revolution
  double kv_1_s = 30;                 // position-loop gain (velocity per following error)
  double feedforward = 1.0;           // velocity feed-forward gain, 0..1
  double drive_tau_s = 0.005;         // first-order motor/drive time constant
  double ferror_limit_mm = 2.0;       // following error beyond which the machine faults
  bool limit_switches = true;         // switches at both travel ends
  double switch_overtravel_mm = 2.0;  // a limit switch sits this far beyond the travel end
  HomeSide home_side = HomeSide::Negative;
  double home_backoff_mm = 30.0;
  double home_vel_mm_s = 0;           // homing's search speed (0: a tenth of max_vel_mm_s)

  double mm_per_count() const { return mm_per_rev / counts_per_rev; }
  friend bool operator==(const AxisConfig&, const AxisConfig&) = default;
};

// The SPC200 positioning controller (spc200.md), used when `softmc run` is given a program store: the
// [spc] table. Plain values here; control/spc turns them into its own configuration.
struct SpcMachineConfig {
  std::string mode = "start-stop";  // S-8 "start-stop" or S-9 "record-select"
  int task_a = -1;                  // start (S-8) / record (S-9) program of task A, 0..99; -1 = none
  int task_b = -1;
  double self_test_s = 10.0;        // power-up self-test (S-8/S-9: about 10 s)
  double input_filter_s = 0.005;    // every input's filter time (S-9: 5 ms)
  double g61_window2_mm = 1.0;      // G61 condition 2..6: actual position within ± this of the target (S-3)
  double g61_window3_mm = 0.5;
  double g61_window4_mm = 0.2;
  double g61_window5_mm = 0.1;
  double g61_window6_mm = 0.05;
  double g61_settle_s = 0.05;       // ... for this long
  double g02_ramp_s = 0.1;          // G02 smoothing: shortest sine-squared acceleration ramp
  bool g01_s_curve = false;         // G00/G01 jerk-limited (axis max_jerk_mm_s3) instead of trapezoids
  std::string registers_file;       // SQLite file of the retentive registers; "" = registers.sqlite in the store
  friend bool operator==(const SpcMachineConfig&, const SpcMachineConfig&) = default;
};

// The look-ahead planner (docs/planner.md): the [planner] table.
struct PlannerMachineConfig {
  double tolerance_mm = 0.05;      // G64 without P, and G23: largest distance of the path from a programmed corner
  std::size_t lookahead = 2000;    // blocks in the look-ahead window (a blended corner makes two)
  double max_feed_override = 2.0;  // P-8: the feed override is clamped to [0, this]; planned for
  double emergency_accel_scale = 1.0;  // P-5: an emergency stop brakes with this × each axis's acceleration and jerk
  double merge_share = 0.5;        // nearly collinear lines merge while within merge_share·P (0 = off)
  double smoothing_turn_deg = 20;  // jerk mode: runs of lines turning less than this become a C² spline (0 = off)
  double fillet_share = 0.8;       // jerk mode: a line–arc–line fillet becomes one quintic where it keeps this share of the arc's cap (0 = off)
  bool corner_stops = true;        // a corner is a stop where that is estimated quicker than its blend (false: always blend)
  bool corner_overlap = true;      // jerk mode: a stop between two lines starts the second while the first still brakes, within P
  bool jerk_guard_simulate = false;  // jerk mode: simulate the fallback brake where the certificate cannot decide
  friend bool operator==(const PlannerMachineConfig&, const PlannerMachineConfig&) = default;
};

// One M function's configuration (plc_interface.md P-10): a [gcode.m.<n>] table. An entry gives the
// function's whole configuration: flags not written are false. Fixed functions keep their group.
struct MFunctionConfig {
  int number = 0;                 // M0 … M199 (P-10 configures 0 … 100; LinuxCNC's user M100 … M199)
  int group = 0;                  // 0 = its own: a fixed function's P-10 group, else 14; free groups 4, 10 … 14
  bool break_path_start = false;  // the continuous path stops before the block
  bool break_path_end = false;    // … after the block
  bool changes_position = false;  // the function moves the machine (the path is re-read after it)
  friend bool operator==(const MFunctionConfig&, const MFunctionConfig&) = default;
};

// The G-code interpreter (docs/gcode.md): the [gcode] table. Relative paths in a configuration file
// are taken from that file's folder (load_machine makes them absolute).
struct GcodeMachineConfig {
  std::string tool_table;                    // LinuxCNC .tbl file for H and D words; "" = none
  std::vector<std::string> subroutine_path;  // folders searched for o<name> call files, in order
  std::vector<MFunctionConfig> m;            // [gcode.m.<n>], by number
  friend bool operator==(const GcodeMachineConfig&, const GcodeMachineConfig&) = default;
};

struct MachineConfig {
  std::string name = "cutting_table";
  double period_s = 0.001;                 // interpolation period
  std::vector<AxisConfig> axes;            // the configured axes, in axis order
  std::string tool_output = "torch";       // name of the tool (torch/spindle) output
  std::size_t planner_queue = 256;         // timed segments the planner may hold
  SpcMachineConfig spc;                    // [spc]
  PlannerMachineConfig planner;            // [planner]
  GcodeMachineConfig gcode;                // [gcode]

  // Only enabled axes count as the machine's axes: axis() is nullptr for a disabled one.
  const AxisConfig* axis(std::size_t index) const;
  core::AxisMask axis_mask() const;
  motion::MachineLimits limits() const;
  // Blocks the planner's window holds: planner.lookahead, or planner_queue where that is larger.
  std::size_t planner_window() const { return planner.lookahead > planner_queue ? planner.lookahead : planner_queue; }
  friend bool operator==(const MachineConfig&, const MachineConfig&) = default;
};

// The built-in machine: the two-axis cutting table of the thesis (cutting_table.md T-1), plus Z.
MachineConfig default_machine();

// Parse a TOML document over a base configuration (keys not given keep the base's values).
// Throws ConfigError naming the key (and file:line:col where toml++ knows it) on bad input.
struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
MachineConfig load_machine(const std::string& path);                       // file over default_machine()
MachineConfig parse_machine(const std::string& toml_text, const std::string& source_name);
// Apply one `key=value` override (e.g. "axes.x.max_vel_mm_s=100") through the loader's code path:
// same keys, types and per-value rules. Rules across keys (min_mm < max_mm, ...) are left to
// validate(), run once after all overrides, so a sequence of overrides may pass through them.
void apply_override(MachineConfig& cfg, const std::string& assignment);
// The effective configuration as TOML (round-trips through parse_machine).
std::string to_toml(const MachineConfig& cfg);
// Checks every value; throws ConfigError naming the first bad key.
void validate(const MachineConfig& cfg);

}  // namespace softmc::machine
