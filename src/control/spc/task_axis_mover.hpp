// One SPC axis's setpoint generator: online point-to-point motion, retargetable on the fly (S-2, S-3).
//
// Three kernels, chosen when a motion starts from rest; a takeover (a new target while moving, G25) keeps
// position and speed continuous:
//   Trapezoid  G00/G01: discrete-time online trapezoid, accelerate with a, brake with d (G08/G09 apart),
//              landing exactly on the target. A takeover retargets it (p, v continuous; a is a step anyway).
//   SCurve     G00/G01 with `g01_s_curve`: motion::Otg1, jerk-limited from (p, v, a); a takeover is an
//              Otg1 update, continuous in p, v and a. One acceleration limit: min(a, d).
//   Sine2      G02: motion::plan_sin2 from rest, sampled in closed form (sin² acceleration ramps, peak jerk
//              a·π/T). A takeover hands the state (p, v, a) to Otg1, jerk-limited at the G02 jerk, so the
//              axis stays smooth (no acceleration step) into its new target.
//
//   retarget ──► at rest? ── kernel by profile ──► step(): p, v (and a) every period
//                 └ moving ── Trapezoid: retarget │ SCurve: Otg1 update │ Sine2: Otg1 from (p, v, a)
#pragma once

#include <cstdint>

#include "motion/profile/otg1.hpp"
#include "motion/profile/sine2.hpp"

namespace softmc::control::spc {

struct MoverState {
  double p_mm = 0, v_mm_s = 0;
};

enum class MoverProfile : std::uint8_t { Trapezoid, SCurve, SineSquared };

struct MoverLimits {
  double v_mm_s = 0;
  double a_mm_s2 = 0;  // acceleration (G08)
  double d_mm_s2 = 0;  // deceleration (G09)
  double j_mm_s3 = 0;  // SCurve and SineSquared: jerk limit (> 0); Trapezoid: unused
};

class AxisMover {
 public:
  // Configuration: the period and the start position.
  void configure(double period_s, double start_mm);

  // rt-safe. New target and limits, taken over from the current state (see the header comment).
  void retarget(double target_mm, const MoverLimits& lim, MoverProfile profile);
  // rt-safe. Stop at once (STOP=0, no ramp): hold the current setpoint.
  void halt();
  // rt-safe. One period.
  MoverState step();
  bool done() const { return kernel_ == Kernel::Rest; }
  double target_mm() const { return target_; }
  MoverState state() const { return {p_, v_}; }
  double acceleration_mm_s2() const { return a_; }

 private:
  enum class Kernel : std::uint8_t { Rest, Trapezoid, Otg, Sine2 };
  double raw_step();
  void start_otg(const MoverLimits& lim);
  void arrive();

  double dt_ = 0.001;
  double target_ = 0;
  double v_max_ = 0, acc_ = 0, dec_ = 0;  // Trapezoid
  double p_ = 0, v_ = 0, a_ = 0;          // the output setpoint
  Kernel kernel_ = Kernel::Rest;
  motion::Otg1 otg_;
  motion::Sine2 sine2_{};
  double sine2_t_ = 0, sine2_from_ = 0, sine2_dir_ = 1;
};

}  // namespace softmc::control::spc
