// The jerk follower's safety check: one-cycle steps with their bounds, and the simulated fallback brake.
#include "motion/interp/jerk_guard.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>

#include "motion/profile/jerk_path.hpp"
#include "motion/profile/jerk_ramp.hpp"

namespace softmc::motion {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kRel = 1e-9;       // relative slack of every limit comparison (rounding)
constexpr double kAbs = 1e-9;       // absolute slack (mm/s, mm/s², mm/s³)
constexpr double kTouch_mm = 1e-12;  // a cycle ending this near a block's end lands on the next block's start
                                     // (the interpolator passes the block a cycle later, at s ≥ length)
constexpr int kMaxBrakeCycles = 200000;  // 200 s of braking at 1 ms: beyond, the state is refused

bool over(double x, double lim) { return x > lim * (1 + kRel) + kAbs; }

// Integrates phases of constant jerk over one cycle and keeps the bounds reached within it.
struct Cycle {
  PathStep st;
  double left;
  Cycle(const ProfileState& x0, double dt) : left(dt) {
    st.x = x0;
    st.x.s = 0;
    st.x.j = 0;
    st.a_abs = std::abs(x0.a);
    st.v_peak = st.v_min = x0.v;
  }
  void take(const ProfileState& y) {
    st.v_peak = std::max(st.v_peak, y.v);
    st.v_min = std::min(st.v_min, y.v);
    st.a_abs = std::max(st.a_abs, std::abs(y.a));
  }
  // (Inlined: four calls a ramp_cycle; out of line they cost ~85 instructions a blended cycle.)
  __attribute__((always_inline)) void phase(double dur, double j) {
    if (left <= 0 || !(dur > 0)) return;
    const double t = std::min(dur, left);
    if (j != 0) {  // the speed's extreme inside the phase, where a crosses 0
      const double ts = -st.x.a / j;
      if (ts > 0 && ts < t) take(advance(st.x, j, ts));
    }
    st.x = advance(st.x, j, t);
    st.j_abs = std::max(st.j_abs, std::abs(j));
    left -= t;
    take(st.x);
  }
  void hold_rest(double v, double a) {  // the rest of the cycle at (v, a = 0) exactly
    st.x.v = v;
    st.x.a = a;
    st.x.j = 0;
    if (left > 0) st.x.s += v * left;
    left = 0;
    take(st.x);
  }
};

// The phases of constant jerk of the ramp from x towards speed vt, as ramp_cycle follows it: |x.a|
// first brought within a_max at j_max when it is beyond (phase 0), then plan_ramp's three phases
// from there (|a| clamped to a_max against rounding).
struct RampPhases {
  std::array<double, 4> jerk{}, dur{};
};
// (Inlined: returned through memory, its phases cost ~40 instructions a call more.)
__attribute__((always_inline)) inline RampPhases ramp_phases(const ProfileState& x, double vt, double a_max,
                                                             double j_max) {
  RampPhases ph;
  ProfileState z{0, x.v, x.a, 0};
  if (std::abs(x.a) > a_max) {
    ph.jerk[0] = x.a > 0 ? -j_max : j_max;
    ph.dur[0] = (std::abs(x.a) - a_max) / j_max;
    z = advance(z, ph.jerk[0], ph.dur[0]);
  }
  z.a = std::clamp(z.a, -a_max, a_max);
  const Ramp r = plan_ramp(z.v, z.a, vt, a_max, j_max);
  ph.jerk = {ph.jerk[0], r.dir * r.j, 0, -r.dir * r.j};
  ph.dur = {ph.dur[0], r.t1, r.t2, r.t3};
  return ph;
}

// The ramp to rest from x with limits a, j, as ramp_cycle follows it: |x.a| first brought within a
// at jerk j when it is beyond (phase 0), then plan_ramp's three phases; the distance to rest, the
// largest speed on it, and the largest |a| from each phase on.
struct BrakeRamp {
  static constexpr int kPhases = 4;
  std::array<ProfileState, kPhases> at;  // state at the start of each phase, s from x
  std::array<double, kPhases> jerk, dur;
  // Largest |a| from the start of phase i to rest: filled only when the ramp has a phase 0 (|x.a|
  // above a: the certificate reads it, and a_after, only while phase 0 lasts), else left as it was.
  std::array<double, kPhases + 1> a_from;
  double d_stop, v_up;

  BrakeRamp(const ProfileState& x, double a, double j) { build(x, a, j); }
  // Left unset, to be built before it is read (the certificate's: ~40 instructions a walk less).
  struct Unset {};
  explicit BrakeRamp(Unset) {}
  // Rebuilt in place (the certificate's walk rebuilds it at each lowered limit it must account for).
  void build(const ProfileState& x, double a, double j) {
    const RampPhases ph = ramp_phases(x, 0, a, j);
    ProfileState y{0, x.v, x.a, 0};
    v_up = x.v;
#pragma GCC unroll 4
    for (int i = 0; i < kPhases; ++i) {
      at[i] = y;
      jerk[i] = ph.jerk[i];
      dur[i] = ph.dur[i] > 0 ? ph.dur[i] : 0.0;
      if (dur[i] > 0) {
        // The speed peaks where a falls through 0: v + a²/2|j| (a > 0, jerk < 0).
        if (y.a > 0 && jerk[i] < 0 && -y.a / jerk[i] < dur[i]) v_up = std::max(v_up, y.v - y.a * y.a / (2 * jerk[i]));
        y = advance(y, jerk[i], dur[i]);
      }
      if (i == 0) y.a = std::clamp(y.a, -a, a);  // as ramp_cycle clamps it
      v_up = std::max(v_up, y.v);
    }
    d_stop = y.s;
    if (!(dur[0] > 0)) return;
    a_from[kPhases] = 0;
#pragma GCC unroll 4
    for (int i = kPhases - 1; i >= 0; --i) {
      const double a_end = i + 1 < kPhases ? std::abs(at[i + 1].a) : 0.0;
      a_from[i] = std::max(std::max(a_from[i + 1], a_end), dur[i] > 0 ? std::abs(at[i].a) : 0.0);
    }
  }

  // The largest |a| on the ramp from distance d on (|a| is linear in time within a phase: the
  // larger of its value at d and everything after).
  double a_after(double d) const {
    if (d <= 0) return a_from[0];
    for (int i = 0; i < kPhases; ++i) {
      if (!(dur[i] > 0)) continue;
      const ProfileState end = advance(at[i], jerk[i], dur[i]);
      if (end.s < d) continue;
      double lo = 0, hi = dur[i];  // s(t) = d: s rises with t (v ≥ 0 on a brake)
      for (int it = 0; it < 60 && hi - lo > 1e-15; ++it) {
        const double mid = 0.5 * (lo + hi);
        (advance(at[i], jerk[i], mid).s < d ? lo : hi) = mid;
      }
      const double a_d = std::abs(advance(at[i], jerk[i], lo).a);  // lo: just before d
      return std::max({a_d, std::abs(i + 1 < kPhases ? at[i + 1].a : 0.0), a_from[i + 1]});
    }
    return 0;
  }

// Distance from x where the speed, past its peak, has fallen to `cap` (0 when it never exceeds it):
  // beyond it the speed stays at or below cap.
  double reach_speed(double cap) const {
    if (v_up <= cap) return 0;
#pragma GCC unroll 4
    for (int i = 0; i < kPhases; ++i) {
      const ProfileState& y = at[i];
      const double j = jerk[i], t_end = dur[i];
      if (!(t_end > 0)) continue;
      // The speed falls from t0 on in this phase (a ≤ 0 there); before t0 it rises.
      double t0 = 0;
      if (y.a > 0) {
        if (!(j < 0) || -y.a / j >= t_end) continue;
        t0 = -y.a / j;
      }
      if (advance(y, j, t_end).v > cap) continue;
      const ProfileState y0 = advance(y, j, t0);
      if (y0.v <= cap) return y0.s;
      // v(t) = y0.v + y0.a·t + j·t²/2 = cap on (0, t_end − t0], v falling there: its one root.
      const double c = y0.v - cap, b = y0.a;
      double t;
      if (j == 0) {
        t = -c / b;
      } else {
        const double disc = std::sqrt(std::max(0.0, b * b - 2 * j * c));
        const double q = -0.5 * (b + (b >= 0 ? disc : -disc));  // roots q / (j/2) and c / q
        const double r1 = q / (0.5 * j), r2 = q != 0 ? c / q : r1;
        const double lo = std::min(r1, r2), hi = std::max(r1, r2);
        t = lo >= 0 ? lo : hi;
      }
      t = std::clamp(t, 0.0, t_end - t0);
      return advance(y0, j, t).s;
    }
    return d_stop;
  }
};

// BrakeRamp(x, a, j).d_stop for x.v ≥ 0 and x.a ≥ 0 (a, j > 0, finite) in closed form, up to
// rounding: a few operations where building the ramp's phases costs about 370 instructions. From
// x.a ≥ 0 the ramp runs at jerk −j until a has fallen through 0 (phase 0 and the first phase join):
// the rise to its peak speed w = v + a0²/2j over v·t + a0·t²/3 (t = a0/j), then the ramp to rest
// from (w, 0), symmetric in speed about its middle, so w times half its duration: w·(w/a + a/j)/2
// where it reaches a (w·j ≥ a²), else w·√(w/j).
__attribute__((always_inline)) inline double brake_distance_rising(const ProfileState& x, double a, double j) {
  const double t = x.a / j;
  const double w = x.v + 0.5 * x.a * t;
  const double rise = t * (x.v + x.a * t / 3);
  const double fall = w * j >= a * a ? 0.5 * w * (w / a + a / j) : w * std::sqrt(w / j);
  return rise + fall;
}
// The half-width of the bracket the certificate puts around it, relative: the two roundings differ
// by at most 1.1e-15 of the distance over the jerk benchmarks and test suites (phase 0 included).
constexpr double kClosedFormRel = 1e-9;
}  // namespace

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

// rt-safe
void JerkGuard::index_through(std::size_t k) const {
  const std::size_t last = std::min(k, n_ - 1);
  while (built() <= last) index_block();
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

bool JerkGuard::fail(GuardVerdict& v, bool hard, double at, double u, bool stop) const {
  if (!v.failed()) {
    v.fail_at_mm = at;
    v.fail_u_mm_s = u;
    v.stop_binds = stop;
  }
  (hard ? v.hard_ok : v.soft_ok) = false;
  return false;
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

// rt-safe. The certificate (see the header) for the rest from x (at p, in block c.k):
//  - its limits A, J: A the least acceleration of the blocks the ramp to rest enters, J the least
//    jerk of those and of the blocks π's scans would look at beyond (so that it accepts no more than
//    π would: greedy steps π refuses end up slower). Lowering them lengthens the ramp, so the walk
//    goes on from where it is with the new distance until it covers the ramp; an exact stop or the
//    window's end ends it (the ramp may reach it at rest, never cross it);
//  - |x.a| may be above A: the ramp first brings it down at J (as ramp_cycle does), and a block
//    entered meanwhile must allow the |a| from where it is entered on;
//  - that ramp, known in closed form, against every block it enters, in order of distance: at every
//    junction no faster than the junction allows, and under every cap and soft cap of a block from
//    where it enters it (past its peak the speed only falls: where it has fallen to a cap it stays
//    under it); no reversal. |jerk| ≤ J all along by construction.
// Safe: v.cert_a, v.cert_j are set. Fails: v holds the first broken limit as the simulation would
// report it, given only when π is that same ramp (uniform: every block π's brakes would scan has
// the limits of the block the ramp starts in, so its anticipation and jerk never differ). Otherwise
// Unknown (v then holds the first broken limit as a hint, and v.brake_s the ramp's duration).
JerkGuard::Cert JerkGuard::certify(const ProfileState& x0, double p, const Cursor& c, GuardVerdict& v,
                                   std::size_t* gate, std::size_t* jerk_gate, double a_init, double j_init) const {
  const ProfileState x{0, x0.v, x0.a, 0};
  v.brake_s = kInf;
  if (!(x.v >= 0)) return Cert::Unknown;
  const auto reach = [](double d) { return d * (1 + kRel) + kAbs + kTouch_mm; };  // d with rounding
  const auto clear = [](double d_need, double d_have) { return d_need * (1 + kRel) + kAbs <= d_have; };
  double a = std::min(acc(c.k), a_init), j = std::min(jerk(c.k), j_init);
  BrakeRamp r{BrakeRamp::Unset{}};  // the ramp with the present (a, j), kept for the check below (built before it is read)
  bool r_built = false;
  double r_a = 0, r_j = 0;  // the limits r was built with
  const auto distance = [&] {
    if (!(j > 0) || !std::isfinite(j) || !(a > 0)) return -1.0;
    // Braking too hard already: it would reverse (by more than check() lets pass; a position-mode
    // stop ends exactly on v = a²/2J, up to rounding).
    if (x.a < 0 && x.v < x.a * x.a / (2 * j) - kAbs) return -1.0;
    r.build(x, a, j);  // |x.a| above a: first brought down to it at j
    r_built = true;
    r_a = a;
    r_j = j;
    return r.d_stop;
  };
  // The ramp's reach, reach(d), as of the limits of the last refresh (a_r, j_r): bracketed by
  // reach_lo ≤ reach(d) ≤ reach_hi. From x.a ≥ 0 a refresh takes the distance in closed form
  // (brake_distance_rising), a bracket a few ppb wide: a test it decides is decided as the ramp's
  // own distance would decide it, and only a block inside it builds the ramp (`sharpen`), closing
  // the bracket on reach(d). So every pass, stop, group and refresh of the walk below is the one
  // the built ramp gives, and the ramp is built once, at the end, for the limits the walk ends with
  // (instead of at the start and at each refresh: 5–6 times a walk on smoothed paths). From x.a < 0
  // every refresh builds it (the closed form would need phase 0's cases).
  const bool closed_form = g_.bracket && x.a >= 0;
  double a_r = a, j_r = j;
  double reach_lo = 0, reach_hi = 0;
  bool dirty = false;  // a or j lowered since the last refresh
  // (refresh inlined: called out of line, its calls cost more than the ramps it saves on blended
  // paths, about +120 instructions a cycle.)
  const auto refresh = [&]() __attribute__((always_inline)) {  // false: no ramp any more
    dirty = false;
    a_r = a;
    j_r = j;
    if (closed_form && j > 0 && std::isfinite(j) && a > 0) {
      const double dc = brake_distance_rising(x, a, j);
      if (dc > 0) {  // (at rest, dc = 0, the ramp is built: a relative bracket is no bracket there)
        reach_lo = reach(dc * (1 - kClosedFormRel));
        reach_hi = reach(dc * (1 + kClosedFormRel));
        return true;
      }
    }
    const double d = distance();
    if (!(d >= 0)) return false;
    reach_lo = reach_hi = reach(d);
    return true;
  };
  const auto sharpen = [&] {  // the bracket closed on reach(d) (valid limits, x.a ≥ 0: d > 0)
    ++g_.sharpened;
    r.build(x, a_r, j_r);
    r_built = true;
    r_a = a_r;
    r_j = j_r;
    reach_lo = reach_hi = reach(r.d_stop);
  };
  // `at` ≤ reach(d) + extra, as the built ramp would answer it.
  const auto reached = [&](double at, double extra) {
    if (at <= reach_lo + extra) return true;
    if (!(at <= reach_hi + extra)) return false;
    sharpen();
    return at <= reach_lo + extra;
  };
  if (!refresh()) {  // no ramp: about how long a brake would last, for verify()'s choice to simulate
    v.brake_s = std::abs(x.a) / j + 2 * std::sqrt(std::max(0.0, x.v) / j) + std::max(0.0, x.v) / a;
    return Cert::Unknown;
  }
  // π's brakes plan their jerk with every block up to their reach plus v_up·(|a|/J + 2·dt)
  // (brake()), |a| ≤ A: the certificate takes its jerk over the same range, so it accepts no more
  // than π would (greedy steps that π refuses end up slower). When all of those blocks have
  // exactly A and J (uniform), π is this same ramp.
  // (Its invariants in registers: x.a², 2·dt, the sign; recomputed at about 15 lowered limits a walk.)
  const double xa2 = x.a * x.a, two_dt = 2 * dt_, xv = x.v;
  const bool rising = x.a > 0;
  const auto scan = [xa2, two_dt, xv, rising](double a_, double j_) {
    return (rising ? xv + xa2 / (2 * j_) : xv) * (a_ / j_ + two_dt) + kTouch_mm;
  };
  bool uniform = true;
  double stop_at = kInf;  // from p: the first exact stop or the window's end the walk meets
  // Two cursors over the blocks after c.k: `ks` scans (jerk, stops, uniformity) up to the ramp's
  // reach plus π's scan; `ke` follows it over the blocks the ramp enters (acceleration). A lower
  // limit lengthens the ramp (but for a lower J while |a| above A is brought down: it keeps the
  // stronger deceleration longer), and both cursors go on from where they are.
  // The ramp's distance is brought up to date (`refresh`) only where the walk would otherwise stop:
  // one distance per extension of the walk, not one per block. reached(at, 0) tests `at` against
  // the ramp's reach as of the last refresh, scan_x = scan() as of the present limits. A whole
  // group of 8 (g.groups) is taken at once only where block by block the walk would go through it
  // without a refresh and end the same, its least limits taken
  // as block after block would take them (a review's differential fuzzer found the cases where
  // refreshing early, or entering on the way, changed the verdict:
  // PlannerJerk.CertificateGroupsGiveTheBlockByBlockVerdict).
  // (Plain locals, no closures over them: this walk is most of a smoothed path's cycle.)
  const GuardScratch& g = g_;
  constexpr std::size_t G = GuardScratch::kGroup;
  const bool groups = g.groups;
  // The index's arrays never move (sized once; indexing only writes their elements): read through
  // pointers taken once, not through the vectors at every block. Block k is at position o_ + k;
  // groups are aligned on positions: block k's group is (o_ + k) / G.
  const double* const acc_k = g.acc.data() + o_;
  const double* const jerk_k = g.jerk.data() + o_;
  const double* const u2_k = g.u2.data() + o_;
  const double* const gacc = g.group_acc.data();
  const double* const gjerk = g.group_min.data();
  const double* const gu2 = g.group_u2.data();
  const double* const st = g.start.data() + o_;  // block k's start from now: st[k] − base_, once indexed
  const std::size_t o = o_;
  std::size_t ks = c.k + 1, ke = c.k + 1;
  double scan_x = scan(a, j);
  bool scan_stale = false;
  double a_seen = a;  // the least acceleration of the blocks the scan has passed (c.k, c.k + 1, …, ks − 1)
  std::size_t indexed = built();  // built(), kept here: only the walk's index_through calls change it
  for (;; ++ks) {
    // Enter the blocks ke < ks (indexed: the scan has read them) that the ramp reaches.
    while (ke < ks) {
      // A whole group within reach as it stands (no refresh: one by one, the walk would enter it all
      // without one) is entered at once, taking its least acceleration, unless a gate may lie in it
      // (a block below half the running least: found one by one).
      if (groups && (o + ke) % G == 0 && ke + G <= ks &&
          (gacc[(o + ke) / G] >= 0.5 * a || !gate || *gate != 0)) {
        const double at = (st[ke + G - 1] - base_) - p;
        // With a refresh pending and the group's end beyond the reach as it stands, block by block
        // the walk would enter what it reaches and refresh at the first block it does not, with
        // limits no higher than now: refreshed now (cheap in closed form), a group it then reaches
        // whole it would enter whole too, and the limits, entries and later tests end the same (a
        // stale reach only defers a refresh: every test that fails on one refreshes when one is
        // pending).
        bool in = reached(at, 0);
        if (!in && dirty && closed_form) {
          if (!refresh()) return Cert::Unknown;
          in = reached(at, 0);
        }
        if (in) {
          if (gacc[(o + ke) / G] < a) {
            a = gacc[(o + ke) / G];
            dirty = scan_stale = true;
          }
          ke += G;
          continue;
        }
      }
      const double at = (st[ke] - base_) - p;
      if (!reached(at, 0)) {
        if (!dirty) break;
        if (!refresh()) return Cert::Unknown;
        if (!reached(at, 0)) break;
      }
      const double ak = acc_k[ke];
      if (ak < a) {
        if (gate && *gate == 0 && ak < 0.5 * a) *gate = ke;  // the first far lower one: certify_gated's
        a = ak;
        dirty = scan_stale = true;
      }
      ++ke;
    }
    if (scan_stale) scan_x = scan(a, j), scan_stale = false;
    if (groups && (o + ks) % G == 0 && ks + G <= n_) {
      if (ks + G > indexed) index_through(ks + G - 1), indexed = built();
      const std::size_t q = (o + ks) / G;
      // Scanned whole only where one by one the walk would go through it without a refresh (the
      // ramp's distance is not monotonic in J while |a| above A is being brought down, and a lower
      // A narrows π's scan, so a refresh or an entry on the way could end the walk inside it):
      //  - within: the whole group within the ramp's reach as it stands, the entry cursor here:
      //    the walk enters every block of it too (its least limits), the gates aside (a block below
      //    half the running least acceleration or jerk: one by one, as the loops find them);
      //  - quiet: no refresh pending and no block in it below the limits so far, its last block
      //    within π's scan: the walk scans it all and changes nothing.
      if (gu2[q] > 0) {
        const double at = (st[ks + G - 1] - base_) - p;
        const bool lower = gacc[q] < a || gjerk[q] < j;
        const bool within = ke == ks && (gacc[q] >= 0.5 * a || !gate || *gate != 0) &&
                            (gjerk[q] >= 0.5 * j || !jerk_gate || *jerk_gate != 0) && reached(at, 0);
        if (within || (!lower && !dirty && reached(at, scan_x))) {
          if (lower) {
            uniform = false;
            a = std::min(a, gacc[q]);
            j = std::min(j, gjerk[q]);
            dirty = scan_stale = true;
          } else {
            for (std::size_t i = ks; uniform && i < ks + G; ++i) uniform = acc_k[i] == a && jerk_k[i] == j;
          }
          if (within) ke = ks + G;
          a_seen = std::min(a_seen, gacc[q]);
          ks += G - 1;
          continue;
        }
        // scanned: a group only π's scan reaches that lowers the jerk (the entry cursor behind it).
        // Block by block the walk would scan it all without a refresh ending the walk inside it when
        // its last block lies within the reach and scan of every state the walk can pass through on
        // the way: the reach only grows as the limits fall (closed form, x.a ≥ 0), the jerk only
        // falls, and the acceleration never falls below the least of the blocks seen up to the
        // group's end (a_seen, the group's): scan(a, j) ≥ scan(that least, j now). Entries and
        // refreshes the group's blocks would have caused are then made by the loops that follow, to
        // the same fixpoint (PlannerJerk.CertificateGroupsGiveTheBlockByBlockVerdict).
        // Likewise a group that lowers nothing while a refresh is pending (the quiet case needs none
        // pending: a refresh there may narrow the scan). Either way `uniform` is false already or
        // now: a pending refresh means a block of other limits was met.
        if (closed_form && (gjerk[q] < j || dirty) && gjerk[q] > 0 &&
            (gjerk[q] >= 0.5 * j || !jerk_gate || *jerk_gate != 0) &&
            at <= (reach_lo + scan(std::min(a_seen, gacc[q]), j)) * (1 - 1e-12)) {
          uniform = false;
          if (gjerk[q] < j) j = gjerk[q], dirty = scan_stale = true;
          a_seen = std::min(a_seen, gacc[q]);
          ks += G - 1;
          continue;
        }
      }
    }
    if (ks >= indexed) index_through(ks), indexed = built();  // its start, and its limits when it is inside the window
    const double ss = (st[ks] - base_) - p;
    if (!reached(ss, scan_x)) {
      if (!dirty) break;
      if (!refresh()) return Cert::Unknown;
      if (!reached(ss, scan_x)) break;
    }
    if (ks >= n_ || u2_k[ks] <= 0) {
      stop_at = ss;
      break;
    }
    const double jk = jerk_k[ks];
    a_seen = std::min(a_seen, acc_k[ks]);
    if (acc_k[ks] != a || jk != j) uniform = false;
    if (jk < j) {
      // A far lower jerk is a gate too, where only π's scan reaches it: a ramp from a hard brake
      // on a line eased at a short corner's jerk reverses, so the single ramp cannot decide.
      if (jerk_gate && *jerk_gate == 0 && jk < 0.5 * j) *jerk_gate = ks;
      j = jk;
      dirty = scan_stale = true;
    }
  }
  // The blocks scanned last that the ramp reaches: the entry loop above once more, written out
  // again because a closure shared by both places keeps a, j, d and the cursors in memory (tried:
  // +16 % instructions per smoothed cycle).
  while (ke < ks) {
    const double at = (st[ke] - base_) - p;
    if (!reached(at, 0)) {
      if (!dirty) break;
      if (!refresh()) return Cert::Unknown;
      if (!reached(at, 0)) break;
    }
    if (acc_k[ke] < a) {
      if (gate && *gate == 0 && acc_k[ke] < 0.5 * a) *gate = ke;
      a = acc_k[ke];
      dirty = true;
    }
    ++ke;
  }
  // The ramp of the limits the walk ends with (built already where the last refresh or a bracket
  // built it for them; distance() refuses the limits a refresh would have refused).
  if (!(r_built && r_a == a && r_j == j) && !(distance() >= 0)) return Cert::Unknown;
  v.brake_s = r.dur[0] + r.dur[1] + r.dur[2] + r.dur[3];
  const auto broken = [&](bool hard, double at, double u, bool stop) {
    fail(v, hard, p + at, u, stop);  // the simulation's answer when uniform, else a hint
    return uniform ? Cert::Fails : Cert::Unknown;
  };
  // Every block the ramp enters (all indexed: the scan went beyond them), one by one, or a group
  // of 8 at once where all its caps and junction speeds are at least the ramp's peak v_up, none
  // of them a stop, beyond where |a| is brought down (phase 0): each block's test passes there.
  const double v_up2 = r.v_up * r.v_up * (1 + 1e-12);
  const double phase0_end = r.dur[0] > 0 ? reach(r.at[1].s) : -kInf;
  const double reach_stop = reach(r.d_stop);
  // reach_speed of the last cap asked: blocks in a row often share a cap or junction speed (a
  // polyline's identical corner blends), and it costs ~110 instructions where the ramp passes it.
  double memo_cap = std::numeric_limits<double>::quiet_NaN(), memo_d = 0;
  const auto reach_speed = [&](double cap) {
    if (r.v_up <= cap) return 0.0;  // (reach_speed's own first answer)
    if (!(cap == memo_cap)) memo_cap = cap, memo_d = r.reach_speed(cap);
    return memo_d;
  };
  for (std::size_t k = c.k;;) {
    if (k > indexed) index_through(k - 1), indexed = built();  // (this->start(k), as in the walk)
    const double start = (st[k] - base_) - p;
    if (!(start <= reach_stop)) break;
    if (k > c.k && start >= stop_at) {  // an exact stop or the window's end: reached at rest, never crossed
      // Only the rounding of a touch, not a fixed 1e-9 mm nor a share of the distance: the follower
      // may run this brake for hundreds of cycles (it is its last resort), and it ends past its
      // point by the slack it was accepted with, a position step of several cycles' jerk where
      // j·dt³ is near its floor (motion::kMinJerkStep_mm; a review found 1.075× with 1e-9 of the
      // distance, accepted 0.066 mm before the stop).
      if (r.d_stop > start + kTouch_mm) return broken(true, start, 0, true);
      break;
    }
    if (g.groups && k > c.k && (o + k) % G == 0 && k + G <= n_ && start >= kAbs && start > phase0_end) {
      if (k + G > indexed) index_through(k + G - 1), indexed = built();
      const std::size_t q = (o + k) / G;
      if ((st[k + G - 1] - base_) - p < stop_at) {
        // Every cap and junction speed at least the ramp's peak; or where the speed has fallen to
        // the group's least cap or junction speed before the group starts (past its peak the
        // speed only falls, and it falls to a higher cap no later): each block's test passes
        // (with room for reach_speed's rounding between caps).
        const bool above = g.group_u2[q] > v_up2 && g.group_cap[q] >= r.v_up;
        if (above || (g.group_u2[q] > 0 &&
                      clear(reach_speed(std::min(std::sqrt(g.group_u2[q]), g.group_cap[q])) * (1 + 1e-9) + 1e-12, start))) {
          k += G;
          ++g_.groups_skipped;
          continue;
        }
      }
    }
    if (k > c.k) {
      // |x.a| above A comes down at J first: a block entered meanwhile must allow the |a| from
      // where it is entered on (A itself it allows: A is the least of the blocks entered).
      // (Only while phase 0 lasts: after it |a| ≤ A.)
      if (start <= phase0_end && acc_k[k] < r.a_from[0] && acc_k[k] < r.a_after(start * (1 - kRel) - kAbs))
        return Cert::Unknown;
      // (v_up² clearly below the junction's u²: reach_speed(u) is 0, no square root needed.)
      if (!(v_up2 < u2_k[k]) || !clear(0, start)) {
        const double u = std::sqrt(u2_k[k]);
        if (!clear(reach_speed(u), start)) return broken(true, start, u, false);
      }
    }
    const double here = std::max(start, 0.0);
    const auto over_cap = [&](double cap) { return k == c.k ? r.v_up > cap : !clear(reach_speed(cap), start); };
    if (over_cap(hard(k))) return broken(true, here, hard(k), false);
    if (over_cap(soft(k))) return broken(false, here, soft(k), false);  // the front's relaxed to v_now
    ++k;
  }
  v.cert_a = a;
  v.cert_j = j;
  return Cert::Safe;
}

namespace {
// The ramp from x to speed w (< x.v or not) with limits a, j as ramp_cycle follows it: its distance
// to w (where a = 0) and the largest and least speed on it.
struct RampTo {
  double d = 0, v_up = 0, v_min = 0;
};
RampTo ramp_to(const ProfileState& x, double w, double a, double j) {
  const RampPhases ph = ramp_phases(x, w, a, j);
  ProfileState y{0, x.v, x.a, 0};
  RampTo r{0, x.v, x.v};
  for (int i = 0; i < 4; ++i) {
    const double dur = ph.dur[i], jk = ph.jerk[i];
    if (dur > 0) {
      if (jk != 0 && -y.a / jk > 0 && -y.a / jk < dur) {
        const double v = advance(y, jk, -y.a / jk).v;
        r.v_up = std::max(r.v_up, v);
        r.v_min = std::min(r.v_min, v);
      }
      y = advance(y, jk, dur);
    }
    if (i == 0) y.a = std::clamp(y.a, -a, a);
    r.v_up = std::max(r.v_up, y.v);
    r.v_min = std::min(r.v_min, y.v);
  }
  r.d = y.s;
  return r;
}
}  // namespace

// rt-safe. Where the ramp to rest cannot pass a block whose acceleration is far below the ones
// before it (a short curve between lines: under the jerk limit its tangential acceleration is a
// fraction of theirs), every ramp to rest with one A would brake at that block's A from far ahead,
// or stop before it. Likewise a block whose jerk is far below theirs (the same short curve, 3 000
// against a line's 10 000 mm/s³): a ramp with that jerk cannot ease a brake taken on the line at the
// line's jerk without reversing, wherever it would meet the block. The gated certificate brakes in
// two stages instead:
//
//   x ──ramp to w (A1, J1)──► w ── cruise ──┃ gate: block k ──ramp to rest (certify, from w, a = 0)──► 0
//
// A1, J1 the least of the blocks before the gate, w the speed the gate block allows at its start;
// the first ramp must reach w before the gate, never below w on the way, and keep under every cap
// and junction up to it, and the second is the certificate from (w, a = 0) one cycle of cruising
// past the gate (the fallback starts it in the first cycle after the gate; a ramp started earlier on
// the same blocks is slower everywhere and keeps the same limits). Safe only when both are.
// The first ramp need only end before the gate, not a cycle before it: its last cycle, at J1, may
// end inside the gate block whose jerk is lower. The motion keeps every limit in continuous time
// (the ramp's jerk is J1 only while it is still on the blocks before the gate, and a = 0 from where
// it reaches w), as with the acceleration gate; a cycle-by-cycle check() of that last cycle would
// count J1 against the gate block and refuse it (a review's note, stop 21).
JerkGuard::Cert JerkGuard::certify_gated(const ProfileState& x0, double p, const Cursor& c, std::size_t k,
                                         GuardVerdict& v) const {
  const ProfileState x{0, x0.v, x0.a, 0};
  if (!(x.v > 0) || !(k > c.k) || k >= n_) return Cert::Unknown;
  double a1 = acc(c.k), j1 = jerk(c.k);
  // The front block's soft cap as it is, not relaxed to the present speed: the first stage may
  // cruise at w, and only a ramp down is allowed above it (after an override drop the plain
  // certificate's ramp to rest decides).
  double cap = std::min(hard(c.k), need(c.k).soft[o_ + c.k]);
  for (std::size_t i = c.k + 1; i < k; ++i) {
    if (u2(i) <= 0) return Cert::Unknown;  // a stop before the gate
    a1 = std::min(a1, acc(i));
    j1 = std::min(j1, jerk(i));
    cap = std::min({cap, hard(i), soft(i), std::sqrt(u2(i))});
  }
  if (!(a1 > 0) || !(j1 > 0) || !std::isfinite(j1) || std::abs(x.a) > a1 || u2(k) <= 0) return Cert::Unknown;
  const double gate = start(k) - p;
  const double w = std::min({x.v, hard(k), soft(k), std::sqrt(u2(k)), cap});
  if (!(w > 0) || !(gate > 0)) return Cert::Unknown;
  const RampTo r = ramp_to(x, w, a1, j1);
  // The first stage never below w: from a state braking harder than the ramp to w, that ramp dips
  // and comes back up to w before the gate. Accepted, such states let the follower ease the brake
  // at a corner's lower jerk in one cycle and ride the dip to near rest in the next (surfacing.ngc).
  if (r.v_min < w * (1 - kRel) - kAbs || !(r.d * (1 + kRel) + kAbs <= gate) || over(r.v_up, cap)) return Cert::Unknown;
  // The second stage from one cycle past the gate, inside the gate block.
  const double p2 = start(k) + w * dt_;
  if (!(start(k + 1) > p2 + kTouch_mm)) return Cert::Unknown;
  GuardVerdict v2;
  if (certify(ProfileState{0, w, 0, 0}, p2, Cursor{k}, v2) != Cert::Safe) return Cert::Unknown;
  v.cert_a = a1;
  v.cert_j = j1;
  v.cert_w = w;
  v.cert_gate_mm = gate;
  v.cert_a2 = v2.cert_a;
  v.cert_j2 = v2.cert_j;
  v.brake_s = kInf;
  return Cert::Safe;
}

// rt-safe
GuardVerdict JerkGuard::check_step(const PathStep& step) const {
  GuardVerdict v;
  Cursor c{0};
  check(c, 0, v_now_, step, v);
  return v;
}

// rt-safe
GuardVerdict JerkGuard::certify_cruise(const PathStep& cruise) const {
  GuardVerdict v;
  Cursor c{0};
  if (!(cruise.x.a == 0 && cruise.j_abs == 0 && cruise.a_abs == 0 && cruise.x.v >= 0 && cruise.v_peak == cruise.x.v &&
        cruise.v_min == cruise.x.v)) {
    fail(v, true, 0, 0, false);
    return v;
  }
  if (!check(c, 0, v_now_, cruise, v) || v.failed()) return v;
  double a0 = acc(0), j0 = jerk(0);  // every block the stretch passes: c.k's in certify
  for (std::size_t k = 1; k < c.k; ++k) a0 = std::min(a0, acc(k)), j0 = std::min(j0, jerk(k));
  if (certify(cruise.x, cruise.x.s, c, v, nullptr, nullptr, a0, j0) != Cert::Safe) {
    if (!v.failed()) fail(v, true, 0, 0, false);
    v.cert_a = v.cert_j = 0;
  }
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
