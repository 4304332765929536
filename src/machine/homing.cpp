// Homing (T-4, P-9): the reference cycle of one axis on its home-side limit switch.
#include "machine/homing.hpp"

#include <algorithm>
#include <cmath>

namespace softmc::machine {

const char* to_string(HomingPhase p) {
  switch (p) {
    case HomingPhase::Idle: return "idle";
    case HomingPhase::Clear: return "clear";
    case HomingPhase::Search: return "search";
    case HomingPhase::Brake: return "brake";
    case HomingPhase::BackOff: return "back-off";
    case HomingPhase::Done: return "done";
    case HomingPhase::Failed: return "failed";
  }
  return "?";
}

double home_speed_mm_s(const AxisConfig& a) {
  return a.home_vel_mm_s > 0 ? std::min(a.home_vel_mm_s, a.max_vel_mm_s) : a.max_vel_mm_s / 10;
}

double home_switch_mm(const AxisConfig& a) {
  return a.home_side == HomeSide::Negative ? a.min_mm - a.switch_overtravel_mm : a.max_mm + a.switch_overtravel_mm;
}

double homed_mm(const AxisConfig& a) {
  return a.home_side == HomeSide::Negative ? home_switch_mm(a) + a.home_backoff_mm
                                           : home_switch_mm(a) - a.home_backoff_mm;
}

motion::OtgLimits AxisHoming::limits(double v) const { return {v, cfg_.max_acc_mm_s2, cfg_.max_jerk_mm_s3}; }

void AxisHoming::start(double cmd_mm) {
  otg_.reset({cmd_mm, 0, 0, 0});
  start_ = cmd_mm;
  latched_ = shift_ = 0;
  error_ = "";
  if (!cfg_.limit_switches) {
    phase_ = HomingPhase::Failed;
    error_ = "the axis has no limit switch to home on (limit_switches = false)";
    return;
  }
  phase_ = HomingPhase::Search;  // the first step() turns to Clear when the switch is already closed
  const double dir = cfg_.home_side == HomeSide::Negative ? -1.0 : 1.0;
  otg_.update_velocity(dir * home_speed_mm_s(cfg_), limits(home_speed_mm_s(cfg_)));
}

// rt-safe
AxisHoming::Command AxisHoming::step(bool switch_closed, double measured_mm, double dt_s) {
  Command c;
  const double dir = cfg_.home_side == HomeSide::Negative ? -1.0 : 1.0;
  const double v_home = home_speed_mm_s(cfg_);
  switch (phase_) {
    case HomingPhase::Search:
      if (switch_closed && otg_.state().v * dir <= 0) {
        // Standing on the switch: off it first, away from it, then the search again.
        phase_ = HomingPhase::Clear;
        otg_.update_velocity(-dir * v_home, limits(v_home));
      } else if (switch_closed) {
        // The reading of this cycle is the switch's point, within one cycle of travel at the search
        // speed and the encoder's count.
        latched_ = measured_mm;
        phase_ = HomingPhase::Brake;
        otg_.stop(limits(v_home));
      } else if (std::abs(otg_.state().s - start_) >
                 (cfg_.max_mm - cfg_.min_mm) + 2 * cfg_.switch_overtravel_mm + 2 * cfg_.home_backoff_mm) {
        phase_ = HomingPhase::Failed;
        error_ = "no home switch found within the whole travel";
        otg_.stop(limits(v_home));
      }
      break;
    case HomingPhase::Clear:
      if (!switch_closed) {
        phase_ = HomingPhase::Search;
        otg_.update_velocity(dir * v_home, limits(v_home));
      }
      break;
    case HomingPhase::Brake:
      if (otg_.finished()) {
        // At rest: the latched point becomes the switch's coordinate, then back off from it.
        shift_ = home_switch_mm(cfg_) - latched_;
        c.shift_mm = shift_;
        otg_.reset({otg_.state().s + shift_, 0, 0, 0});
        otg_.update(homed_mm(cfg_), limits(cfg_.max_vel_mm_s));
        phase_ = HomingPhase::BackOff;
      }
      break;
    case HomingPhase::BackOff:
      if (otg_.finished()) phase_ = HomingPhase::Done;
      break;
    default:
      break;
  }
  if (phase_ != HomingPhase::Idle && phase_ != HomingPhase::Done) otg_.step(dt_s);
  const auto& x = otg_.state();
  c.pos_mm = x.s;
  c.vel_mm_s = x.v;
  c.acc_mm_s2 = x.a;
  return c;
}

}  // namespace softmc::machine
