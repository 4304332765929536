// The interpolator: executes the look-ahead window once per cycle into setpoints — the lazy forward
// pass of the planner, feed override, feed hold, motion enable and stop ramps (P-2, P-5, P-8).
//
//   window: [front | 1 | 2 | ...]     front: VelocityRamp from the actual (s, v) to the exit limit
//             ▲ s, v                  v2_entry_max of block 1 (0 when it is the last), re-planned
//             └ sampled at t          whenever an input changes: O(1) per cycle, no allocation
//
// Time left over at the end of a block carries into the next one (several short blocks may pass in
// one cycle), so block boundaries are not rounded to the cycle.
#pragma once

#include <algorithm>
#include <cstdint>

#include "motion/interp/jerk_follower.hpp"
#include "motion/interp/jerk_guard.hpp"
#include "motion/interp/velocity_ramp.hpp"
#include "motion/limits.hpp"
#include "motion/planner/plan_queue.hpp"
#include "motion/profile/otg1.hpp"

namespace softmc::motion {

struct Setpoint {
  Vec pos;           // mm, per axis
  Vec vel;           // mm/s, per axis
  Vec acc;           // mm/s², per axis
  double path_v = 0;  // mm/s along the path
  bool moving = false;   // a block is being executed (also while held at rest on the path)
  bool rapid = false;
  std::uint32_t tag = 0;  // tag of the block the setpoint lies on
  std::uint32_t tag_last = 0;  // its last instruction (a merged line stands for tag..tag_last)
};

// P-5: a normal stop uses the blocks' normal acceleration, an emergency stop that times this factor.
enum class StopKind : std::uint8_t { None, Normal, Emergency };

struct InterpolatorConfig {
  double max_feed_override = 2.0;      // P-8: the override is clamped to [0, this]
  double emergency_accel_scale = 1.0;  // P-5: emergency ramp relative to the normal one (≥ 1; less is taken as 1)
  int max_blocks_per_cycle = 512;      // bounds one cycle's work; 512 blocks per ms = 512k blocks/s
  // Jerk mode (the S-curve path profile) looks at most this many blocks ahead per cycle; the end of
  // that horizon is treated as a point to stop at, so it is always safe (only slower when too short).
  int max_horizon_blocks = 8192;
  // Jerk mode: the guard ends its brake simulation where the rest is one closed-form ramp that keeps
  // every limit (same verdicts, bit-identical setpoints); false simulates to rest (tests, benchmarks).
  bool guard_closed_form = true;
  // Jerk mode: the guard answers its brake's range queries from the group minima of its index of
  // the window, and its certificate skips groups that keep every cap (same answers as taking the
  // blocks one by one; false takes them one by one: tests, benchmarks).
  bool guard_index = true;
  // Jerk mode: the certificate's walk takes its ramp's distance in closed form wherever that
  // decides (same verdicts, bit-identical setpoints; false builds the ramp at every refresh of the
  // distance: tests, benchmarks).
  bool guard_distance_bracket = true;
  // Jerk mode: the guard first tries its certificate, the closed-form ramp to rest with the smallest
  // limits it meets (jerk_guard.hpp), and simulates its brake π only where that cannot decide: with
  // guard_simulate always (planner.jerk_guard_simulate), else only when the ramp lasts at most
  // guard_short_brake_cycles (near a stop point: a few cycles of work); otherwise the candidate is
  // refused. guard_certificate = false always simulates (tests, benchmarks).
  bool guard_certificate = true;
  bool guard_simulate = false;
  int guard_short_brake_cycles = 10;
  // Jerk mode: where the certificate cannot decide, its gated form (two ramps: to the speed a block
  // of far lower acceleration allows at its start, then to rest from there; jerk_certificate.cpp) first.
  bool guard_gate = true;
  // ... with a block of far lower jerk (half the least before it) as a gate too, where the plain
  // certificate's ramp or π's scan reaches one (false: acceleration gates only; tests).
  bool guard_jerk_gate = true;
  // Jerk mode: while braking towards blocks of far lower jerk, a candidate that eases the brake at
  // the jerk of the blocks this cycle reaches (false: only at the least jerk ahead; tests).
  bool ease_brake = true;
  // Tests: from this jerk-mode cycle on every candidate is refused, so the fallback brake certified
  // last (plain or gated) runs to rest and its limits show on the trace (−1: never).
  long long guard_refuse_from_cycle = -1;
  // The position-mode stop candidate's plan is sampled on while it is taken (StopPlan); false solves
  // it every cycle (the reference the kept plan is tested against).
  bool keep_stop_plan = true;
  // Jerk mode, with the certificate: cruising at the speed asked for (a = 0), the guard certifies
  // this many cycles of that cruise at once (JerkGuard::certify_cruise), and the cycles within
  // them check only their own step; refused, half as long a stretch is tried the next cycle, down to
  // 2 cycles, then the whole length again after half as many cycles (0 or 1: every cycle certifies
  // its own step; tests, benchmarks).
  int guard_cruise_cycles = 16;
  // Jerk mode: at a corner between two lines that the planner left a stop (overlap_mm > 0 on the
  // second), the second line begins once the first has at most overlap_mm left to brake, with its
  // limits lowered by what the first's end still uses on each axis (the corner overlap; false:
  // every such corner at rest; planner.corner_overlap).
  bool corner_overlap = true;
  // The machine's axis limits, which the overlap shares between the two lines (no axis present:
  // unknown, and each axis's limit is taken as the larger of what the two lines allow it).
  MachineLimits axis_limits{};
};

// True when any present axis has a jerk limit (blocks then carry a finite j_mm_s3: the jerk follower runs).
bool jerk_mode(const MachineLimits& lim);

class Interpolator {
 public:
  Interpolator(PlanQueue& queue, const Vec& start, const InterpolatorConfig& config = {})
      : queue_(queue), config_(config), scratch_(queue.ring().capacity()) {
    sp_.pos = start;
    // Below 1 a stop would brake more gently than the corners ahead were planned for.
    config_.emergency_accel_scale = std::max(1.0, config_.emergency_accel_scale);
  }

  // rt-safe. Advances time by dt and returns the new setpoint.
  const Setpoint& step(double dt);
  // Jerk mode: corners whose next line began while the line before still braked (corner overlap).
  std::uint64_t corner_overlaps() const { return overlaps_; }
  // The braking line's end still runs beside the path (corner overlap): not at rest even where the
  // path is.
  bool overlapping() const { return tail_.active; }

  // rt-safe. P-8: feed override factor (1 = programmed feed), acting from the next step with the
  // ramps kept; rapids follow it up to 1. No axis ever exceeds its own speed limit.
  void set_feed_override(double factor);
  // rt-safe. P-8 caps on the path speed of feed moves and of rapids (mm/s; ∞, 0 or less: none),
  // acting like an override: from the next step, with the ramps kept.
  void set_speed_limits(double feed_limit_mm_s, double rapid_limit_mm_s);
  // rt-safe. Feed hold: brake to rest on the path; release resumes from there.
  void set_feed_hold(bool hold) { hold_ = hold; }
  // rt-safe. P-2: motion enable of the path's axes; dropping it brakes to rest on the path with the
  // normal ramp, restoring it resumes on the path without a jump.
  void set_motion_enable(bool enable) { enable_ = enable; }
  // rt-safe. P-5: brake to rest on the path, then drop everything planned.
  void request_stop(StopKind kind);

  const Setpoint& setpoint() const { return tail_.active ? out_ : sp_; }
  // True while there is nothing left to move (nothing committed, nothing pending).
  bool idle() const { return queue_.empty() && !tail_.active; }
  // True when a stop has ended, until acknowledge_stop().
  bool stopped() const { return stopped_ && !tail_.active; }
  void acknowledge_stop() { stopped_ = false; }
  // rt-safe. Forgets a stop requested or ended and not acknowledged (a fault cut it short): a new
  // program starts without it. The queue is the caller's (empty when a program starts).
  void cancel_stop() {
    stop_ = StopKind::None;
    stopped_ = false;
  }
  bool stopping() const { return stop_ != StopKind::None; }
  // The path's speed and, in jerk mode, acceleration after the last step (0 with trapezoids).
  double path_speed() const { return v_; }
  double path_acceleration() const { return a_; }
  double front_progress() const { return s_; }  // jerk mode: distance into the front block
  double feed_override() const { return rule_.feed_override; }
  const SpeedRule& speed_rule() const { return rule_; }
  // Jerk mode: cycles run, and candidate steps whose verdict needed the simulation of π (the rest
  // were settled by the certificate or refused by the check of the step itself); for benchmarks.
  std::uint64_t jerk_cycles() const { return jerk_cycles_; }
  std::uint64_t guard_simulations() const { return guard_simulations_; }
  std::uint64_t guard_verifies() const { return guard_verifies_; }  // candidates checked
  std::uint64_t cruise_cycles_certified() const { return cruise_hits_; }  // steps within a cruise certificate
  // Jerk mode: the fallback brake kept from the last accepted step (its cert_* fields).
  const GuardVerdict& fallback() const { return cert_; }
  // Jerk mode: the position-mode stop candidate's plans, solved and sampled on (StopPlan).
  const StopPlan& stop_plan() const { return stop_plan_; }
  std::uint64_t guard_groups_skipped() const { return scratch_.groups_skipped; }  // GuardScratch
  // A feed hold or a motion-enable drop (P-2) is braking the path or holds it.
  bool held() const { return hold_ || !enable_; }
  // At rest on the path because of a hold, an enable drop or a stop in progress.
  bool halted_at_rest() const { return sp_.moving && sp_.path_v == 0 && halt() && !tail_.active; }

 private:
  struct Inputs {
    double vc = 0, v1_want = 0, v1_max = 0, acc_scale = 1;
    friend bool operator==(const Inputs&, const Inputs&) = default;
  };
  bool halt() const { return hold_ || !enable_ || stop_ != StopKind::None; }
  double soft_speed(const Block& b) const;
  Inputs inputs(const Block& b) const;
  void replan(const Block& b, const Inputs& in);
  static double ramp_acc(const TangentLaw& law, double dist, double v0, const Inputs& in);
  static VelocityRamp ramp_for(const Block& b, double dist, double v0, const Inputs& in);
  void rest_at_end();
  const Setpoint& rest_at_window_end();
  const Setpoint& step_path(double dt);
  const Setpoint& step_jerk(double dt);
  void begin_overlap(double dt);
  const Setpoint& step_trapezoid(double dt);  // step() on a front block without a jerk limit

  PlanQueue& queue_;
  InterpolatorConfig config_;
  GuardScratch scratch_;  // the jerk guard's index of the window, kept between cycles, sized once
  Setpoint sp_;
  bool started_ = false;  // the front block has begun
  VelocityRamp ramp_;
  double t_ = 0;          // time since ramp_ began
  double v_ = 0;          // path speed carried across block boundaries
  double a_ = 0;          // jerk mode: path acceleration
  double s_ = 0;          // jerk mode: distance into the front block
  // Jerk mode: the fallback brake from the present state, certified when the state was accepted:
  // its cert_* fields (the ramp to rest with cert_a, cert_j; gated: cert_a2 > 0), or (cert_a 0) π.
  GuardVerdict cert_;
  StopPlan stop_plan_;  // the position-mode stop candidate, kept while it is taken cycle after cycle
  // Jerk mode: a cruise certified ahead (guard_cruise_cycles): at speed v up to end (the index's
  // coordinates of its epoch, with the window ending no earlier than window_end), the fallback brake
  // from any point of it the ramp to rest with a, j.
  struct CruiseCert {
    bool valid = false;
    std::uint64_t epoch = 0;
    std::size_t window_end = 0;
    double v = 0, end = 0, a = 0, j = 0;
    int wait = 0;    // cycles before a refused cruise certificate is tried again
    int cycles = 0;  // the next one's length (halved after each refusal, down to 2)
  };
  CruiseCert cruise_;
  std::uint64_t cruise_hits_ = 0;
  std::uint64_t jerk_cycles_ = 0, guard_simulations_ = 0, guard_verifies_ = 0;
  std::uint32_t rest_cycles_ = 0;  // jerk mode: cycles in a row that ended at rest without moving
  Inputs in_;
  // Jerk mode, the corner overlap: the end of the braking line runs on beside the next one, as a
  // position-mode stop from the state it had (`otg`, along `dir`, s ≤ 0 up to its end at 0), added
  // to the path's setpoint (out_). The next line's limits, lowered meanwhile, come back when it ends.
  struct Tail {
    bool active = false;
    Otg1 otg;
    Vec dir{};
    double t = 0;
    double a = 0, j = 0, v_cap = 0, v_split = 0;  // the next line's limits before the overlap
    std::uint64_t pops = 0;                       // the ring's pops while that line is its front
    std::uint32_t tag = 0, tag_last = 0;          // the braking line's instructions
    bool rapid = false;
    double a1 = 0, j1 = 0;                        // the braking line's acceleration and jerk
    bool emergency = false;                       // re-planned with the emergency scale (P-5)
  };
  Tail tail_;
  Setpoint out_;  // the path's setpoint plus the tail's, while a tail runs
  std::uint64_t overlaps_ = 0;
  std::uint64_t overlap_refused_ = ~std::uint64_t{0};  // the ring's pops at a corner found no use to overlap
  SpeedRule rule_;  // override and P-8 speed limits
  bool hold_ = false, enable_ = true, stopped_ = false;
  StopKind stop_ = StopKind::None;
};

}  // namespace softmc::motion
