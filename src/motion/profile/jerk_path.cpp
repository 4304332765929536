// Piecewise-constant-jerk path: building and closed-form sampling.
#include "motion/profile/jerk_path.hpp"

#include <cassert>

namespace softmc::motion {

void JerkPath::reset(const ProfileState& start) {
  n_ = 0;
  t_end_ = 0;
  start_ = start;
  start_.j = 0;
  end_ = start_;
}

void JerkPath::push(double dur, double j) {
  if (!(dur > 0)) return;
  assert(n_ < kMaxPhases);
  if (n_ >= kMaxPhases) return;
  ProfileState x = end_;
  x.j = j;
  ph_[n_++] = {t_end_, x};
  end_ = advance(x, j, dur);
  end_.j = 0;
  t_end_ += dur;
}

void JerkPath::push_acc(double dur, double a) {
  end_.a = a;
  push(dur, 0);
}

// rt-safe
ProfileState JerkPath::at(double t) const {
  if (n_ == 0 || t >= t_end_) return end_;
  if (t <= 0) return ph_[0].x0;
  int i = n_ - 1;
  while (i > 0 && ph_[i].t0 > t) --i;
  const Phase& p = ph_[i];
  return advance(p.x0, p.x0.j, t - p.t0);
}

}  // namespace softmc::motion
