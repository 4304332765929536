// The jerk follower's safety check: one-cycle steps with their bounds, and the simulated fallback brake.
#include "motion/interp/jerk_guard.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "motion/interp/jerk_guard_detail.hpp"

namespace softmc::motion {

using namespace guard_detail;

// rt-safe
PathStep ramp_cycle(const ProfileState& x, double vt, double a_max, double j_max, double dt) {
  Cycle c(x, dt);
  c.st.gen = StepGen::Ramp;
  c.st.gen_vt = vt;
  c.st.gen_a = a_max;
  c.st.gen_j = j_max;
  const RampPhases ph = ramp_phases(x, vt, a_max, j_max);
  c.phase(ph.dur[0], ph.jerk[0]);
  if (c.left <= 0) return c.st;
  c.st.x.a = std::clamp(c.st.x.a, -a_max, a_max);
#pragma GCC unroll 4
  for (int i = 1; i < 4; ++i) c.phase(ph.dur[i], ph.jerk[i]);
  if (c.left > 0) c.hold_rest(vt, 0);  // exactly the target once there
  return c.st;
}

// rt-safe
PathStep jerk_cycle(const ProfileState& x, double j, double dt) {
  Cycle c(x, dt);
  c.st.gen = StepGen::Jerk;
  c.st.gen_j = j;
  c.phase(dt, j);
  return c.st;
}

// rt-safe
ProfileState step_at(const ProfileState& x, const PathStep& st, double t) {
  switch (st.gen) {
    case StepGen::Ramp: return ramp_cycle(x, st.gen_vt, st.gen_a, st.gen_j, t).x;
    case StepGen::Jerk: return jerk_cycle(x, st.gen_j, t).x;
    default: return {x.v * t, x.v, 0, 0};
  }
}

JerkGuard::JerkGuard(const core::Ring<Block>& ring, std::size_t n, double s_front, double v_now, double dt,
                     double scale, bool halt, const SpeedRule& rule, GuardScratch& scratch)
    : ring_(ring), n_(n), v_now_(v_now), dt_(dt), scale_(scale), halt_(halt),
      rule_(rule), g_(scratch) {
  assert(n >= 1 && n <= ring.size() && n <= g_.cap);
  GuardScratch& g = g_;
  // The index of the last cycle holds while the blocks were only popped (the front moves on in it)
  // and limits read the same; blocks committed since can have lowered the old back's jerk.
  const std::uint64_t popped = ring.pops() - g.pops;
  const std::size_t o = g.origin + static_cast<std::size_t>(popped);
  if (ring.changes() - g.changes != popped || popped > g.size || o > g.built || o > g.cap ||
      g.start[o] > GuardScratch::kRebase_mm || scale != g.scale || halt != g.halt ||
      !(rule == g.rule) || dt != g.dt) {
    g.origin = g.built = g.nstops = 0;  // begin again from the front
    g.start[0] = 0;
    ++g.epoch;
  } else {
    g.origin = o;
    if (ring.size() + static_cast<std::size_t>(popped) != g.size)  // pushed since: the old back again
      g.built = std::max(o, std::min(g.built, o + (g.size - static_cast<std::size_t>(popped)) - 1));
  }
  while (g.nstops > 0 && g.stops[g.nstops - 1] >= g.built) --g.nstops;
  g.changes = ring.changes();
  g.pops = ring.pops();
  g.size = ring.size();
  o_ = g.origin;
  base_ = s_front + g.start[o_];
  g.scale = scale;
  g.halt = halt;
  g.rule = rule;
  g.dt = dt;
}

// rt-safe
double JerkGuard::jerk_min_walk(std::size_t from, double p, double d, double j) const {
  for (std::size_t k = from; k < n_ && start(k) - p < d && u2(k) > 0; ++k) j = std::min(j, jerk(k));
  return j;
}

// rt-safe. Indexes the next block: its limits, the start of the one after, its group's minima.
void JerkGuard::index_block() const {
  GuardScratch& g = g_;
  const std::size_t k = g.built;  // a position in the index: ring block k − o_
  const Block& b = ring_.at(k - o_);
  // A block without a jerk limit (Trapezoid profile, axes with j = 0) reaches its acceleration in one cycle.
  const double jk = (std::isfinite(b.j_mm_s3) ? b.j_mm_s3 : b.a_mm_s2 / dt_) * scale_;
  const double sk = soft_raw(b);
  g.jerk[k] = jk;
  g.acc[k] = b.a_mm_s2 * scale_;
  g.hard[k] = b.v_split_mm_s;
  g.soft[k] = sk;
  g.u2[k] = b.v2_junction;
  if (b.v2_junction <= 0) g.stops[g.nstops++] = k;
  const std::size_t q = k / GuardScratch::kGroup;
  const double cap = std::min(b.v_split_mm_s, sk);
  const bool first = k % GuardScratch::kGroup == 0;
  g.group_min[q] = first ? jk : std::min(g.group_min[q], jk);
  g.group_cap[q] = first ? cap : std::min(g.group_cap[q], cap);
  g.group_u2[q] = first ? b.v2_junction : std::min(g.group_u2[q], b.v2_junction);
  g.group_acc[q] = first ? g.acc[k] : std::min(g.group_acc[q], g.acc[k]);
  g.start[k + 1] = g.start[k] + b.length;
  ++g.built;
  ++g.blocks_indexed;
}

// rt-safe. Extends the index while the next block to index starts within d of p.
void JerkGuard::index_until(double p, double d) const {
  while (built() < n_ && start(built()) - p < d) index_block();
}

// rt-safe. The walk's answer from the group minima: the blocks from `from` up to the first that
// starts d or more beyond p, the first exact stop, or n.
double JerkGuard::jerk_min(std::size_t from, double p, double d, double j) const {
  if (!g_.groups) return jerk_min_walk(from, p, d, j);
  if (from >= n_) return j;
  index_until(p, d);
  const GuardScratch& g = g_;
  // Indexed: blocks 0 … built − 1 and starts 0 … built (the loop above stops once the next start
  // is d beyond p, or at n). Block k is taken while k < n, start − p < d, and it is no stop.
  // Positions in the index from here on (block k at o_ + k).
  from += o_;
  std::size_t lo = from, hi = std::max(from, o_ + std::min(built(), n_));  // the first in [from, hi) failing, else hi
  // (capped at n: an index built for a longer window must not reach past this one)
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (g.start[mid] - base_ - p < d) lo = mid + 1; else hi = mid;
  }
  std::size_t end = lo;  // blocks [from, end) start within d, all indexed
  // The first exact stop at or after `from` ends the range too.
  std::size_t a = 0, b = g.nstops;
  while (a < b) {
    const std::size_t mid = a + (b - a) / 2;
    if (g.stops[mid] < from) a = mid + 1; else b = mid;
  }
  if (a < g.nstops) end = std::min(end, g.stops[a]);
  constexpr std::size_t G = GuardScratch::kGroup;
  std::size_t k = from;
  while (k < end && k % G != 0) j = std::min(j, g.jerk[k++]);
  while (k + G <= end) {
    j = std::min(j, g.group_min[k / G]);
    k += G;
  }
  while (k < end) j = std::min(j, g.jerk[k++]);
  return j;
}

double JerkGuard::soft_raw(const Block& b) const {
  if (halt_) return kInf;
  // v_split_mm_s: a block without a jerk limit keeps a_mm_s2 only up to there (Block).
  const double s = std::min(soft_speed(b, rule_), b.v_split_mm_s);
  return s > 0 ? s : kInf;  // override 0: the ramp to the cruise speed 0 stops the path
}

void JerkGuard::limits_until(double to_mm, double& a_min, double& j_min) const {
  a_min = acc(0);
  j_min = jerk(0);
  for (std::size_t k = 1; k < n_ && start(k) < to_mm - kTouch_mm && u2(k) > 0; ++k) {
    a_min = std::min(a_min, acc(k));
    j_min = std::min(j_min, jerk(k));
  }
}

// rt-safe. The cycle from p0 (in block c.k) to p0 + st.x.s against every block it touches; moves c
// to the block the cycle ends in. False at the first broken limit.
bool JerkGuard::check(Cursor& c, double p0, double v0, const PathStep& st, GuardVerdict& verdict) const {
  (void)v0;
  const double p1 = p0 + st.x.s;
  if (st.v_min < -kAbs) return fail(verdict, true, p0, 0, false);  // the path would reverse
  for (;;) {
    const std::size_t k = c.k;
    const double here = std::max(p0, start(k));
    if (over(st.j_abs, jerk(k)) || over(st.a_abs, acc(k)) || over(st.v_peak, hard(k)))
      return fail(verdict, true, here, hard(k), false);
    if (over(st.v_peak, soft(k))) return fail(verdict, false, here, soft(k), false);
    const double end = start(k + 1);
    if (p1 < end - kTouch_mm) return true;  // the cycle ends inside block k
    const bool cross = p1 > end + kTouch_mm;
    if (k + 1 >= n_) {  // the end of the window (or of the horizon): a point to stop at
      if (cross || st.x.v > kAbs) return fail(verdict, true, end, 0, true);
      return true;
    }
    const double u = std::sqrt(u2(k + 1));
    if (u <= 0) {  // an exact stop: reached at rest, never crossed
      if (cross || st.x.v > kAbs) return fail(verdict, true, end, 0, true);
    } else if (over(cross ? st.v_peak : st.x.v, u)) {
      return fail(verdict, true, end, u, false);
    }
    c = {k + 1};
    if (!cross) {  // lands on the start of k + 1: its limits hold from here
      if (over(std::abs(st.x.a), acc(k + 1)) || over(st.x.v, hard(k + 1))) return fail(verdict, true, end, u, false);
      if (over(st.x.v, soft(k + 1))) return fail(verdict, false, end, soft(k + 1), false);
      return true;
    }
  }
}

// rt-safe. π: one cycle of the time-optimal ramp to rest, with
//  - the jerk of every block the rest of the brake may run through (the release at its end must not
//    meet a block allowing less jerk than it was planned with: the brake's reach only shrinks as it
//    goes on, so the jerk it plans with only rises);
//  - the acceleration of the blocks this cycle can reach, and |a| lowered ahead of blocks allowing
//    less: reaching block m at distance d takes at least d/v_up, in which |a| can fall by
//    J·(d/v_up − 2·dt). Two cycles are lost: check() holds the largest |a| of the whole cycle that
//    crosses into m against m's limit, so |a| must be down before that cycle starts, and a cycle
//    lowers |a| towards what was planned at its start. (With one, a run of blocks whose limits fall
//    a little from one block to the next — CAM curves — had every accelerating step refused by a
//    brake that entered the next block 0.1–4 % over its limit, and crawled at 1–5 mm/s.)
// A brake never enters a block behind an exact stop: those limits do not apply.
PathStep JerkGuard::brake(const ProfileState& x, double p, const Cursor& c) const {
  double j_eff = jerk(c.k), a_eff = acc(c.k);
  const double v_up = x.a > 0 ? x.v + x.a * x.a / (2 * j_eff) : std::max(0.0, x.v);
  if (v_up > 0) {
    const double reach = v_up * dt_ + kTouch_mm;
    const double scan = std::max(reach, v_up * (std::abs(x.a) / j_eff + 2 * dt_));
    for (std::size_t k = c.k + 1; k < n_ && start(k) - p < scan && u2(k) > 0; ++k) {
      const double at = start(k) - p;
      if (at < reach) {
        a_eff = std::min(a_eff, acc(k));
        j_eff = std::min(j_eff, jerk(k));
      } else {
        a_eff = std::min(a_eff, acc(k) + j_eff * std::max(0.0, at / v_up - 2 * dt_));
      }
    }
    a_eff = std::max(a_eff, 1e-9);
    double horizon = reach;
    for (int it = 0; it < 4; ++it) {
      const double a0 = std::clamp(x.a, -a_eff, a_eff);
      const double d = ramp_end({0, x.v, a0, 0}, plan_ramp(x.v, a0, 0, a_eff, j_eff)).s +
                       v_up * (std::abs(x.a) / j_eff + 2 * dt_);
      if (!(d > horizon)) break;
      const double j_new = jerk_min(c.k + 1, p, d, j_eff);
      horizon = d;
      if (j_new == j_eff) break;
      j_eff = j_new;
    }
  }
  a_eff = std::max(a_eff, 1e-9);
  return ramp_cycle(x, 0, a_eff, j_eff, dt_);
}

// rt-safe. True when the rest of π from x (at p, in block c.k) provably meets every limit without
// simulating it. Let A, J be block c.k's limits and D the distance of the ramp from x to rest with
// them. If every block entered within D (+ rounding) has exactly A and J, and every block π's scans
// look at beyond that (brake(): up to D + v_up·(A/J + 2·dt)) allows at least A and J, then every
// future π cycle plans with A and J: π is the remainder of that one ramp. It never exceeds v_up
// (the speed where a reaches 0), |a| ≤ A, |jerk| ≤ J, never reverses (v ≥ a²/2J when braking); so it is safe when every cap,
// soft cap and junction speed it meets is ≥ v_up, and no stop or the window's end lies within D.
bool JerkGuard::tail_safe(const ProfileState& x, double p, const Cursor& c) const {
  const double a0 = acc(c.k), j0 = jerk(c.k);
  if (!(x.v >= 0) || !(std::abs(x.a) <= a0) || !(j0 > 0) || !std::isfinite(j0)) return false;
  // Braking already too hard to bring a to 0 before v does: π reverses (the simulation refuses it).
  if (x.a < 0 && x.v < x.a * x.a / (2 * j0)) return false;
  const double v_up = x.a > 0 ? x.v + x.a * x.a / (2 * j0) : x.v;
  const double d_stop = ramp_end({0, x.v, x.a, 0}, plan_ramp(x.v, x.a, 0, a0, j0)).s;
  if (!(d_stop >= 0)) return false;
  const double entered = p + d_stop * (1 + 1e-9) + 1e-9;
  const double scanned = entered + v_up * (a0 / j0 + 2 * dt_) + kTouch_mm;
  for (std::size_t k = c.k; k < n_; ++k) {
    const double start = this->start(k);
    if (k > c.k) {
      if (u2(k) <= 0) return start > entered + kTouch_mm;  // a stop: π's scans end here
      if (start <= entered + kTouch_mm) {  // entered (or touched): the same limits, every cap ≥ v_up
        if (acc(k) != a0 || jerk(k) != j0 || std::sqrt(u2(k)) < v_up) return false;
      } else if (acc(k) < a0 || jerk(k) < j0) {
        return false;
      }
    }
    if (start <= entered + kTouch_mm && (hard(k) < v_up || soft(k) < v_up)) return false;
    const double end = this->start(k + 1);
    if (end > scanned) return end > entered + kTouch_mm;  // the rest of π ends inside this block
  }
  return start(n_) > entered + kTouch_mm;  // the window's end (a point to stop at) lies beyond the brake
}

// rt-safe. BrakeRamp's d_stop without its bookkeeping (speeds, |a| bounds, phase starts): where no
// phase 0 brings |x.a| down, plan_ramp's three phases advanced as build() advances them (the same
// operations, so the same distance to the bit) at about a third of the instructions.
double JerkGuard::brake_distance(const ProfileState& x, double a, double j) {
  if (std::abs(x.a) > a) return brake_distance_built(x, a, j);
  ProfileState y{0, x.v, std::clamp(x.a, -a, a), 0};
  const Ramp r = plan_ramp(y.v, y.a, 0, a, j);
  if (r.t1 > 0) y = advance(y, r.dir * r.j, r.t1);
  if (r.t2 > 0) y = advance(y, 0, r.t2);
  if (r.t3 > 0) y = advance(y, -r.dir * r.j, r.t3);
  return y.s;
}

// rt-safe
double JerkGuard::brake_distance_built(const ProfileState& x, double a, double j) {
  return BrakeRamp({0, x.v, x.a, 0}, a, j).d_stop;
}

// rt-safe
PathStep JerkGuard::anchored_brake(const ProfileState& now, double a, double j, double stop_mm) const {
  const ProfileState x{0, now.v, now.a, 0};
  if (!(stop_mm > 0) || !(j > 0) || !std::isfinite(j) || !(a > 0)) return certified_brake(now, a, j);
  // Braking too hard already (it would reverse): the plain ramp, as certify() would not take it.
  if (x.a < 0 && x.v < x.a * x.a / (2 * j)) return certified_brake(now, a, j);
  // Only past the point by more than a ten-thousandth of a cycle's jerk (j·dt³): the certificate's
  // own slack is a touch (1e-12 mm), and a step this small is lost in the rounding of the positions.
  if (!(brake_distance(x, a, j) > stop_mm + std::max(kTouch_mm, 1e-4 * j * dt_ * dt_ * dt_))) return certified_brake(now, a, j);
  // The distance falls as J rises (the ramp ends sooner): bisect in [j, j·(1 + kRel)].
  double lo = j, hi = j * (1 + kRel);
  if (brake_distance(x, a, hi) > stop_mm) return certified_brake(now, a, hi);  // the most the slack allows
  for (int it = 0; it < 40 && lo < hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (brake_distance(x, a, mid) > stop_mm ? lo : hi) = mid;
  }
  return certified_brake(now, a, hi);
}

// rt-safe
GuardVerdict JerkGuard::check_step(const PathStep& step) const {
  GuardVerdict v;
  Cursor c{0};
  check(c, 0, v_now_, step, v);
  return v;
}

GuardVerdict JerkGuard::verify(const PathStep& step, const GuardMode& mode) const {
  GuardVerdict v;
  Cursor c{0};
  if (!check(c, 0, v_now_, step, v) || v.failed()) return v;
  if (mode.certify) {
    std::size_t gate = 0;       // the first block of far lower acceleration the ramp entered (0: none)
    std::size_t jerk_gate = 0;  // the first block of far lower jerk it or π's scan reached (0: none)
    const Cert r = certify(step.x, step.x.s, c, v, mode.gate ? &gate : nullptr, mode.gate && mode.jerk_gate ? &jerk_gate : nullptr);
    if (r != Cert::Unknown) return v;
    for (const std::size_t k : {gate, jerk_gate != gate ? jerk_gate : 0}) {
      GuardVerdict g;  // v as check() left it: it writes a verdict only to fail
      if (k > 0 && certify_gated(step.x, step.x.s, c, k, g) == Cert::Safe) return g;
    }
    if (!mode.simulate && !(v.brake_s <= mode.simulate_up_to_s)) {  // refused, with the hint of where the ramp breaks a limit
      if (!v.failed()) fail(v, true, 0, 0, false);
      return v;
    }
    v = GuardVerdict{};
  }
  v.simulated = true;
  double p = step.x.s;
  ProfileState x = step.x;
  std::size_t tried = n_;  // the block where the closed-form tail was last tried
  for (int i = 0; i < kMaxBrakeCycles; ++i) {
    if (std::abs(x.v) <= 1e-12 && std::abs(x.a) <= 1e-9) return v;  // at rest: it may stay
    if (mode.closed_form && c.k != tried) {  // its conditions change only with the blocks ahead
      tried = c.k;
      if (tail_safe(x, p, c)) return v;
    }
    const PathStep b = brake(x, p, c);
    if (!check(c, p, x.v, b, v) || v.failed()) return v;
    p += b.x.s;
    x = b.x;
  }
  v.hard_ok = false;
  return v;
}

}  // namespace softmc::motion
