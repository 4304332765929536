// The built-in cutting table, the machine's axis view (mask, limits) and validation of a configuration.
#include "machine/config.hpp"

#include <algorithm>

#include "machine/config_keys.hpp"

namespace softmc::machine {

const AxisConfig* MachineConfig::axis(std::size_t index) const {
  for (const auto& a : axes)
    if (a.index == index && a.enabled) return &a;
  return nullptr;
}

core::AxisMask MachineConfig::axis_mask() const {
  core::AxisMask m = 0;
  for (const auto& a : axes)
    if (a.enabled && a.index < core::kMaxAxes) m |= core::axis_bit(a.index);
  return m;
}

motion::MachineLimits MachineConfig::limits() const {
  motion::MachineLimits l;
  l.period_s = period_s;
  for (const auto& a : axes) {
    if (!a.enabled || a.index >= core::kMaxAxes) continue;  // absent axes keep v_max = 0
    auto& al = l.axis[a.index];
    al.v_max_mm_s = a.max_vel_mm_s;
    al.a_max_mm_s2 = a.max_acc_mm_s2;
    al.j_max_mm_s3 = a.max_jerk_mm_s3;
    al.min_mm = a.min_mm;
    al.max_mm = a.max_mm;
  }
  return l;
}

namespace {

// T-1: belt axis, 512 counts/rev encoder, 65 mm per motor revolution (0.127 mm per count).
// Speeds are what a light belt gantry carrying a torch does, far below the motor's 6000 rpm
// (which would be 6.5 m/s); docs/configuration.md explains each figure.
AxisConfig belt_axis(std::size_t index, double max_mm) {
  AxisConfig a;
  a.name = std::string(1, static_cast<char>(core::letter(index) - 'A' + 'a'));
  a.index = index;
  a.min_mm = 0;
  a.max_mm = max_mm;
  a.max_vel_mm_s = 250;      // 15 m/min rapid
  a.max_acc_mm_s2 = 2000;    // 0.2 g
  a.max_jerk_mm_s3 = 50000;  // full acceleration in 40 ms
  a.counts_per_rev = 512;
  a.mm_per_rev = 65;
  a.kv_1_s = 30;
  a.feedforward = 1.0;
  a.drive_tau_s = 0.005;
  a.ferror_limit_mm = 2.0;
  a.limit_switches = true;
  a.switch_overtravel_mm = 2.0;
  a.home_side = HomeSide::Negative;
  a.home_backoff_mm = 30.0;  // T-4
  return a;
}

}  // namespace

MachineConfig default_machine() {
  MachineConfig m;
  m.name = "cutting_table";
  m.period_s = 0.001;
  m.planner_queue = 256;
  m.tool_output = "torch";
  m.axes.push_back(belt_axis(core::index(core::Axis::X), 600));
  m.axes.push_back(belt_axis(core::index(core::Axis::Y), 400));

  // Torch height: the same motor and encoder on a 5 mm lead screw, homing upwards, away from the sheet.
  AxisConfig z = belt_axis(core::index(core::Axis::Z), 100);
  z.max_vel_mm_s = 50;
  z.max_acc_mm_s2 = 500;
  z.max_jerk_mm_s3 = 10000;
  z.mm_per_rev = 5;
  z.home_side = HomeSide::Positive;
  z.home_backoff_mm = 10;
  m.axes.push_back(z);
  return m;
}

void validate(const MachineConfig& cfg) {
  if (auto p = find_problem(cfg)) {
    const std::string where = cfg.name.empty() ? std::string("machine") : cfg.name;
    throw ConfigError(where + ": error: " + p->message);
  }
}

}  // namespace softmc::machine
