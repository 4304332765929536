// Piecewise-constant-jerk path: building and closed-form sampling.
#include "motion/profile/jerk_path.hpp"

#include <cassert>
#include <cmath>

namespace softmc::motion {

void JerkPath::reset(const ProfileState& start) {
  n_ = 0;
  t_end_ = 0;
  start_ = start;
  start_.j = 0;
  end_ = start_;
  stretch_ = 1;
}

void JerkPath::snap_end(const ProfileState& exact) {
  const double own = end_.s - start_.s, want = exact.s - start_.s;
  const double k = own != 0 ? want / own : 1.0;
  stretch_ = std::abs(k - 1) <= 1e-9 ? k : 1.0;
  end_ = exact;
  end_.j = 0;
}

void JerkPath::push(double dur, double j) {
  if (!(dur > 0)) return;
  assert(n_ < kMaxPhases);
  assert(stretch_ == 1);  // snap_end comes last
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
  ProfileState x = advance(p.x0, p.x0.j, t - p.t0);
  if (stretch_ != 1) {
    x.s = start_.s + (x.s - start_.s) * stretch_;
    x.v *= stretch_;
    x.a *= stretch_;
    x.j *= stretch_;
  }
  return x;
}

}  // namespace softmc::motion
