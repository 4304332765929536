// Online trapezoid with exact landing and an optional sine-squared velocity kernel (see the header).
#include "control/spc/task_axis_mover.hpp"

#include <algorithm>
#include <cmath>

namespace softmc::control::spc {

void AxisMover::configure(double period_s, double smoothing_s, double start_mm) {
  dt_ = period_s;
  const auto n = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(smoothing_s / period_s)));
  kernel_.assign(n, 0.0);
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double s = std::sin(M_PI * (static_cast<double>(i) + 0.5) / static_cast<double>(n));
    kernel_[i] = s * s;
    sum += kernel_[i];
  }
  for (auto& w : kernel_) w /= sum;
  history_.assign(n, 0.0);
  head_ = 0;
  nonzero_ = n;
  target_ = raw_p_ = p_ = start_mm;
  raw_v_ = v_ = 0;
  done_ = true;
}

void AxisMover::retarget(double target_mm, double v_max_mm_s, double a_max_mm_s2, double d_max_mm_s2, bool smooth) {
  target_ = target_mm;
  v_max_ = v_max_mm_s;
  a_ = a_max_mm_s2;
  d_ = d_max_mm_s2;
  if (done_) smooth_ = smooth;  // at rest: the history is all zero, the kernel may change
  done_ = false;
}

void AxisMover::halt() {
  // The raw generator jumps to the output setpoint with zero speed: the setpoint stops this period.
  std::fill(history_.begin(), history_.end(), 0.0);
  nonzero_ = history_.size();
  raw_p_ = target_ = p_;
  raw_v_ = v_ = 0;
  done_ = true;
}

// rt-safe. Discrete braking: the largest speed from which braking by d·dt per period still stops
// within the remaining distance e (Σ of the braking speeds · dt = e), capped to land exactly.
double AxisMover::raw_step() {
  const double e = target_ - raw_p_;
  const double ae = std::fabs(e);
  const double dir = e > 0 ? 1.0 : e < 0 ? -1.0 : 0.0;
  const double dd = d_ * dt_;
  const double v_brake = dd * (std::sqrt(0.25 + 2.0 * ae / (dd * dt_)) - 0.5);
  const double v_des = dir * std::min({v_max_, v_brake, ae / dt_});
  const double dv = v_des - raw_v_;
  const bool speeding_up = raw_v_ * dv > 0 || (raw_v_ == 0);
  const double lim = (speeding_up ? a_ : d_) * dt_;
  raw_v_ += std::clamp(dv, -lim, lim);
  if (dir != 0 && raw_v_ * dir > 0 && std::fabs(raw_v_) * dt_ >= ae - 1e-12) {
    // Landing: the remaining distance is at most one period's travel; cover it exactly. The speed
    // then drops to zero in the next period (by at most about one braking step).
    raw_v_ = e / dt_;
    raw_p_ = target_;
  } else if (dir == 0) {
    raw_v_ = 0;  // at the target after a landing: stop (a step of at most ~1.5 braking steps)
  } else {
    raw_p_ += raw_v_ * dt_;
  }
  return raw_v_;
}

MoverState AxisMover::step() {
  if (done_) return {p_, v_};
  const double vr = raw_step();
  if (!smooth_) {
    v_ = vr;
    p_ = raw_p_;
  } else {
    const std::size_t n = history_.size();
    history_[head_] = vr;
    double v = 0;
    for (std::size_t i = 0; i < n; ++i) v += kernel_[i] * history_[(head_ + n - i) % n];
    head_ = (head_ + 1) % n;
    nonzero_ = vr != 0 ? 0 : nonzero_ + 1;
    v_ = v;
    p_ += v * dt_;
  }
  const bool raw_done = raw_p_ == target_ && raw_v_ == 0;
  if (raw_done && (!smooth_ || nonzero_ >= history_.size())) {
    p_ = target_;  // the kernel has drained: remove the rounding residue of the sum
    v_ = 0;
    done_ = true;
  }
  return {p_, v_};
}

}  // namespace softmc::control::spc
