// Simulated drive: position loop with velocity feed-forward, first-order motor, quantised encoder.
//
//  setpoint x* ──►(+)── Kv ──►(+)──► v_cmd ──► [ 1/(1+τs) ] ── v ──► ∫ ──► x ──► quantise ──► x_meas
//                 ▲(-)        ▲ ff·v*                                                  │
//                 └────────────────────────────────────────────────────────────────────┘
// The loop runs at the interpolation period; the motor is integrated exactly over the period.
#pragma once

#include "machine/config.hpp"

namespace softmc::machine {

class SimDrive {
 public:
  explicit SimDrive(const AxisConfig& cfg, double start_mm = 0);

  // rt-safe. One period: setpoint position and velocity in, new measured position out.
  double update(double setpoint_mm, double setpoint_vel_mm_s, double dt_s);

  double measured_mm() const { return measured_; }   // encoder position (quantised)
  double true_mm() const { return x_; }              // the load's real position (simulation only)
  double velocity_mm_s() const { return v_; }
  double following_error_mm() const { return last_setpoint_ - measured_; }
  // Scales the moving mass (SPC M37): the time constant grows with the mass.
  void set_mass_factor(double k) { mass_factor_ = k; }
  // Enable/disable the position loop (disabled: the motor coasts to rest, no torque).
  void set_enabled(bool on) { enabled_ = on; }
  // Simulated limit switches: closed when the load is at or beyond the switch, which sits
  // `switch_overtravel_mm` beyond each end of the travel.
  bool limit_negative() const;
  bool limit_positive() const;

 private:
  double quantise(double x) const;

  AxisConfig cfg_;
  double x_ = 0, v_ = 0, measured_ = 0, last_setpoint_ = 0;
  double mass_factor_ = 1.0;
  bool enabled_ = true;
};

}  // namespace softmc::machine
