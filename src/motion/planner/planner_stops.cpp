// The planner's limits near rest: blocks braked harder while a stop slows (limit_for_stop) and
// given back at rest, and blocks next to rest relimited to what they can reach (limit_to_reach).
#include "motion/planner/planner.hpp"

#include <algorithm>
#include <cmath>

#include "motion/planner/planner_detail.hpp"

namespace softmc::motion {

using namespace planner_detail;

// rt-safe. A stop (P-5), the path at speed v and acceleration a, s_front into the front block. Once
// a ≤ 0 the brake only slows it: no block it may still reach needs its limits above v. A Poly block's
// fixed split was derived for the speed it was asked for (its cap, from the feed at the highest
// override); derived again for v, the centripetal share and the curvature's share of the jerk take
// only what v needs and the tangential acceleration and jerk get the rest (a corner quintic's
// 3·v·a_t·κ alone: its acceleration × cap / v). Each such block within reach of the brake is raised
// by those ratios (what junction shares took off stays off, in proportion) and capped at v. Called
// every cycle of a stop, as v falls: the brake is certified with the limits of the present cycle,
// which the next only raises, so the fallback certified before stays safe. While a > 0 (v still
// rises a little) nothing changes. Lines, arcs and blend arcs keep theirs. At most kStopBlocks
// blocks: bounded work. A stop ends the program and drops the window, so nothing else runs on the
// blocks changed here. A feed hold or an enable drop brakes the same way and the blocks stay: at
// rest restore_limits() gives them back what they were planned with, and a hold released before
// rest leaves them capped at the speed they were derived for until then (sound: their limits hold
// up to that cap).
void Planner::limit_for_stop(double v, double a, double s_front) {
  auto& ring = queue_.ring_;
  // The blocks the follower plans with: an open back's jerk may still be lowered by the next
  // commit, which restore_limits() would undo.
  const std::size_t n = std::min(queue_.visible(), kStopBlocks);
  if (n == 0 || !(v > 0) || a > 0) return;
  // The blocks a brake with the least limits so far could reach: it lasts no longer than bringing
  // a to −A, then ramping down from v (each at least A, J), at speeds up to v.
  double a_min = kInf, j_min = kInf, walked = -s_front;
  std::size_t reach = 0;
  while (reach < n) {
    const Block& b = ring.at(reach++);
    a_min = std::min(a_min, b.a_mm_s2);
    j_min = std::min(j_min, b.j_mm_s3);
    walked += b.length;
    if (!std::isfinite(j_min) || !(a_min > 0) || !(j_min > 0)) return;  // a trapezoid block: its own law
    if (walked >= v * ((a_min - a) / j_min + v / a_min + a_min / j_min)) break;
  }
  bool changed = false;
  for (std::size_t k = 0; k < reach; ++k) {
    Block& b = ring.at(k);
    if (!(b.base_a > 0) || !(b.base_j > 0) || b.seg.kind != SegmentKind::Poly || !(v < b.v_cap_mm_s)) continue;
    const double a0 = b.stop_a0 > 0 ? b.stop_a0 : b.a_mm_s2, j0 = b.stop_a0 > 0 ? b.stop_j0 : b.j_mm_s3;
    double A = 0, J = 0;
    if (!relimit(b, v, a0, j0, A, J)) continue;
    if (!(b.stop_a0 > 0)) b.stop_v0 = b.v_cap_mm_s;
    b.stop_a0 = a0, b.stop_j0 = j0;
    b.v_cap_mm_s = b.v_split_mm_s = v;
    b.a_mm_s2 = A;
    b.j_mm_s3 = J;
    b.law = TangentLaw::constant(A);
    changed = true;
  }
  if (changed) {
    ring.touch();  // readers that keep what they derived from the blocks begin again
    limits_raised_ = true;
  }
}

// rt-safe. A block limit_for_stop changed is within the first kStopBlocks of the window then, and
// the front only moves on: the same bound finds it now.
void Planner::restore_limits() {
  if (!limits_raised_) return;
  limits_raised_ = false;
  auto& ring = queue_.ring_;
  const std::size_t n = std::min(ring.size(), kStopBlocks);
  bool changed = false;
  for (std::size_t k = 0; k < n; ++k) {
    Block& b = ring.at(k);
    if (!(b.stop_a0 > 0)) continue;
    b.v_cap_mm_s = b.v_split_mm_s = b.stop_v0;
    b.a_mm_s2 = b.stop_a0;
    b.j_mm_s3 = b.stop_j0;
    b.law = TangentLaw::constant(b.stop_a0);
    b.stop_a0 = b.stop_j0 = b.stop_v0 = 0;
    changed = true;
  }
  if (changed) ring.touch();
}

// rt-safe. A Poly block's limits derived again for the speed c (segment_limits as its own were, kept
// on the block: base_a, base_j, relimit_v, relimit_norm), applied to its limits a0, j0 by the ratio
// to what they were derived from, never lowered: what junction shares took off stays off, in
// proportion. false where the ratio is not finite.
bool Planner::relimit(const Block& b, double c, double a0, double j0, double& A, double& J, SegmentLimits* out) const {
  const SegmentLimits l = segment_limits(b.seg, limits_, config_.centripetal_share, std::min(c, b.relimit_v), b.relimit_norm);
  const double fa = l.a_max_mm_s2 / b.base_a, fj = l.j_max_mm_s3 / b.base_j;
  if (!std::isfinite(fa) || !std::isfinite(fj)) return false;
  A = a0 * std::max(1.0, fa);
  J = j0 * std::max(1.0, fj);
  if (out) *out = l;
  return true;
}

// rt-safe. A Poly block whose one end is at rest (an exact stop, or the window's start) never runs
// faster than it reaches from rest within its length; its limits, derived for its cap (the curvature
// terms of its jerk and acceleration budget take what that speed needs), are derived again for the
// speed c it reaches with them: the fixed point of the reach, by bisection, kept at the bracket's
// upper end (reach(c) < c). A cap it never meets, and more tangential acceleration and jerk for the
// ramp from or to rest (the rest of the budget: "Blocks at rest"). What junction shares took off
// stays off, in proportion (as limit_for_stop). Sound for a block a certified brake may already run
// through (the one before a new exact stop, which ended the window): every such brake comes to rest
// by the block's end within its old limits, so it stays below the reach of those, which c exceeds
// (the limits only rise as the cap falls). Bounded: 14 derivations, none where the block reaches its
// cap with the limits it has.
bool Planner::limit_to_reach(Block& b, bool from_rest, double d_more, double a_more, double j_more) const {
  if (!(b.base_a > 0) || !(b.base_j > 0) || b.seg.kind != SegmentKind::Poly || b.stop_a0 > 0 || !(b.length > 0)) return false;
  if (!std::isfinite(b.j_mm_s3) || !(b.v_cap_mm_s > 0)) return false;
  SegmentLimits l;
  double A = 0, J = 0;
  const auto at = [&](double c) { return relimit(b, c, b.a_mm_s2, b.j_mm_s3, A, J, &l); };
  double hi = b.v_cap_mm_s, lo = 0;
  // Entered from rest (from_rest): from any state the path can reach there, (v, a) with v within the
  // reach and a ≤ A (and ≤ ∛(6·x·J²) within x of rest, the jerk phase's), the guard's brake first
  // brings a down to 0 and gains a²/2J on the way; that too
  // must stay under the cap, or the guard would hold the path below its reach where it accelerates
  // (10 % slower on a run of tiny collinear pieces). Left at rest, every brake ends at that rest:
  // its speed never exceeds the reach itself.
  const auto reach = [&] {
    const double a = std::max(A, a_more), j = std::max(J, j_more), x = b.length + d_more;
    const double a_x = std::min(a, std::cbrt(6 * x * j * j));  // no more acceleration within x of rest
    return reach_from_rest(x, a, j) + (from_rest ? 0.5 * a_x * a_x / j : 0.0);
  };
  A = b.a_mm_s2, J = b.j_mm_s3;  // the limits only rise as the cap falls: reached already, nothing to do
  if (reach() >= hi || !at(hi) || reach() >= hi) return false;
  for (int it = 0; it < 12; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (!at(mid)) return false;
    (reach() < mid ? hi : lo) = mid;
  }
  if (!at(hi)) return false;
  b.v_cap_mm_s = b.v_split_mm_s = hi;
  b.a_mm_s2 = A;
  b.j_mm_s3 = J;
  b.law = TangentLaw::constant(A);
  b.base_a = l.a_max_mm_s2;  // what limit_for_stop's ratios start from
  b.base_j = l.j_max_mm_s3;
  b.relimit_v = std::min(b.relimit_v, hi);
  return true;
}
}  // namespace softmc::motion
