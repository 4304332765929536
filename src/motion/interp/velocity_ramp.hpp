// The path-speed plan over the rest of one block, from the actual state: ramp, cruise, ramp.
//
//   v ^ v0                          v0 above the cruise speed (override lowered, hold):
//     |   \___________              the first ramp decelerates; cruise at 0 = a hold on the path
//     |  /  vc        \__ v1
//     |_/_________________\___> t   (t1)      (tc)      (t3)
//
// Built again whenever an input changes (exit limit, override, hold, stop), always from the state the
// interpolator has just sampled, so every change acts in the cycle it is seen with the ramps kept.
#pragma once

#include "motion/profile/trapezoid.hpp"

namespace softmc::motion {

struct VelocityRamp {
  double s0 = 0, dist = 0;  // starts at s0, ends at s0 + dist (the block's end)
  double v0 = 0;
  double a1 = 0, t1 = 0, d1 = 0;  // first ramp
  double vc = 0, tc = 0, dc = 0;  // cruise (tc infinite: holding at rest, vc = 0)
  double a3 = 0, t3 = 0;          // last ramp
  double v1 = 0;                  // speed at the block's end

  double duration() const { return t1 + tc + t3; }
  // rt-safe: state at time t after the plan's start; at the end for t ≥ duration().
  ProfileState at(double t) const;
};

// rt-safe. Plans `dist` mm from speed v0 with acceleration magnitude `acc`: cruise at `vc` (which may
// lie below v0), end at `v1_want` if reachable, never above v1_max (the hard exit limit). Where the
// exit cannot be brought down to v1_want within the distance, the plan brakes all the way.
VelocityRamp plan_ramp(double dist, double v0, double vc, double v1_want, double v1_max, double acc);

}  // namespace softmc::motion
