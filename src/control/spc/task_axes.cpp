// The shared SPC axes: command checks, stepping, G61 windows.
#include "control/spc/task_axes.hpp"

#include <cmath>

namespace softmc::control::spc {

SpcAxesConfig spc_axes_from(const machine::MachineConfig& m) {
  SpcAxesConfig c;
  c.period_s = m.period_s;
  for (std::size_t i = 0; i < kSpcAxes; ++i) {
    const auto* a = m.axis(core_axis(i));
    if (!a) continue;
    c.axis[i] = {true, a->max_vel_mm_s, a->max_acc_mm_s2, a->min_mm, a->max_mm};
  }
  return c;
}

const char* to_string(AxisCmd r) {
  switch (r) {
    case AxisCmd::Ok: return "ok";
    case AxisCmd::NotPresent: return "axis not configured";
    case AxisCmd::OwnedByOtherTask: return "axis is moving under the other task";
    case AxisCmd::NeedsAbsolute: return "relative move refused after a stop: give the axis an absolute one";
    case AxisCmd::OutOfTravel: return "target outside the axis travel";
  }
  return "?";
}

TaskAxes::TaskAxes(const SpcAxesConfig& cfg, std::array<double, kSpcAxes> start_mm) : cfg_(cfg) {
  for (std::size_t i = 0; i < kSpcAxes; ++i) {
    movers_[i].configure(cfg.period_s, cfg.sine_squared_s, start_mm[i]);
    out_.setpoint_mm[i] = actual_[i] = start_mm[i];
  }
}

AxisCmd TaskAxes::check(int task, int axis, double target_mm, bool relative) const {
  const auto& a = cfg_.axis[axis];
  if (!a.present) return AxisCmd::NotPresent;
  if (moving(axis) && owner_[axis] != task) return AxisCmd::OwnedByOtherTask;
  if (relative && needs_absolute_[axis]) return AxisCmd::NeedsAbsolute;
  if (target_mm < a.min_mm - 1e-9 || target_mm > a.max_mm + 1e-9) return AxisCmd::OutOfTravel;
  return AxisCmd::Ok;
}

void TaskAxes::command(int task, int axis, double target_mm, double v_mm_s, double a_mm_s2, double d_mm_s2,
                       program::SpcProfile profile, bool relative) {
  owner_[axis] = task;
  if (!relative) needs_absolute_[axis] = false;
  movers_[axis].retarget(target_mm, v_mm_s, a_mm_s2, d_mm_s2, profile == program::SpcProfile::SineSquared);
  settled_s_[axis] = {};
}

void TaskAxes::stop_all() {
  for (std::size_t i = 0; i < kSpcAxes; ++i) {
    movers_[i].halt();
    needs_absolute_[i] = true;
    out_.velocity_mm_s[i] = 0;
  }
}

bool TaskAxes::complete(int axis, int condition) const {
  if (moving(axis)) return false;
  if (condition <= 1) return true;
  return settled_s_[axis][condition - 2] >= cfg_.settle_s - 1e-12;
}

void TaskAxes::step() {
  for (std::size_t i = 0; i < kSpcAxes; ++i) {
    const MoverState s = movers_[i].step();
    out_.setpoint_mm[i] = s.p_mm;
    out_.velocity_mm_s[i] = s.v_mm_s;
    if (!actual_given_[i]) actual_[i] = s.p_mm;  // no drive feedback wired: the setpoint is the position
    if (movers_[i].done()) {
      const double err = std::fabs(actual_[i] - movers_[i].target_mm());
      for (std::size_t k = 0; k < cfg_.windows_mm.size(); ++k)
        settled_s_[i][k] = err <= cfg_.windows_mm[k] ? settled_s_[i][k] + cfg_.period_s : 0.0;
    }
  }
}

}  // namespace softmc::control::spc
