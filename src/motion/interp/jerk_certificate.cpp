// The guard's certificates: the closed-form ramp to rest checked against every block it enters
// instead of simulating the fallback brake, its gated form, and cruise certificates (docs/planner.md,
// "Jerk", "Cruise certificates").
#include "motion/interp/jerk_guard.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "motion/interp/jerk_guard_detail.hpp"

namespace softmc::motion {

using namespace guard_detail;

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
}  // namespace softmc::motion
