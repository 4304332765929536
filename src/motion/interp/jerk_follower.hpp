// One-cycle moves of the jerk-limited path speed: the velocity ramp and the position-mode stop
// (docs/planner.md, "Jerk"; which one runs is decided by interp/jerk_guard).
//
// A brake that must end at rest (an exact stop, the end of the window) is planned in position mode,
// so the path stops exactly on the point instead of creeping up to it.
#pragma once

#include <cstdint>

#include "motion/profile/jerk_path.hpp"
#include "motion/profile/otg1.hpp"
#include "motion/profile/profile_state.hpp"

namespace softmc::motion {

// rt-safe. The velocity-mode ramp from x towards speed vt (first bringing |a| within a_max), held
// there; returns the state dt later, with x.s as the origin of s.
ProfileState ramp_step(const ProfileState& x, double vt, double a_max, double j_max, double dt);

// The position-mode stop, kept from cycle to cycle. The rest of a time-optimal stop is the
// time-optimal stop from where it has got to, so while the follower takes this stop cycle after
// cycle towards the same point with the same limits, the plan is sampled on instead of solved again
// (Otg1's peak-speed search: about 9 000 instructions a call). Any other step, point or limit solves
// it anew.
class StopPlan {
 public:
  // rt-safe. The time-optimal jerk-limited motion from x to rest at s = target (x.s as origin), no
  // faster than v_max; returns the state dt later, exact at the target once reached. From the kept
  // plan when x is where it left the path.
  ProfileState step(const ProfileState& x, double target, double v_max, double a_max, double j_max, double dt);
  // rt-safe. The state t (0 ≤ t ≤ dt) into the step the last step() returned, from its start
  // state (s from there): the same plan, cut at t.
  ProfileState last_at(double t) const;
  // rt-safe. Whether the follower took the last step() as its cycle (else the plan is dropped). Call
  // once every jerk cycle, with false when step() was not asked.
  void taken(bool yes);
  std::uint64_t solves() const { return solves_; }  // plans solved since construction
  std::uint64_t reuses() const { return reuses_; }  // steps taken from a kept plan

 private:
  Otg1 otg_;
  double v_max_ = 0, a_max_ = 0, j_max_ = 0, target_ = 0;  // the plan's limits and point (from its origin)
  double t_ = 0, t_next_ = 0;  // time of the present state in the plan; of the state step() returned
  // The last step(): its start in the plan (time, s), or its start state and limits where the stop
  // could not be solved and the ramp to rest was taken instead.
  double t0_ = 0, s0_ = 0;
  ProfileState x0_{};
  double a0_ = 0, j0_ = 0;
  bool solved_ = false;
  bool kept_ = false, asked_ = false;
  std::uint64_t solves_ = 0, reuses_ = 0;
};

}  // namespace softmc::motion
