// Simulated drive: exact discretisation of a first-order motor under a P position loop with feed-forward.
#include "machine/sim_drive.hpp"

#include <cmath>

namespace softmc::machine {

SimDrive::SimDrive(const AxisConfig& cfg, double start_mm) : cfg_(cfg), x_(start_mm) {
  measured_ = quantise(x_);
  last_setpoint_ = start_mm;
}

SimDrive::SimDrive(const AxisConfig& cfg, double reading_mm, double physical_mm)
    : cfg_(cfg), x_(physical_mm), x0_(physical_mm), r0_(reading_mm) {
  measured_ = reading_mm;
  last_setpoint_ = reading_mm;
}

// rt-safe
void SimDrive::shift_reference(double shift_mm) {
  r0_ += shift_mm;
  measured_ += shift_mm;
  last_setpoint_ += shift_mm;
}

double SimDrive::quantise(double x) const {
  const double q = cfg_.mm_per_count();
  return std::round(x / q) * q;
}

// rt-safe
double SimDrive::update(double setpoint_mm, double setpoint_vel_mm_s, double dt_s) {
  last_setpoint_ = setpoint_mm;
  // The loop closes on the measured (quantised) position, as a real drive does on its encoder.
  const double v_cmd =
      enabled_ ? cfg_.feedforward * setpoint_vel_mm_s + cfg_.kv_1_s * (setpoint_mm - measured_) : 0.0;
  // v' = (v_cmd − v)/τ integrated exactly over the period, with v_cmd held (zero-order hold).
  const double tau = cfg_.drive_tau_s * mass_factor_;
  const double e = std::exp(-dt_s / tau);
  const double dv = v_ - v_cmd;
  x_ += v_cmd * dt_s + dv * tau * (1.0 - e);
  v_ = v_cmd + dv * e;
  measured_ = quantise(x_ - x0_) + r0_;
  return measured_;
}

bool SimDrive::limit_negative() const {
  return cfg_.limit_switches && x_ <= cfg_.min_mm - cfg_.switch_overtravel_mm;
}
bool SimDrive::limit_positive() const {
  return cfg_.limit_switches && x_ >= cfg_.max_mm + cfg_.switch_overtravel_mm;
}

}  // namespace softmc::machine
