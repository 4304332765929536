// Helpers the planner's files share (planner.cpp, planner_curves.cpp, planner_stops.cpp,
// segment_limits.cpp): blend shapes, a block's limits, side times, peak distances, curvature steps.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "motion/planner/planner.hpp"

namespace softmc::motion::planner_detail {

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kMinLength_mm = 1e-9;  // shorter pieces carry no motion worth a block (see min_length_mm)

// The quintic corner blend's shape for a deflection δ (make_corner_blend): the control-point
// spacing (α, β) that, for a given distance of the midpoint from the corner, keeps the jerk term
// v³(κ² + dκ/ds) lowest, fitted over δ = 0.35 … 2.8 rad (docs/planner.md, "Corner blends").
inline void corner_blend_shape(double delta, double& alpha, double& beta) {
  beta = std::min(0.9, 0.18 + 0.2 * std::max(0.0, delta - 1.0) + 0.35 * std::max(0.0, delta - 2.2));
  alpha = 0.46 + 0.5 * beta;
}

// A corner blend between a and b: a rapid only between rapids, the slower feed, and the tags of
// the instructions it runs from (a's) into (b's last).
inline void join_blend(Block& blend, const Block& a, const Block& b) {
  blend.rapid = a.rapid && b.rapid;
  blend.feed_mm_s = std::min(a.feed_mm_s, b.feed_mm_s);
  blend.tag = a.tag;
  blend.tag_last = b.tag_last;
}

// A block's speed limits from its segment's (j: its path jerk, ∞ without a jerk limit), derived by
// segment_limits for the speed v_target with jerk_norm (kept on Poly blocks: limit_for_stop).
inline void set_limits(Block& b, const SegmentLimits& l, double j, double v_target = 0, bool jerk_norm = true) {
  b.a_mm_s2 = l.a_max_mm_s2;
  b.v_cap_mm_s = l.v_max_mm_s;
  b.v_split_mm_s = l.v_max_mm_s;
  b.j_mm_s3 = j;
  const bool keep = b.seg.kind == SegmentKind::Poly && !b.is_blend && std::isfinite(j) && v_target > 0;
  b.base_a = keep ? l.a_max_mm_s2 : 0;
  b.base_j = keep ? j : 0;
  b.relimit_v = keep ? v_target : 0;
  b.relimit_norm = jerk_norm;
}

// rt-safe. Least time to cover x mm from speed v0 at zero acceleration, within the acceleration
// `acc` and the speed vm, ending at the top of the profile (the acceleration back at 0): one side of
// a corner, from the corner to the middle of its line, for join()'s choice between a blend and a
// stop. The acceleration rises at j_near (the jerk of what the side starts from) and falls at j_far
// (∞: no jerk limit). Bisection on the speed gained: bounded, no allocation.
inline double side_time(double x, double v0, double vm, double acc, double j_near, double j_far) {
  if (!(x > 0)) return 0;
  struct Ramp {
    double t, s;
  };
  const double inv_j = 1 / j_near + 1 / j_far;
  // The ramp gaining dv: the acceleration up to its peak ap at j_near, held, down at j_far.
  const auto ramp = [&](double dv) {
    const double ap = dv > 0 ? std::min(acc, std::sqrt(2 * dv / inv_j)) : 0.0;
    const double t1 = ap / j_near, t3 = ap / j_far;
    const double t2 = ap > 0 ? std::max(0.0, dv - 0.5 * ap * ap * inv_j) / ap : 0.0;
    const double v1 = v0 + 0.5 * ap * t1, v2 = v1 + ap * t2;
    return Ramp{t1 + t2 + t3, v0 * t1 + ap * t1 * t1 / 6 + v1 * t2 + 0.5 * ap * t2 * t2 + v2 * t3 + ap * t3 * t3 / 3};
  };
  const double dv_max = std::max(0.0, vm - v0);
  const Ramp full = ramp(dv_max);
  if (full.s <= x) return full.t + (x - full.s) / std::max(vm, v0);
  double lo = 0, hi = dv_max;
  for (int k = 0; k < 24; ++k) {  // to 6e-8 of the speed gained: ample for a choice between two times
    const double mid = 0.5 * (lo + hi);
    (ramp(mid).s < x ? lo : hi) = mid;
  }
  return ramp(hi).t;
}

// rt-safe. Largest off(u) over u ∈ (0, 1) — the distance of a blend's point from the curves it
// joins: samples, then the peak refined between its neighbours (it sits where the nearest of the
// curves changes, a kink that samples alone miss by up to their spacing). A caller that only asks
// whether the peak is within `above` gets the first value found beyond it (the same answer, a
// fillet's bisection at about half the work). off(u, floor) is the distance at u where it exceeds
// floor, and any value from it up to floor where it does not (the samples only look for the peak: a
// caller may skip the curves it has not measured once a nearer one is within floor); the golden
// section asks for exact values (floor −1).
template <class Off>
inline double peak_distance(const Off& off, double above = kInf) {
  constexpr int kSamples = 32;
  double dev = 0;
  int peak = 1;
  for (int i = 1; i < kSamples; ++i) {
    const double e = off(static_cast<double>(i) / kSamples, dev);
    if (e > above) return e;
    if (e > dev) dev = e, peak = i;
  }
  // Golden-section search: the peak is the max of a rising and a falling distance (unimodal there);
  // 20 steps narrow the two sample spacings to 1e-4 of them.
  constexpr double kG = 0.6180339887498949;
  double lo = (peak - 1.0) / kSamples, hi = (peak + 1.0) / kSamples;
  double m1 = hi - kG * (hi - lo), m2 = lo + kG * (hi - lo);
  double e1 = off(m1, -1.0), e2 = off(m2, -1.0);
  for (int k = 0; k < 20; ++k) {
    dev = std::max({dev, e1, e2});
    if (dev > above) return dev;
    if (e1 < e2) {
      lo = m1;
      m1 = m2;
      e1 = e2;
      m2 = lo + kG * (hi - lo);
      e2 = off(m2, -1.0);
    } else {
      hi = m2;
      m2 = m1;
      e2 = e1;
      m1 = hi - kG * (hi - lo);
      e1 = off(m1, -1.0);
    }
  }
  return std::max({dev, e1, e2});
}

// The largest v² at which a step dk of the curvature vector (a junction of curvatures) moves every
// jerk-limited axis's acceleration by at most `share` of j_i·dt within one cycle (∞: no step).
inline double curvature_step_v2(const Vec& dk, const MachineLimits& lim, double share) {
  double v2 = kInf;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    const double d = std::abs(dk[i]);
    if (d < 1e-12 || !(lim.axis[i].j_max_mm_s3 > 0)) continue;
    v2 = std::min(v2, share * lim.axis[i].j_max_mm_s3 * lim.period_s / d);
  }
  return v2;
}

// rt-safe. The most speed a motion can have anywhere within L mm of rest (entering a block at rest,
// or leaving it at rest: time runs backwards) within the path acceleration A and jerk J: from rest at
// J up to A, then at A.
inline double reach_from_rest(double L, double A, double J) {
  const double d1 = A * A * A / (6 * J * J);
  if (L <= d1) {
    const double t = std::cbrt(6 * L / J);
    return 0.5 * J * t * t;
  }
  const double v1 = A * A / (2 * J);
  return std::sqrt(v1 * v1 + 2 * A * (L - d1));
}

// An arc that moves axes out of its plane: a helix (its speed term and its fillets differ).
inline bool is_helix(const Segment& g) { return g.kind == SegmentKind::Arc && core::norm(g.linear) > 1e-12; }

}  // namespace softmc::motion::planner_detail

namespace softmc::motion {

// rt-safe. A trapezoid block (no jerk limit) runs on its speed-dependent law, capped where the
// centripetal acceleration alone reaches an axis's limit; a jerk block keeps the fixed split, which
// the jerk follower's limits assume. a_mm_s2 and v_split_mm_s keep the split for either.
template <class MakeLaw>
void Planner::set_law(Block& b, const MakeLaw& make_law) const {
  if (std::isinf(b.j_mm_s3) && config_.speed_dependent_tangential) {
    const CurveLaw c = make_law();  // built only for the blocks that use it
    if (!c.law.full) {
      b.law = c.law;
      // Never cruise where no tangential acceleration is left: a hold or a stop must always brake.
      b.v_cap_mm_s = std::min(c.v_max_mm_s, std::sqrt(b.law.reserve_w(config_.tangential_reserve)));
      return;
    }
  }
  b.law = TangentLaw::constant(b.a_mm_s2);
}

}  // namespace softmc::motion
