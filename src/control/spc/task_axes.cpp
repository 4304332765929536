// The shared SPC axes: command checks, stepping, G61 windows.
#include "control/spc/task_axes.hpp"

#include <algorithm>
#include <cmath>

namespace softmc::control::spc {

SpcAxesConfig spc_axes_from(const machine::MachineConfig& m) {
  SpcAxesConfig c;
  c.period_s = m.period_s;
  for (std::size_t i = 0; i < kSpcAxes; ++i) {
    const auto* a = m.axis(core_axis(i));
    if (!a) continue;
    c.axis[i] = {true, a->max_vel_mm_s, a->max_acc_mm_s2, a->min_mm, a->max_mm, a->max_jerk_mm_s3};
  }
  const auto& s = m.spc;
  c.windows_mm = {s.g61_window2_mm, s.g61_window3_mm, s.g61_window4_mm, s.g61_window5_mm, s.g61_window6_mm};
  c.settle_s = s.g61_settle_s;
  c.sine_squared_s = s.g02_ramp_s;
  c.s_curve = s.g01_s_curve;
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
    movers_[i].configure(cfg.period_s, start_mm[i]);
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
  const auto& ac = cfg_.axis[axis];
  MoverLimits lim{v_mm_s, a_mm_s2, d_mm_s2, ac.j_max_mm_s3};
  MoverProfile kind = cfg_.s_curve ? MoverProfile::SCurve : MoverProfile::Trapezoid;
  if (profile == program::SpcProfile::SineSquared) {
    kind = MoverProfile::SineSquared;
    // G02 smoothing: a ramp of at least sine_squared_s caps the jerk at a·π/T (and the axis's own limit).
    const double a = std::min(a_mm_s2, d_mm_s2);
    const double j_smooth = cfg_.sine_squared_s > 0 ? a * M_PI / cfg_.sine_squared_s : 0.0;
    if (j_smooth > 0 && (lim.j_mm_s3 <= 0 || j_smooth < lim.j_mm_s3)) lim.j_mm_s3 = j_smooth;
    if (lim.j_mm_s3 <= 0) lim.j_mm_s3 = a * M_PI / 0.01;  // a takeover needs some jerk limit for Otg1
  }
  movers_[axis].retarget(target_mm, lim, kind);
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
