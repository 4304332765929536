// The start-up sequence of a simulated machine (cutting_table.md T-4/T-5, plc_interface.md P-9):
// every axis with limit switches homes on its home-side switch, the simulated drives keep what the
// homing did (the load's position, the reference it set), and a program can then run on them.
#pragma once

#include <array>
#include <memory>
#include <string>

#include "core/axes.hpp"
#include "machine/config.hpp"
#include "machine/sim_drive.hpp"

namespace softmc::app {

struct AxisHomingResult {
  bool homed = false;
  double power_up_mm = 0;   // where the load stood (simulation only: the controller did not know)
  double switch_mm = 0;     // the coordinate homing gave the switch's point (home_switch_mm)
  double position_mm = 0;   // the commanded position at the end (the back-off point)
  double true_mm = 0;       // where the load really is then
  double reference_error_mm = 0;  // reading − true position at the end: the reference's error
  double time_s = 0;        // from the start of the sequence to this axis's end
  double overshoot_mm = 0;  // how far the load went past the switch's point while braking (simulation only)
};

struct HomingRunResult {
  bool ok = false;
  std::string result = "ok";  // or what failed ("homing X: ...")
  double time_s = 0;          // the whole sequence, until every drive is in position
  std::array<AxisHomingResult, core::kMaxAxes> axis{};
  // The drives, as the sequence leaves them: a program's simulation runs on these.
  std::array<std::unique_ptr<machine::SimDrive>, core::kMaxAxes> drives{};
  // Where each axis is commanded at the end (the back-off point, or 0 for an axis without switches):
  // the position a program starts from.
  core::Vec position{};
};

// Axes homing in the positive direction (a torch's Z: up, away from the work) go first, then all
// the others together. Axes without limit switches are not moved; their reading starts at 0 and
// they are referenced as they stand. `power_up`: the loads' positions at power-up, unknown to the
// controller, whose readings start at 0.
HomingRunResult run_homing(const machine::MachineConfig& cfg, const core::Vec& power_up, double max_time_s = 600);

// The default power-up positions: the middle of each axis's travel.
core::Vec mid_travel(const machine::MachineConfig& cfg);

}  // namespace softmc::app
