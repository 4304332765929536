// Safety of a jerk-limited path state: a cycle's step is taken only when, from where it ends, the
// fallback brake π still meets every limit ahead (docs/planner.md, "Jerk").
//
//   now ──step──► x ──π──π──π──…──► rest        π: one cycle of the time-optimal ramp to speed 0,
//   (candidate)      (simulated cycle by cycle      with the acceleration limit lowered ahead of
//                     with the interpolator's dt)   blocks that allow less (anticipation)
//
// Every cycle of the simulation is checked against the blocks it touches: |jerk| ≤ J_k, |a| ≤ A_k,
// v ≤ hard cap, v ≤ junction speed when crossing a block start, no crossing of a point to stop at
// (exact stop, end of the window). π is a fixed (Markov) policy of the state and position, so the
// first π step from an accepted state lands on the rest of the same, already checked, simulation:
// once a state is accepted there is always a safe next step. Limits are never exceeded by design,
// not by a distance model of the brake.
// Shortcut (same verdict, fewer cycles): where every block the rest of π can reach or scan has the
// acceleration and jerk limit π brakes with now, π is one closed-form ramp to rest; when that ramp
// keeps every cap, junction and stop of those blocks, the cycle-by-cycle simulation stops there.
//
// Certificate (no simulation at all): before simulating π, verify() tries the ramp to rest with the
// smallest acceleration A and jerk J of every block it enters. That ramp is known in closed form, so
// whether it keeps every limit is a walk over those blocks (its speed where it passes each cap and
// junction, from its phases). When it does, the state is accepted with that ramp as its fallback
// brake instead of π: the interpolator remembers (A, J), and in a cycle where nothing better is
// accepted it takes one cycle of that ramp, whose rest is the same ramp (the remainder of a
// time-optimal ramp is the time-optimal ramp from where it has got to). Either way an accepted state
// always has a checked next step.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/ring.hpp"
#include "motion/planner/block.hpp"
#include "motion/profile/profile_state.hpp"

namespace softmc::motion {

// What the path speed is asked to be, besides the blocks' own limits (P-8): the feed override, and
// the PLC's caps on path speed for feed moves and for rapids (∞: none).
struct SpeedRule {
  double feed_override = 1;
  double feed_limit_mm_s = std::numeric_limits<double>::infinity();
  double rapid_limit_mm_s = std::numeric_limits<double>::infinity();
  SpeedRule() = default;
  SpeedRule(double override_factor) : feed_override(override_factor) {}  // NOLINT: an override alone
  friend bool operator==(const SpeedRule&, const SpeedRule&) = default;
};

// rt-safe. Path speed the feed, the override and the limits ask for on `b`, under its hard cap
// (rapids: override ≤ 1).
inline double soft_speed(const Block& b, const SpeedRule& r) {
  if (b.rapid) return std::min(b.v_cap_mm_s * std::min(1.0, r.feed_override), r.rapid_limit_mm_s);
  const double v = std::min(b.v_cap_mm_s, b.feed_mm_s * r.feed_override);
  return std::min(v, r.feed_limit_mm_s);
}

// What made a step, so that any instant within it can be computed again (step_at): the ramp
// towards gen_vt with limits gen_a, gen_j, or constant jerk gen_j, from the cycle's start state; a
// position-mode stop (the StopPlan knows it); or a step of constant speed (a cruise).
enum class StepGen : std::uint8_t { Ramp, Jerk, Stop, Cruise };

// One cycle of path motion: the state it ends in (x.s = distance moved) and bounds within the cycle.
struct PathStep {
  ProfileState x{};
  double j_abs = 0;   // largest |jerk| used
  double a_abs = 0;   // largest |a| reached
  double v_peak = 0;  // largest speed reached
  double v_min = 0;   // smallest speed reached (< 0: the path would reverse)
  StepGen gen = StepGen::Cruise;
  double gen_vt = 0, gen_a = 0, gen_j = 0;
};

// rt-safe. dt of the velocity ramp from x towards speed vt (|a| first brought within a_max), held
// there once reached; x.s is the origin.
PathStep ramp_cycle(const ProfileState& x, double vt, double a_max, double j_max, double dt);
// rt-safe. dt at constant jerk j.
PathStep jerk_cycle(const ProfileState& x, double j, double dt);
// rt-safe. The state t (0 ≤ t ≤ the cycle) into the step `st` made by ramp_cycle or jerk_cycle from
// x (x.s as origin): the same phases, cut at t. (StepGen::Stop is the StopPlan's: StopPlan::last_at;
// a cruise holds its speed.)
ProfileState step_at(const ProfileState& x, const PathStep& st, double t);

struct GuardVerdict {
  bool hard_ok = true;   // no hard limit broken (caps, junctions, acceleration, jerk, stops)
  bool soft_ok = true;   // nor a soft one (feed × override)
  bool stop_binds = false;  // the first failure is a point to stop at (exact stop, window end)
  double fail_at_mm = 0;    // distance from now of the first failing limit
  double fail_u_mm_s = 0;   // its speed limit
  // Accepted by the certificate: the fallback brake from the step's end is the ramp to rest with
  // these limits (0: accepted by simulating π, which is the fallback).
  double cert_a = 0, cert_j = 0;
  // A gated certificate (cert_a2 > 0): the fallback brake first ramps to speed cert_w with
  // cert_a, cert_j, reached before the block cert_gate_mm ahead (whose acceleration or jerk is far
  // lower), never below cert_w on the way, then from there ramps to rest with cert_a2, cert_j2
  // (JerkGuard::gated_brake).
  double cert_w = 0, cert_gate_mm = 0, cert_a2 = 0, cert_j2 = 0;
  bool simulated = false;  // the verdict needed the simulation of π
  double brake_s = 0;      // the certificate's ramp to rest: its duration (∞ when it has none)
  bool failed() const { return !hard_ok || !soft_ok; }
};

// Index of the window for the guard, sized once (Interpolator construction): for each block, its
// start (distance from an origin, the start of the block that was the front when the index was
// begun), its limits as the guard sees them (scaled acceleration and jerk, hard cap, soft cap under
// the override, junction speed²), the minima of each group of 8, and the exact stops; filled
// lazily as far as a check looks, and kept from cycle to cycle while it holds (JerkGuard's
// constructor): only pops since (Ring::pops: the front moves on in the index, `origin`, and nothing
// is indexed again), the same scale, halt, override and dt; when blocks were committed since, the
// old back is indexed again (the commit after it may lower its jerk: Planner::commit). It begins
// again after a clear, a change of those, once the origin has moved `cap` blocks on (the arrays
// hold 2·cap + 1), or once the front starts kRebase_mm from the origin (a start is read as the
// difference of two: kept to the rounding of small numbers).
// Every check reads the blocks through it: the same starts everywhere, compact arrays instead of
// the 1.9 kB blocks. The certificate takes a whole group at once where block by block its walk
// would end the same; brake() asks "the
// smallest jerk from block k while a block starts within d of p" in every simulated cycle: a
// binary search and a few group minima. Group answers (groups = false: block by block, the
// reference) never change a verdict.
struct GuardScratch {
  static constexpr std::size_t kGroup = 8;
  static constexpr double kRebase_mm = 64;
  explicit GuardScratch(std::size_t blocks)
      : start(2 * blocks + 2), jerk(2 * blocks + 2), acc(2 * blocks + 2), hard(2 * blocks + 2), soft(2 * blocks + 2),
        u2(2 * blocks + 2), group_min(2 * blocks / kGroup + 2), group_cap(2 * blocks / kGroup + 2),
        group_u2(2 * blocks / kGroup + 2), group_acc(2 * blocks / kGroup + 2), stops(2 * blocks + 2), cap(blocks) {}
  std::vector<double> start, jerk, acc, hard, soft, u2;  // soft: before relaxing the front's to v_now
  std::vector<double> group_min, group_cap, group_u2;    // per group: least jerk, cap (hard or soft), u²
  std::vector<double> group_acc;                         // per group: least acceleration
  std::vector<std::size_t> stops;                        // positions in the index, rising
  std::size_t cap;
  bool groups = true;
  // The certificate's walk tests blocks against its ramp's distance in closed form, bracketed, and
  // builds the ramp only where a block falls inside the bracket and once at the end (same verdicts;
  // false builds it at every refresh of the distance: the reference for tests).
  bool bracket = true;
  std::uint64_t groups_skipped = 0;  // by the certificate, since construction
  std::uint64_t sharpened = 0;       // ramps the certificate built for a block inside its bracket
  std::uint64_t blocks_indexed = 0;  // since construction
  std::uint64_t epoch = 0;           // times the index began again: positions compare within one epoch
  // What the index was built for, and how far: positions [origin, built) are indexed, the front
  // block at `origin`.
  std::size_t origin = 0, built = 0, nstops = 0, size = 0;
  std::uint64_t changes = ~std::uint64_t{0}, pops = 0;
  double scale = 0, dt = 0;
  SpeedRule rule{0.0};
  bool halt = false;
};

// How JerkGuard::verify reaches its verdict (InterpolatorConfig's guard_* keys).
struct GuardMode {
  bool closed_form = true;      // the simulation of π ends where its rest is one closed-form ramp
  bool certify = false;         // the certificate first
  bool simulate = true;         // where the certificate cannot decide: simulate π (else refuse) ...
  double simulate_up_to_s = 0;  // ... or only when the certificate's ramp lasts at most this
  bool gate = true;             // where the certificate cannot decide, its gated form first
  bool jerk_gate = true;        // ... a block of far lower jerk being a gate too
};

class JerkGuard {
 public:
  // `n` blocks of `ring` from the front (the rest is beyond the horizon: its start is a stop);
  // `s_front` the distance into the front block, `v_now` the present speed (the front block's soft
  // cap is relaxed to it: an override that dropped cannot be obeyed instantly); `scale` scales A, J.
  // `scratch` holds at least n + 1 blocks.
  JerkGuard(const core::Ring<Block>& ring, std::size_t n, double s_front, double v_now, double dt, double scale,
            bool halt, const SpeedRule& rule, GuardScratch& scratch);

  // rt-safe. Checks the step from now, then (mode.certify) the certificate from where it ends, and
  // where that cannot decide, π, cycle by cycle until rest (mode.closed_form: until the rest of π is
  // one ramp that provably keeps every limit, same verdict).
  GuardVerdict verify(const PathStep& step, const GuardMode& mode) const;
  // rt-safe. Only the check of the step itself (its blocks' caps, junctions, stops, acceleration
  // and jerk), no fallback brake from where it ends.
  GuardVerdict check_step(const PathStep& step) const;
  // rt-safe. A cruise certificate (InterpolatorConfig::guard_cruise_cycles): `cruise` is a stretch
  // of constant speed from now (x.a = 0, no jerk) ending x.s ahead. Accepted (not failed) when the
  // stretch keeps every limit and the certificate's ramp to rest from its end, with limits no
  // higher than those of every block the stretch passes (cert_a, cert_j), keeps every limit ahead.
  // The ramp with those limits from any point of the stretch at that speed is then a safe fallback
  // brake too: it enters no block the two checks did not cover, and it is nowhere faster than the
  // stretch and the ramp from its end (past its start a ramp to rest only slows, so a later start
  // is at least as fast at every point), and it comes to rest no later (docs/planner.md, "Cruise
  // certificates").
  GuardVerdict certify_cruise(const PathStep& cruise) const;
  // The present position and the window's end (an index position) in the index's coordinates,
  // which hold while scratch.epoch does.
  double now_in_index() const { return base_; }
  std::size_t window_end_in_index() const { return o_ + n_; }
  // rt-safe. One cycle of π from the present state.
  PathStep brake_now(const ProfileState& now) const { return brake({now.s, now.v, now.a, 0}, 0, Cursor{0}); }
  // rt-safe. One cycle of the certified ramp to rest with limits a, j from the present state.
  PathStep certified_brake(const ProfileState& now, double a, double j) const { return ramp_cycle(now, 0, a, j, dt_); }
  // rt-safe. The same, kept from ending past a point to stop at `stop_mm` ahead: run for thousands
  // of cycles, the ramp solved again from each cycle's rounded state drifts (2.5e-11 mm past a stop
  // after 13 s at 0.25 ms), and the last cycle's landing on the point took the drift as a jerk step.
  // Where the ramp would end past the point (by more than 1e-4 of j·dt³), its jerk is raised by what
  // lands it there, at most the guard's relative slack (kRel): a cycle's drift needs about 1e-14 of J.
  PathStep anchored_brake(const ProfileState& now, double a, double j, double stop_mm) const;
  // rt-safe. Distance of the ramp to rest with limits a, j from x (|x.a| above a first brought to it).
  static double brake_distance(const ProfileState& x, double a, double j);
  // rt-safe. The same from the whole ramp built (the reference for tests).
  static double brake_distance_built(const ProfileState& x, double a, double j);
  // rt-safe. One cycle of a gated certificate's brake (GuardVerdict::cert_a2 > 0) with the gate
  // gate_mm ahead: before it the ramp to w, past it the ramp to rest.
  PathStep gated_brake(const ProfileState& now, const GuardVerdict& c) const {
    return c.cert_gate_mm > 0 ? ramp_cycle(now, c.cert_w, c.cert_a, c.cert_j, dt_)
                              : ramp_cycle(now, 0, c.cert_a2, c.cert_j2, dt_);
  }
  // Limits (scaled) of the blocks from the front up to distance `to_mm` from now.
  void limits_until(double to_mm, double& a_min, double& j_min) const;

  // What the guard holds block k (< n) to: acceleration and jerk (scaled), the speed the feed and
  // override ask for (the front's relaxed to the present speed), read from the index.
  // (Inline: the certificate asks them of every block its ramp enters.)
  double acc(std::size_t k) const { return need(k).acc[o_ + k]; }
  double jerk(std::size_t k) const { return need(k).jerk[o_ + k]; }
  double soft(std::size_t k) const {
    const double s = need(k).soft[o_ + k];
    return k == 0 ? std::max(s, v_now_) : s;  // already faster (the override dropped): only the ramp down is asked
  }
  // Block k's start (k ≤ n) from now, as every check reads it.
  double start_of(std::size_t k) const { return start(k); }

 private:
  struct Cursor {
    std::size_t k = 0;  // block containing the position (its start: start(k))
  };
  PathStep brake(const ProfileState& x, double p, const Cursor& c) const;
  bool tail_safe(const ProfileState& x, double p, const Cursor& c) const;
  enum class Cert { Safe, Fails, Unknown };
  // gate (optional): set to the first block the ramp entered whose acceleration is below half the
  // least before it, when it is still 0; jerk_gate likewise to the first block the walk scanned
  // (entered, or only within π's scan) whose jerk is below half the least before it.
  // a_init, j_init: limits the walk starts from besides block c.k's (certify_cruise's stretch).
  Cert certify(const ProfileState& x, double p, const Cursor& c, GuardVerdict& v, std::size_t* gate = nullptr,
               std::size_t* jerk_gate = nullptr, double a_init = std::numeric_limits<double>::infinity(),
               double j_init = std::numeric_limits<double>::infinity()) const;
  Cert certify_gated(const ProfileState& x, double p, const Cursor& c, std::size_t gate, GuardVerdict& v) const;
  bool check(Cursor& c, double p0, double v0, const PathStep& st, GuardVerdict& verdict) const;
  double soft_raw(const Block& b) const;  // soft(k) before the front's is relaxed to v_now
  bool fail(GuardVerdict& v, bool hard, double at, double u, bool stop) const;
  // min(j, jerk(k)) over k = from, from + 1, … while k < n, the block starts within d of p
  // (start − p < d) and it is no exact stop: block by block, or from the group minima.
  double jerk_min_walk(std::size_t from, double p, double d, double j) const;
  double jerk_min(std::size_t from, double p, double d, double j) const;
  void index_until(double p, double d) const;
  void index_through(std::size_t k) const;  // blocks 0 … min(k, n − 1) and their ends
  void index_block() const;                 // the next block
  // Block k's start from now (k ≤ n), and its limits (k < n), read from the index.
  double start(std::size_t k) const {
    if (k > built()) index_through(k - 1);
    return g_.start[o_ + k] - base_;
  }
  double hard(std::size_t k) const { return need(k).hard[o_ + k]; }
  double u2(std::size_t k) const { return need(k).u2[o_ + k]; }
  const GuardScratch& need(std::size_t k) const {
    if (k >= built()) index_through(k);
    return g_;
  }
  std::size_t built() const { return g_.built - o_; }  // blocks indexed from the front

  const core::Ring<Block>& ring_;
  std::size_t n_;
  double v_now_, dt_, scale_;
  bool halt_;
  SpeedRule rule_;
  GuardScratch& g_;
  std::size_t o_ = 0;  // the front block's position in the index
  double base_ = 0;    // distance from the index's origin to now: start(k) = g_.start[o_ + k] − base_
};

// (Inline: both of the guard's files call them in its walks, jerk_guard.cpp and jerk_certificate.cpp.)
// rt-safe
inline void JerkGuard::index_through(std::size_t k) const {
  const std::size_t last = std::min(k, n_ - 1);
  while (built() <= last) index_block();
}

inline bool JerkGuard::fail(GuardVerdict& v, bool hard, double at, double u, bool stop) const {
  if (!v.failed()) {
    v.fail_at_mm = at;
    v.fail_u_mm_s = u;
    v.stop_binds = stop;
  }
  (hard ? v.hard_ok : v.soft_ok) = false;
  return false;
}

}  // namespace softmc::motion
