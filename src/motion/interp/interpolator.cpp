// Sampling of timed segments.
#include "motion/interp/interpolator.hpp"

namespace softmc::motion {

// rt-safe
const Setpoint& Interpolator::step(double dt) {
  if (queue_.empty()) {
    sp_.vel = Vec{};
    sp_.acc = Vec{};
    sp_.path_v = 0;
    sp_.moving = false;
    t_in_segment_ = 0;
    return sp_;
  }
  t_in_segment_ += dt;
  // Drop finished segments; their leftover time goes into the next one.
  while (!queue_.empty() && t_in_segment_ >= queue_.front().profile.duration()) {
    const TimedSegment& done = queue_.front();
    sp_.pos = done.geom.end;
    t_in_segment_ -= done.profile.duration();
    sp_.tag = done.tag;
    queue_.pop();
  }
  if (queue_.empty()) {
    // Ended exactly at the last target: stand still there.
    sp_.vel = Vec{};
    sp_.acc = Vec{};
    sp_.path_v = 0;
    sp_.moving = false;
    t_in_segment_ = 0;
    return sp_;
  }
  const TimedSegment& seg = queue_.front();
  const ProfileState st = seg.profile.at(t_in_segment_);
  sp_.pos = seg.geom.point(st.s);
  const Vec t = seg.geom.tangent(st.s);
  sp_.vel = t * st.v;
  sp_.acc = t * st.a + seg.geom.curvature(st.s) * (st.v * st.v);
  sp_.path_v = st.v;
  sp_.moving = true;
  sp_.rapid = seg.rapid;
  sp_.tag = seg.tag;
  return sp_;
}

}  // namespace softmc::motion
