// Online trajectory generation for one axis: from the current (p, v, a) to a target position at rest, or to a
// target speed, time-optimal under v/a/jerk limits; a new target or new limits may arrive at any time and the
// motion continues from the current state with no jump in p, v or a (spc200.md S-2 takeover, jog, stops).
//
//   x ─► [brake |a| to a_max] ─► ramp to v_peak (a → 0) ─► cruise at v_peak ─► ramp to rest at the target
//
// Position mode chooses v_peak ∈ [−v_max, v_max]: either cruise at ±v_max, or no cruise with the two ramps
// covering the distance exactly (roots bracketed on the length function's kink speeds and a coarse grid, then
// Illinois regula falsi, safeguarded by bisection); the fastest candidate wins. The family is that of Ruckig's
// 7-phase UDDU/UDUD profiles for a target at rest (a = 0 where the cruise would be); from rest it equals the
// S-curve, and no peak speed found by a dense brute-force scan beats the one chosen (tests). Bounded work, no
// allocation.
//
// Documented exceptions to the limits, all unavoidable from the given state:
//  - |v0| > v_max (e.g. the limit was lowered): the speed falls monotonically to the new v_max first;
//  - |a0| > a_max: the acceleration is first brought to ±a_max at full jerk;
//  - a0 pushing v beyond v_max: v peaks at the inflection speed v0 + a0·|a0|/(2j) before coming back.
#pragma once

#include <cstdint>

#include "motion/profile/jerk_path.hpp"
#include "motion/profile/profile_state.hpp"

namespace softmc::motion {

struct OtgLimits {
  double v_max_mm_s = 0;   // > 0
  double a_max_mm_s2 = 0;  // > 0
  double j_max_mm_s3 = 0;  // ≥ 0; 0 = no jerk limit (acceleration may jump: trapezoid)
};

enum class OtgResult : std::uint8_t { Working, Finished, ErrorInvalidInput };
const char* to_string(OtgResult r);

enum class OtgMode : std::uint8_t { Position, Velocity };

// Length and duration of the no-cruise trajectory from x through peak speed vp (a = 0 there) to rest.
struct PeakTrial {
  double length_mm = 0;
  double duration_s = 0;
};
// rt-safe. Requires |x.a| ≤ a_max when j_max > 0. Exposed for tests and tools.
PeakTrial otg_peak_trial(const ProfileState& x, double vp, const OtgLimits& lim);

class Otg1 {
 public:
  Otg1() { reset({}); }
  explicit Otg1(double p_mm) { reset({p_mm, 0, 0, 0}); }

  // Sets the current state (initialisation, re-synchronisation to the actual position, or a test's starting
  // state); the next update plans from exactly this (p, v, a). Until then the axis coasts at x.v.
  void reset(const ProfileState& x);

  // rt-safe (bounded). Plans from the current state to `target_mm` at rest. Validates first: on error nothing
  // changes and the previous trajectory continues.
  OtgResult update(double target_mm, const OtgLimits& lim);
  // rt-safe. Plans from the current state to the speed v_mm_s (|v| ≤ v_max), then holds it (jog; 0 = stop).
  OtgResult update_velocity(double v_mm_s, const OtgLimits& lim);
  // rt-safe. Stops as fast as the limits allow from the current (v, a).
  OtgResult stop(const OtgLimits& lim) { return update_velocity(0, lim); }

  // rt-safe. Advances the clock by dt and returns Working or Finished (target reached).
  OtgResult step(double dt_s);
  // rt-safe. The state t seconds after the last update (velocity mode extrapolates at the held speed).
  ProfileState at(double t_s) const;

  const ProfileState& state() const { return now_; }
  double time_s() const { return t_; }
  double duration_s() const { return path_.duration(); }
  bool finished() const { return t_ >= path_.duration(); }
  OtgMode mode() const { return mode_; }
  double target_mm() const { return target_mm_; }
  double target_v_mm_s() const { return target_v_; }
  const JerkPath& path() const { return path_; }

 private:
  // Starts a new path at now_ and brings |a| to a_max if needed; returns the state planning starts from.
  ProfileState begin(const OtgLimits& lim);

  JerkPath path_;
  ProfileState now_{};
  double t_ = 0;
  OtgMode mode_ = OtgMode::Velocity;
  double target_mm_ = 0, target_v_ = 0;
};

}  // namespace softmc::motion
