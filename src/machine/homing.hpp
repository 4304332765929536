// Homing (cutting_table.md T-4, plc_interface.md P-9): one axis's reference cycle on its limit switch.
//
//   (Clear: off the switch first when the axis stands on it)
//   Search ──switch closes──► Brake ──at rest──► (reference set) ──► BackOff ──at the back-off point──► Done
//   towards home_side at        the position          the latched point becomes      home_backoff_mm away
//   home_vel_mm_s               is latched            the switch's coordinate        from the switch
//
// The switch's coordinate is where the configuration puts it: switch_overtravel_mm beyond the end of
// travel on the home side (min_mm − overtravel, or max_mm + overtravel). Every move is an Otg1 at the
// axis's speed, acceleration and jerk limits (the search at home_vel_mm_s), so homing keeps them
// like any other motion.
#pragma once

#include <cstdint>

#include "machine/config.hpp"
#include "motion/profile/otg1.hpp"

namespace softmc::machine {

enum class HomingPhase : std::uint8_t { Idle, Clear, Search, Brake, BackOff, Done, Failed };
const char* to_string(HomingPhase p);

// The search speed: home_vel_mm_s, or a tenth of max_vel_mm_s where it is 0.
double home_speed_mm_s(const AxisConfig& a);
// The coordinate homing gives the switch's point, and where the axis ends (the back-off point).
double home_switch_mm(const AxisConfig& a);
double homed_mm(const AxisConfig& a);

class AxisHoming {
 public:
  explicit AxisHoming(const AxisConfig& a) : cfg_(a) {}

  // Not rt: begins the cycle from the commanded position `cmd_mm`, at rest. An axis without limit
  // switches cannot home: Failed at once, with error().
  void start(double cmd_mm);

  // One cycle's command to the drive, and the shift of the axis's coordinates made in this cycle
  // (≠ 0 once, when the reference is set: the drive's position reading and everything in the
  // controller's coordinates move by it; the command is already in the new coordinates).
  struct Command {
    double pos_mm = 0, vel_mm_s = 0, acc_mm_s2 = 0;
    double shift_mm = 0;
  };
  // rt-safe. `switch_closed`: the home-side limit switch now; `measured_mm`: the drive's position
  // reading now (before any shift).
  Command step(bool switch_closed, double measured_mm, double dt_s);

  HomingPhase phase() const { return phase_; }
  bool done() const { return phase_ == HomingPhase::Done; }
  bool failed() const { return phase_ == HomingPhase::Failed; }
  const char* error() const { return error_; }
  double latched_mm() const { return latched_; }  // the reading when the switch closed (old coordinates)
  double shift_mm() const { return shift_; }       // the reference shift applied

 private:
  motion::OtgLimits limits(double v) const;

  AxisConfig cfg_;
  motion::Otg1 otg_;
  HomingPhase phase_ = HomingPhase::Idle;
  double start_ = 0, latched_ = 0, shift_ = 0;
  const char* error_ = "";
};

}  // namespace softmc::machine
