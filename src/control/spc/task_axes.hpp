// The four SPC axes X, Y, Z, U shared by tasks A and B: setpoint generators, ownership (S-2), G61
// completion windows (S-3), the STOP rule for relative moves, M37 mass, and the per-cycle output.
#pragma once

#include <array>
#include <cstdint>

#include "control/spc/task_axis_mover.hpp"
#include "core/axes.hpp"
#include "machine/config.hpp"
#include "program/ir/spc_ops.hpp"

namespace softmc::control::spc {

using program::kSpcAxes;

struct SpcAxisConfig {
  bool present = false;
  double v_max_mm_s = 0;
  double a_max_mm_s2 = 0;
  double min_mm = -1e9, max_mm = 1e9;  // travel
  double j_max_mm_s3 = 0;              // jerk limit of S-curves and G02 (0 = none)
};

struct SpcAxesConfig {
  std::array<SpcAxisConfig, kSpcAxes> axis{};
  double period_s = 0.001;
  // G61 decision (S-3): condition 2..6 = setpoint at target and |actual - target| within window k-2
  // for settle_s.
  std::array<double, 5> windows_mm{1.0, 0.5, 0.2, 0.1, 0.05};
  double settle_s = 0.05;
  double sine_squared_s = 0.1;  // G02 smoothing: shortest sin² ramp, i.e. G02 jerk ≤ a·π/sine_squared_s
  bool s_curve = false;         // G00/G01 jerk-limited (Otg1 at j_max_mm_s3) instead of trapezoids
};

// SPC axis i → core axis index: X Y Z U.
constexpr std::size_t core_axis(std::size_t spc_axis) {
  constexpr std::array<std::size_t, kSpcAxes> k{0, 1, 2, 6};
  return k[spc_axis];
}
// The SPC axes of a machine configuration (those of X, Y, Z, U that are enabled) and its [spc] G61
// windows, settling time and smoothing.
SpcAxesConfig spc_axes_from(const machine::MachineConfig& m);

enum class AxisCmd : std::uint8_t { Ok, NotPresent, OwnedByOtherTask, NeedsAbsolute, OutOfTravel };
const char* to_string(AxisCmd r);

// What the cycle publishes for the drives (the composition root wires it to SimDrive).
struct SpcAxesOutput {
  std::array<double, kSpcAxes> setpoint_mm{};
  std::array<double, kSpcAxes> velocity_mm_s{};
  std::array<double, kSpcAxes> mass_factor{1, 1, 1, 1};  // M37 → machine::SimDrive::set_mass_factor
};

class TaskAxes {
 public:
  explicit TaskAxes(const SpcAxesConfig& cfg, std::array<double, kSpcAxes> start_mm = {});
  const SpcAxesConfig& config() const { return cfg_; }

  // rt-safe. Checks then starts (or takes over) one axis for `task` (0 = A, 1 = B).
  AxisCmd check(int task, int axis, double target_mm, bool relative) const;
  void command(int task, int axis, double target_mm, double v_mm_s, double a_mm_s2, double d_mm_s2,
               program::SpcProfile profile, bool relative);

  // rt-safe state.
  bool moving(int axis) const { return !movers_[axis].done(); }
  int owner(int axis) const { return moving(axis) ? owner_[axis] : -1; }
  double setpoint_mm(int axis) const { return out_.setpoint_mm[axis]; }
  double actual_mm(int axis) const { return actual_[axis]; }
  double target_mm(int axis) const { return movers_[axis].target_mm(); }
  // G61 condition 1..6 (S-3) for an axis.
  bool complete(int axis, int condition) const;
  bool needs_absolute(int axis) const { return needs_absolute_[axis]; }

  // rt-safe inputs.
  void set_actual_mm(int axis, double mm) { actual_[axis] = mm; actual_given_[axis] = true; }
  void set_mass_pct(int axis, int pct) { out_.mass_factor[axis] = (pct == 0 ? 100 : pct) / 100.0; }
  // STOP=0 (S-8, S-9): every axis holds where its setpoint is; relative moves are refused until an
  // absolute one.
  void stop_all();
  // rt-safe: one period for every axis; after the tasks' update.
  void step();

  const SpcAxesOutput& output() const { return out_; }

 private:
  SpcAxesConfig cfg_;
  std::array<AxisMover, kSpcAxes> movers_{};
  std::array<int, kSpcAxes> owner_{-1, -1, -1, -1};
  std::array<bool, kSpcAxes> needs_absolute_{};
  std::array<double, kSpcAxes> actual_{};
  std::array<bool, kSpcAxes> actual_given_{};
  std::array<std::array<double, 5>, kSpcAxes> settled_s_{};
  SpcAxesOutput out_;
};

}  // namespace softmc::control::spc
