// One SPC axis's setpoint generator: online point-to-point motion, retargetable on the fly (S-2, S-3).
//
// SWITCH TO Otg1: the profile engineer's online jerk-limited generator (src/motion/profile/otg1)
// replaces the body of this class when it lands; the interface below is what the task needs.
//
// Until then: a discrete-time online trapezoid (accelerate with a, brake with d, exact landing)
// produces a raw velocity; G02 passes it through a sine-squared FIR kernel of length T, which turns
// each acceleration step into a sin²-jerk ramp (jerk ∝ sin², peak jerk 2·a/T) and keeps the total
// displacement (weights sum to 1). Retargeting changes only the raw generator, so position and
// velocity stay continuous whatever the new target.
//
//   raw trapezoid v_raw ──► [ FIR sin² (G02) | identity ] ──► v ──► ∫ ──► setpoint p
#pragma once

#include <cstdint>
#include <vector>

namespace softmc::control::spc {

struct MoverState {
  double p_mm = 0, v_mm_s = 0;
};

class AxisMover {
 public:
  // Configuration (allocates): the period and the longest smoothing kernel.
  void configure(double period_s, double smoothing_s, double start_mm);

  // rt-safe. New target and limits, taken over from the current state; `smooth` selects the sin²
  // kernel (G02). The kernel changes only while the axis is at rest (no jump on a takeover).
  void retarget(double target_mm, double v_max_mm_s, double a_max_mm_s2, double d_max_mm_s2, bool smooth);
  // rt-safe. Stop at once (STOP=0, no ramp): hold the current setpoint.
  void halt();
  // rt-safe. One period.
  MoverState step();
  bool done() const { return done_; }
  double target_mm() const { return target_; }
  MoverState state() const { return {p_, v_}; }

 private:
  double raw_step();

  double dt_ = 0.001;
  double target_ = 0;
  double v_max_ = 0, a_ = 0, d_ = 0;
  double raw_p_ = 0, raw_v_ = 0;  // the unsmoothed generator
  double p_ = 0, v_ = 0;          // the output setpoint
  bool done_ = true;
  bool smooth_ = false;
  std::vector<double> kernel_;    // sin² weights, sum 1
  std::vector<double> history_;   // raw velocities, ring
  std::size_t head_ = 0;
  std::size_t nonzero_ = 0;       // samples since the raw velocity was last non-zero (drain detection)
};

}  // namespace softmc::control::spc
