// The interpolator: samples the planner's queue of timed segments once per cycle into setpoints.
#pragma once

#include <cstdint>

#include "core/ring.hpp"
#include "motion/planner/planner.hpp"

namespace softmc::motion {

struct Setpoint {
  Vec pos;           // mm, per axis
  Vec vel;           // mm/s, per axis
  Vec acc;           // mm/s², per axis
  double path_v = 0;  // mm/s along the path
  bool moving = false;   // a segment is being executed
  bool rapid = false;
  std::uint32_t tag = 0;  // tag of the segment the setpoint lies on
};

class Interpolator {
 public:
  Interpolator(core::Ring<TimedSegment>& queue, const Vec& start) : queue_(queue) { sp_.pos = start; }

  // rt-safe. Advances time by dt and returns the new setpoint. Time left over at the end of a
  // segment carries into the next one, so segment boundaries are not rounded to the cycle.
  const Setpoint& step(double dt);

  const Setpoint& setpoint() const { return sp_; }
  // True while there is nothing left to move.
  bool idle() const { return queue_.empty(); }

 private:
  core::Ring<TimedSegment>& queue_;
  double t_in_segment_ = 0;
  Setpoint sp_;
};

}  // namespace softmc::motion
