// A 1-D trajectory made of phases of constant jerk, sampled in closed form (the common carrier of S-curves and OTG).
//
//   a ^     ___
//     |   /     \          each phase: start time, start state (p, v, a) and a constant jerk j;
//     |__/       \    __   a phase may also start with a jump in a (jerk-unlimited profiles)
//     |           \__/
//     +-----------------> t
#pragma once

#include <array>

#include "motion/profile/profile_state.hpp"

namespace softmc::motion {

// Advances (p, v, a) by t seconds under constant jerk j. rt-safe.
inline ProfileState advance(ProfileState x, double j, double t) {
  x.s += t * (x.v + t * (0.5 * x.a + t * j / 6.0));
  x.v += t * (x.a + 0.5 * t * j);
  x.a += t * j;
  x.j = j;
  return x;
}

class JerkPath {
 public:
  // The longest user: OTG's brake (1) + ramp (3) + cruise (1) + ramp (3). An S-curve uses 7.
  static constexpr int kMaxPhases = 8;

  // Starts an empty path at `start` (time 0).
  void reset(const ProfileState& start);
  // Appends a phase of `dur` seconds at jerk `j`; acceleration stays continuous. dur ≤ 0 adds nothing.
  void push(double dur, double j);
  // Appends a phase of constant acceleration `a` (the acceleration jumps to it: jerk-unlimited profiles).
  void push_acc(double dur, double a);
  // Sets the acceleration at the end of the path (a jump, for jerk-unlimited profiles).
  void set_end_acc(double a) { end_.a = a; }
  // Replaces the integrated end state by the exact one (removes rounding at the target). Where the
  // exact end lies within 1e-9 of the path's own distance from its start, the positions in between
  // are stretched by the same ratio (v, a and j with them), so that the path arrives on the exact end
  // instead of jumping onto it: a jump of δ is a jerk of 2·δ/dt³ in the setpoints' third differences,
  // which a root found to 1e-13 of a 20 mm stop makes 0.6 % of one cycle's jerk at 21 mm/s³ and 0.25 ms.
  void snap_end(const ProfileState& exact);

  double duration() const { return t_end_; }
  const ProfileState& start() const { return start_; }
  const ProfileState& end() const { return end_; }
  int phases() const { return n_; }

  // rt-safe: closed form; t is clamped to [0, duration] (the end state is held, position included).
  ProfileState at(double t) const;

 private:
  struct Phase {
    double t0 = 0;
    ProfileState x0{};  // state at t0, x0.j = this phase's jerk
  };
  std::array<Phase, kMaxPhases> ph_{};
  int n_ = 0;
  double t_end_ = 0;
  double stretch_ = 1;  // positions from start_ scaled by this before the end (snap_end)
  ProfileState start_{}, end_{};
};

}  // namespace softmc::motion
