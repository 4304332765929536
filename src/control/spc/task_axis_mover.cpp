// SPC axis setpoint generator: the trapezoid, Otg1 (S-curve, takeovers) and sine-squared kernels.
#include "control/spc/task_axis_mover.hpp"

#include <algorithm>
#include <cmath>

namespace softmc::control::spc {

void AxisMover::configure(double period_s, double start_mm) {
  dt_ = period_s;
  target_ = p_ = start_mm;
  v_ = a_ = 0;
  kernel_ = Kernel::Rest;
  otg_.reset({start_mm, 0, 0, 0});
}

void AxisMover::start_otg(const MoverLimits& lim) {
  otg_.reset({p_, v_, a_, 0});
  const motion::OtgLimits ol{lim.v_mm_s, std::min(lim.a_mm_s2, lim.d_mm_s2), lim.j_mm_s3};
  if (otg_.update(target_, ol) == motion::OtgResult::ErrorInvalidInput) {
    kernel_ = Kernel::Rest;  // unreachable: the task validated the limits; hold rather than run wild
    return;
  }
  kernel_ = Kernel::Otg;
}

// rt-safe
void AxisMover::retarget(double target_mm, const MoverLimits& lim, MoverProfile profile) {
  target_ = target_mm;
  v_max_ = lim.v_mm_s;
  acc_ = lim.a_mm_s2;
  dec_ = lim.d_mm_s2;
  switch (kernel_) {
    case Kernel::Trapezoid: return;  // the raw generator takes the new target from its (p, v)
    case Kernel::Otg:
    case Kernel::Sine2: return start_otg(lim);  // p, v, a continuous
    case Kernel::Rest: break;
  }
  a_ = 0;
  v_ = 0;
  if (profile == MoverProfile::SineSquared) {
    const double len = std::fabs(target_mm - p_);
    const auto plan = motion::plan_sin2(len, 0, 0, lim.v_mm_s, std::min(lim.a_mm_s2, lim.d_mm_s2), lim.j_mm_s3);
    if (plan) {
      sine2_ = *plan;
      sine2_t_ = 0;
      sine2_from_ = p_;
      sine2_dir_ = target_mm >= p_ ? 1.0 : -1.0;
      kernel_ = Kernel::Sine2;
      return;
    }
  } else if (profile == MoverProfile::SCurve && lim.j_mm_s3 > 0) {
    return start_otg(lim);
  }
  kernel_ = Kernel::Trapezoid;
}

// rt-safe
void AxisMover::halt() {
  target_ = p_;
  v_ = a_ = 0;
  kernel_ = Kernel::Rest;
}

void AxisMover::arrive() {
  p_ = target_;  // remove the rounding residue of the last period
  v_ = a_ = 0;
  kernel_ = Kernel::Rest;
}

// rt-safe. Discrete braking: the largest speed from which braking by d·dt per period still stops
// within the remaining distance e (Σ of the braking speeds · dt = e), capped to land exactly.
double AxisMover::raw_step() {
  const double e = target_ - p_;
  const double ae = std::fabs(e);
  const double dir = e > 0 ? 1.0 : e < 0 ? -1.0 : 0.0;
  const double dd = dec_ * dt_;
  const double v_brake = dd * (std::sqrt(0.25 + 2.0 * ae / (dd * dt_)) - 0.5);
  const double v_des = dir * std::min({v_max_, v_brake, ae / dt_});
  const double dv = v_des - v_;
  const bool speeding_up = v_ * dv > 0 || (v_ == 0);
  const double lim = (speeding_up ? acc_ : dec_) * dt_;
  const double v_prev = v_;
  v_ += std::clamp(dv, -lim, lim);
  if (dir != 0 && v_ * dir > 0 && std::fabs(v_) * dt_ >= ae - 1e-12) {
    // Landing: the remaining distance is at most one period's travel; cover it exactly. The speed
    // then drops to zero in the next period (by at most about one braking step).
    v_ = e / dt_;
    p_ = target_;
  } else if (dir == 0) {
    v_ = 0;  // at the target after a landing: stop (a step of at most ~1.5 braking steps)
  } else {
    p_ += v_ * dt_;
  }
  a_ = (v_ - v_prev) / dt_;
  return v_;
}

// rt-safe
MoverState AxisMover::step() {
  switch (kernel_) {
    case Kernel::Rest: break;
    case Kernel::Trapezoid:
      raw_step();
      if (p_ == target_ && v_ == 0) arrive();
      break;
    case Kernel::Otg: {
      const auto r = otg_.step(dt_);
      const auto& x = otg_.state();
      p_ = x.s;
      v_ = x.v;
      a_ = x.a;
      if (r != motion::OtgResult::Working) arrive();
      break;
    }
    case Kernel::Sine2: {
      sine2_t_ += dt_;
      const auto x = sine2_.at(sine2_t_);
      p_ = sine2_from_ + sine2_dir_ * x.s;
      v_ = sine2_dir_ * x.v;
      a_ = sine2_dir_ * x.a;
      if (sine2_t_ >= sine2_.duration()) arrive();
      break;
    }
  }
  return {p_, v_};
}

}  // namespace softmc::control::spc
