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
  // An axis not yet referenced (homing, T-4): the load stands at `physical_mm` while the position
  // reading starts at `reading_mm`; the encoder counts the motion from there.
  SimDrive(const AxisConfig& cfg, double reading_mm, double physical_mm);

  // rt-safe. One period: setpoint position and velocity in, new measured position out.
  double update(double setpoint_mm, double setpoint_vel_mm_s, double dt_s);

  double measured_mm() const { return measured_; }   // encoder position (quantised)
  double true_mm() const { return x_; }              // the load's real position (simulation only)
  // rt-safe. Homing set the reference: the position reading (and the last setpoint with it) moves
  // by shift_mm; the load does not move.
  void shift_reference(double shift_mm);
  // The reading's frame against the load's real one (simulation only): reading − true position,
  // the encoder's rounding aside. 0 for a drive referenced at construction; after homing, the
  // reference's error.
  double reference_offset_mm() const { return r0_ - x0_; }
  double velocity_mm_s() const { return v_; }
  double following_error_mm() const { return last_setpoint_ - measured_; }
  double last_setpoint() const { return last_setpoint_; }
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
  double x0_ = 0, r0_ = 0;  // reading = quantise(x_ − x0_) + r0_ (the encoder counts from x0_)
  double mass_factor_ = 1.0;
  bool enabled_ = true;
};

}  // namespace softmc::machine
