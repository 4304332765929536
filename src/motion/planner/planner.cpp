// Look-ahead planning: validation, corner blends, junction limits, incremental backward pass.
#include "motion/planner/planner.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "motion/geometry/bezier.hpp"

namespace softmc::motion {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMinLength_mm = 1e-9;  // shorter pieces carry no motion worth a block (see min_length_mm)

// The quintic corner blend's shape for a deflection δ (make_corner_blend): the control-point
// spacing (α, β) that, for a given distance of the midpoint from the corner, keeps the jerk term
// v³(κ² + dκ/ds) lowest, fitted over δ = 0.35 … 2.8 rad (docs/planner.md, "Corner blends").
void corner_blend_shape(double delta, double& alpha, double& beta) {
  beta = std::min(0.9, 0.18 + 0.2 * std::max(0.0, delta - 1.0) + 0.35 * std::max(0.0, delta - 2.2));
  alpha = 0.46 + 0.5 * beta;
}

// A corner blend between a and b: a rapid only between rapids, the slower feed, and the tags of
// the instructions it runs from (a's) into (b's last).
void join_blend(Block& blend, const Block& a, const Block& b) {
  blend.rapid = a.rapid && b.rapid;
  blend.feed_mm_s = std::min(a.feed_mm_s, b.feed_mm_s);
  blend.tag = a.tag;
  blend.tag_last = b.tag_last;
}

// A block's speed limits from its segment's (j: its path jerk, ∞ without a jerk limit), derived by
// segment_limits for the speed v_target with jerk_norm (kept on Poly blocks: limit_for_stop).
void set_limits(Block& b, const SegmentLimits& l, double j, double v_target = 0, bool jerk_norm = true) {
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
double side_time(double x, double v0, double vm, double acc, double j_near, double j_far) {
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
double peak_distance(const Off& off, double above = kInf) {
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
double curvature_step_v2(const Vec& dk, const MachineLimits& lim, double share) {
  double v2 = kInf;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    const double d = std::abs(dk[i]);
    if (d < 1e-12 || !(lim.axis[i].j_max_mm_s3 > 0)) continue;
    v2 = std::min(v2, share * lim.axis[i].j_max_mm_s3 * lim.period_s / d);
  }
  return v2;
}
}  // namespace

const char* to_string(PlanResult r) {
  switch (r) {
    case PlanResult::Ok: return "ok";
    case PlanResult::QueueFull: return "planner queue full";
    case PlanResult::BadFeed: return "feed must be positive";
    case PlanResult::OutsideTravel: return "path leaves the axis travel (soft limits)";
    case PlanResult::Infeasible: return "segment cannot be planned within the axis limits";
  }
  return "?";
}

namespace {

// Jerk on a curved piece (docs/planner.md, "Jerk"): an axis with tangent share t_i and curvature
// share n_i sees  j_i = (j_t − v³κ²)·t_i + 3·v·a_t·κ·n_i  (+ v³·dκ/ds·n_i, zero on circles). The
// budget of an arc's j_max_i is split in fixed shares: j_t two fifths, v³κ² a fifth, 3·v·a_t·κ two
// fifths (a half, a quarter and a quarter until 2026-12-02: swept on the LinuxCNC programs, the
// acceleration along an arc is worth more than its cap now that the follower enters it at the cap).
// `amp_t` bounds |t_i|, `amp_n` bounds |n_i|.
constexpr double kArcTangentJerkShare = 0.4, kArcSpeedJerkShare = 0.2, kArcAccJerkShare = 0.4;
// On a curve in a coordinate plane T_i and N_i are one phase apart with amplitude 1 (T = (cos ψ,
// sin ψ), N = (−sin ψ, cos ψ)), so |j_i| ≤ √((|j_t| + v³κ²)² + (3·v·a_t·κ + v³·|κ'|)²), not the sum.
// On a circle κ' = 0: the three shares scaled by 1/√((⅖ + ⅕)² + (⅖)²) = 1.387 still keep every axis
// within j_max (the sum of the shares alone leaves 28 % of it unused there). A G-code arc whose end
// point is off its circle by the program's rounding is a slight spiral (Segment::dradius), |κ'| =
// κ²·ρ with ρ about |dradius|/length: the scale takes ρ·⅕ onto the last term. Helices and
// blends keep the sum.
// `speed_share`: the v³κ² share (kArcSpeedJerkShare, or less where the arc never runs as fast as
// that share allows: segment_limits).
double circle_jerk_scale(double rho, double speed_share = kArcSpeedJerkShare) {
  const double tv = kArcTangentJerkShare + speed_share, ac = kArcAccJerkShare + rho * speed_share;
  return 1 / std::sqrt(tv * tv + ac * ac);
}
// `k_speed` bounds the axis's speed term over v³: κ²·amp_t on a plane curve (it runs along T).
void curve_jerk(SegmentLimits& l, double j_axis, double amp_t, double k_speed, double scale = 1,
                double speed_share = kArcSpeedJerkShare) {
  if (!(j_axis > 0)) return;
  if (amp_t > 1e-12) l.j_max_mm_s3 = std::min(l.j_max_mm_s3, scale * kArcTangentJerkShare * j_axis / amp_t);
  if (k_speed > 0) l.v_max_mm_s = std::min(l.v_max_mm_s, std::cbrt(scale * speed_share * j_axis / k_speed));
}
// The 3·v·a_t·κ term of arcs and blend arcs, once the speed cap is known (kArcAccJerkShare of j_max;
// Poly curves take theirs in segment_limits, kPolyAccJerkShare at least).
constexpr double kPolyAccJerkShare = 0.2;
void curve_jerk_acc(SegmentLimits& l, double j_axis, double amp_n, double kappa, double scale = 1) {
  if (!(j_axis > 0) || !(kappa > 0) || amp_n < 1e-12 || !std::isfinite(l.v_max_mm_s)) return;
  l.a_max_mm_s2 = std::min(l.a_max_mm_s2, scale * kArcAccJerkShare * j_axis / (3 * l.v_max_mm_s * kappa * amp_n));
}

// An arc that moves axes out of its plane: a helix (its speed term and its fillets differ).
bool is_helix(const Segment& g) { return g.kind == SegmentKind::Arc && core::norm(g.linear) > 1e-12; }

}  // namespace

// rt-safe
double plane_arc_spiral(const Segment& g) {
  if (g.kind != SegmentKind::Arc || !(g.length > 0)) return kInf;
  if (is_helix(g)) return kInf;
  if (!(std::abs(g.dradius) <= 0.01 * std::min(g.radius, g.radius + g.dradius))) return kInf;
  // r runs linearly in the angle: |κ'| = κ²·|dr/dθ|/r·(1 + O(ε²)), ε = |dr/dθ|/r ≤ 1 %; |dr/dθ|/r ≤
  // |dradius|·r_max/(r_min·length·(1 − ε)), within twice |dradius|/length.
  return 2 * std::abs(g.dradius) / g.length;
}

// rt-safe
double jerk_left_by_step(const Vec& step_j, const Block& b, double s_end, double v_mm_s, const MachineLimits& lim) {
  double used = 0;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (lim.axis[i].j_max_mm_s3 > 0) used = std::max(used, step_j[i] / lim.axis[i].j_max_mm_s3);
  const double plain = std::max(0.0, 1 - used);
  const double rho = b.is_blend ? kInf : plane_arc_spiral(b.seg);
  if (!std::isfinite(rho) || !(b.j_mm_s3 > 0) || !std::isfinite(b.j_mm_s3)) return plain;
  const double kappa = core::norm(b.curvature(s_end));
  // The third difference of the setpoints spans three cycles around the junction (never past the
  // block's hard cap).
  const double v = std::min(v_mm_s + 3 * b.a_mm_s2 * lim.period_s, b.v_cap_mm_s);
  const double c_v = v * v * v * kappa * kappa, c_a = 3 * v * b.a_mm_s2 * kappa + rho * c_v;
  // Only the plane's axes carry the arc's jerk; each keeps what its own step leaves.
  double f = kInf;
  for (std::size_t i : {std::size_t{b.seg.axis0}, std::size_t{b.seg.axis1}}) {
    const double j_i = lim.axis[i].j_max_mm_s3;
    if (!(j_i > 0)) continue;
    const double left = std::max(0.0, j_i - step_j[i]);
    const double rest = left * left - c_a * c_a;
    f = std::min(f, rest > 0 ? (std::sqrt(rest) - c_v) / b.j_mm_s3 : 0.0);
  }
  return std::isfinite(f) ? std::clamp(f, 0.0, 1.0) : 1.0;
}

// rt-safe
SegmentLimits segment_limits(const Segment& g, const MachineLimits& lim, double cn, double v_target, bool jerk_norm) {
  SegmentLimits l{kInf, kInf, kInf};
  double& v = l.v_max_mm_s;
  double& a = l.a_max_mm_s2;
  if (g.kind == SegmentKind::Line) {
    // Each axis moves at v·|dir_i|: the path speed is limited by v_max_i / |dir_i|, likewise acceleration.
    for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
      const double d = std::abs(g.dir[i]);
      if (d < 1e-12) continue;
      v = std::min(v, lim.axis[i].v_max_mm_s / d);
      a = std::min(a, lim.axis[i].a_max_mm_s2 / d);
      if (lim.axis[i].j_max_mm_s3 > 0) l.j_max_mm_s3 = std::min(l.j_max_mm_s3, lim.axis[i].j_max_mm_s3 / d);
    }
  } else if (g.kind == SegmentKind::Arc) {
    // Arc: the tangent turns through every direction of the plane, so an in-plane axis may carry the
    // whole in-plane speed. An in-plane axis sees a_t·t_i + κv²·n_i; with a_t·inplane ≤ ct·a and
    // κv² ≤ cn·a its magnitude stays ≤ √(ct² + cn²)·a = a.
    const auto ab = g.arc_bounds();  // a spiral (end off the circle) bounds its tangent and curvature
    const double inplane = ab.inplane, kappa = ab.kappa;
    const double rho = plane_arc_spiral(g);  // ∞: a helix or a real spiral (the plain sum of the shares)
    // The speed term: v³κ² on a plane arc. A helix's in-plane axes run a circle at v·inplane, so
    // theirs is v³·|d³p/ds³| in the plane (ArcBounds::k_speed, κ²/inplane on a circular helix):
    // larger than v³κ² by 1/inplane, tenfold on a helix ten times steeper than its radius.
    const double k_speed = std::max(kappa * kappa, is_helix(g) ? ab.k_speed : 0.0);
    // An arc that will never be asked to run as fast as its curvature allows (v_target: the feed at
    // the highest override, under the axes' speeds) keeps of the centripetal share and of the speed
    // term's jerk share only what that speed needs, and gives the rest to the tangential
    // acceleration and jerk, as Poly pieces do (below): its cap is then that speed. The speed share
    // is taken for the smallest scale (the full share's), so the cap is never below v_target.
    double vt = v_target;
    for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
      const double d = i == g.axis0 || i == g.axis1 ? inplane : std::abs(g.linear[i]);
      if (d >= 1e-12) vt = std::min(vt, lim.axis[i].v_max_mm_s / d);
    }
    double speed_share = kArcSpeedJerkShare;
    if (std::isfinite(vt) && vt > 0 && k_speed > 0 && inplane >= 1e-12) {
      const double s0 = std::isfinite(rho) ? circle_jerk_scale(rho) : 1.0;
      double need = 0;
      for (std::size_t i : {std::size_t{g.axis0}, std::size_t{g.axis1}})
        if (lim.axis[i].j_max_mm_s3 > 0) need = std::max(need, vt * vt * vt * k_speed / (s0 * lim.axis[i].j_max_mm_s3));
      speed_share = std::min(kArcSpeedJerkShare, need);
    }
    // A helix or a real spiral keeps the plain sum of the shares: what the speed term does not take
    // goes to the other two in proportion (1 with the full share, as before).
    const double circle_scale = std::isfinite(rho) ? circle_jerk_scale(rho, speed_share)
                                                   : 1 / (kArcTangentJerkShare + speed_share + kArcAccJerkShare);
    for (std::size_t i : {std::size_t{g.axis0}, std::size_t{g.axis1}}) {
      if (inplane < 1e-12) break;
      const double am = lim.axis[i].a_max_mm_s2;
      const double cn_i = std::isfinite(vt) ? std::min(cn, kappa * vt * vt / am) : cn;
      v = std::min(v, lim.axis[i].v_max_mm_s / inplane);
      a = std::min(a, std::sqrt(std::max(0.0, 1 - cn_i * cn_i)) * am / inplane);
      if (kappa > 0) v = std::min(v, std::sqrt(cn_i * am / kappa));
      curve_jerk(l, lim.axis[i].j_max_mm_s3, inplane, k_speed, circle_scale, speed_share);
    }
    for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
      const double d = std::abs(g.linear[i]);
      if (d < 1e-12) continue;
      v = std::min(v, lim.axis[i].v_max_mm_s / d);
      a = std::min(a, lim.axis[i].a_max_mm_s2 / d);
      if (lim.axis[i].j_max_mm_s3 > 0) l.j_max_mm_s3 = std::min(l.j_max_mm_s3, lim.axis[i].j_max_mm_s3 / d);
    }
    if (inplane >= 1e-12)
      for (std::size_t i : {std::size_t{g.axis0}, std::size_t{g.axis1}})
        curve_jerk_acc(l, lim.axis[i].j_max_mm_s3, 1.0, kappa, circle_scale);
    l.jerk_scale = inplane >= 1e-12 ? circle_scale : 1.0;
  } else {
    // Poly (Bézier, NURBS, splines): per-axis largest tangent share and the largest curvature, both
    // sampled at construction. The tangent and normal of a general curve are not one phase apart as
    // on a circle, so the shares add: a_t·t_i ≤ (1 − cn)·a and κv² ≤ cn·a.
    // A piece whose curvature would let it go faster than it will ever be asked to (v_target: the
    // feed at the highest override, under the axes' speeds) keeps of cn, and of the curvature's
    // jerk share, only what that speed needs, and gives the rest to the tangential acceleration
    // and jerk: its cap is then that speed, which nothing asks to exceed.
    const Vec tmax = g.max_abs_tangent();
    const double kappa = g.max_curvature();
    const double k3 = g.poly.jerk_speed_term();
    double vt = v_target;
    for (std::size_t i = 0; i < core::kMaxAxes; ++i)
      if (tmax[i] >= 1e-12) vt = std::min(vt, lim.axis[i].v_max_mm_s / tmax[i]);
    for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
      const double d = tmax[i];
      if (d < 1e-12) continue;
      const auto& ax = lim.axis[i];
      v = std::min(v, ax.v_max_mm_s / d);
      const double cn_i = std::isfinite(vt) ? std::min(cn, kappa * vt * vt / ax.a_max_mm_s2) : cn;
      a = std::min(a, (1 - cn_i) * ax.a_max_mm_s2 / d);
      if (kappa > 0) v = std::min(v, std::sqrt(cn_i * ax.a_max_mm_s2 / kappa));
      // Jerk: the speed term v³·dκ/ds (κ the curvature vector: d/ds of κ·N is −κ²·T + κ'·N + κτ·B,
      // all three in max_dcurvature, so no κ² on top of it since 2026-12-02) takes up to half of
      // j_max, 3·v·a_t·κ a fifth, j_t·T_i the rest (three tenths or more). Half and a fifth rather than three eighths and an eighth (swept on the
      // LinuxCNC programs, docs/planner.md "Poly segments"): since the gated certificate the
      // follower brakes on the blocks before a curve and enters it at its cap, so the cap and the
      // acceleration along it are worth more than the curve's own tangential jerk.
      if (ax.j_max_mm_s3 > 0) {
        const double sk = std::isfinite(vt) ? std::min(0.5, vt * vt * vt * k3 / ax.j_max_mm_s3) : 0.5;
        l.j_max_mm_s3 = std::min(l.j_max_mm_s3, (1 - kPolyAccJerkShare - sk) * ax.j_max_mm_s3 / d);
        if (k3 > 0) v = std::min(v, std::cbrt(sk * ax.j_max_mm_s3 / k3));
      }
    }
    // 3·v·a_t·κ takes, per axis, what is left of j_max_i by the larger of two bounds that both hold
    // (the path's jerk vector is j_t·T + 3·v·a_t·κ⃗ + v³·dκ⃗/ds, with dκ⃗/ds = −κ²·T + n⃗, n⃗ ⟂ T and
    // |dκ⃗/ds| ≤ k3):
    //   sum:   |j_t|·T_i + v³·k3 + 3·v·a_t·κ ≤ j_i   (at least kPolyAccJerkShare is left by the above)
    //   norm:  an axis sees at most the vector's length, √((|j_t| + v³κ²)² + (3·v·a_t·κ + v³|n⃗|)²),
    //          whose largest value over the split of k3 between κ² and |n⃗| is
    //          v³·k3 + √(j_t² + (3·v·a_t·κ)²) ≤ j_i.
    // The norm is the larger where an axis carries most of the tangent: at a cap that takes half of
    // j_i, 3·v·a_t·κ gets 0.4 of it instead of 0.2.
    if (kappa > 0 && std::isfinite(v) && v > 0)
      for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
        const double ji = lim.axis[i].j_max_mm_s3;
        if (tmax[i] < 1e-12 || !(ji > 0)) continue;
        const double s = v * v * v * k3 / ji, t = l.j_max_mm_s3 / ji;
        const double sum = 1 - t * tmax[i] - s;
        const double norm2 = (1 - s) * (1 - s) - t * t;
        const double u = std::max(sum, jerk_norm && norm2 > 0 && s < 1 ? std::sqrt(norm2) : 0.0);
        l.a_max_mm_s2 = std::min(l.a_max_mm_s2, u * ji / (3 * v * kappa));
      }
  }
  return l;
}

namespace {
// Largest |A·cos φ + B·sin φ| over φ ∈ [0, sweep]: the amplitude where a peak lies inside, else an end.
double max_abs_over(double a, double b, double sweep) {
  const double amp = std::hypot(a, b);
  if (amp < 1e-300) return 0;
  const double theta = std::atan2(b, a);  // peaks at theta + kπ
  const double first = theta - std::floor(theta / std::numbers::pi) * std::numbers::pi;  // in [0, π)
  if (first <= sweep) return amp;
  return std::max(std::abs(a), std::abs(a * std::cos(sweep) + b * std::sin(sweep)));
}
}  // namespace

// rt-safe
SegmentLimits blend_limits(const BlendArc& b, const MachineLimits& lim, double cn) {
  // On p(φ) = c + R(cos φ·u + sin φ·w) axis i sees a_t·t_i(φ) + a_n·n_i(φ), t_i = −u_i sin φ + w_i cos φ,
  // n_i = −(u_i cos φ + w_i sin φ). Two bounds each keep it within a_max_i:
  //   circle:   t_i and n_i are one phase apart with amplitude amp_i = √(u_i² + w_i²), so
  //             √(a_t² + a_n²)·amp_i ≤ a_max_i;
  //   sweep:    a_t·T_i + a_n·N_i ≤ a_max_i with T_i, N_i the largest |t_i|, |n_i| over the blend's own
  //             sweep — much smaller than amp_i on a corner of a few degrees where an axis carries
  //             mostly the tangent (or mostly the normal): the short blends of 3-D CAM polylines.
  // The centripetal a_n = v_cap²/R takes cn of what every axis allows it alone; each axis then
  // gives the tangential acceleration whichever bound leaves more.
  SegmentLimits l{kInf, kInf, kInf};
  const double kappa = 1 / b.radius;
  double an_max = kInf;
  std::array<double, core::kMaxAxes> tmax{}, nmax{};
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    tmax[i] = max_abs_over(b.w[i], -b.u[i], b.sweep);
    nmax[i] = max_abs_over(b.u[i], b.w[i], b.sweep);
    if (tmax[i] < 1e-12 && nmax[i] < 1e-12) continue;
    if (tmax[i] >= 1e-12) l.v_max_mm_s = std::min(l.v_max_mm_s, lim.axis[i].v_max_mm_s / tmax[i]);
    if (nmax[i] >= 1e-12) an_max = std::min(an_max, lim.axis[i].a_max_mm_s2 / nmax[i]);
  }
  const double an = cn * an_max;
  if (std::isfinite(an)) l.v_max_mm_s = std::min(l.v_max_mm_s, std::sqrt(an * b.radius));
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    if (tmax[i] < 1e-12) continue;
    const double amax = lim.axis[i].a_max_mm_s2;
    const double amp = std::hypot(b.u[i], b.w[i]);
    const double circle = std::sqrt(std::max(0.0, (amax / amp) * (amax / amp) - an * an));
    const double sweep = std::max(0.0, amax - an * nmax[i]) / tmax[i];
    l.a_max_mm_s2 = std::min(l.a_max_mm_s2, std::max(circle, sweep));
    curve_jerk(l, lim.axis[i].j_max_mm_s3, tmax[i], kappa * kappa * tmax[i]);
  }
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (nmax[i] >= 1e-12) curve_jerk_acc(l, lim.axis[i].j_max_mm_s3, nmax[i], kappa);
  return l;
}

namespace {
constexpr double kTiny = 1e-12;
}  // namespace

// rt-safe
CurveLaw segment_law(const Segment& g, const MachineLimits& lim) {
  CurveLaw c;
  TangentLaw& l = c.law;
  double v = kInf;
  const auto linear_axes = [&](const Vec& dir) {
    for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
      const double d = std::abs(dir[i]);
      if (d < kTiny) continue;
      v = std::min(v, lim.axis[i].v_max_mm_s / d);
      l.a_const = std::min(l.a_const, lim.axis[i].a_max_mm_s2 / d);
    }
  };
  if (g.kind == SegmentKind::Line) {
    linear_axes(g.dir);
  } else if (g.kind == SegmentKind::Arc) {
    // In-plane axis: |a_t·inplane·τ_i + v²κ·ν_i| ≤ √((a_t·inplane)² + (v²κ)²) ≤ A_i (τ, ν unit and one
    // phase apart) → a_t ≤ √(A_i² − κ²w²) / inplane.
    const auto ab = g.arc_bounds();
    const double inplane = ab.inplane, kappa = ab.kappa;
    // A true circle also has the sweep bound a_t·T_i + v²κ·N_i ≤ A_i with the shares over its own
    // sweep (as blends): an arc piece near an axis's direction loads that axis with mostly one of
    // the two (the Channel cuts long arcs into pieces of at most 45° for this).
    const bool circle = std::abs(g.dradius) <= 1e-9 * g.radius;  // arc pieces carry rounding only
    const Vec tmax = g.max_abs_tangent(), nmax = g.max_abs_normal();
    if (inplane >= kTiny)
      for (std::size_t i : {std::size_t{g.axis0}, std::size_t{g.axis1}}) {
        const double amax = lim.axis[i].a_max_mm_s2;
        const double tm = circle ? tmax[i] : inplane, nm = circle ? nmax[i] : 1.0;
        if (tm >= kTiny) v = std::min(v, lim.axis[i].v_max_mm_s / tm);
        if (kappa > 0 && nm >= kTiny) l.w_cap = std::min(l.w_cap, amax / (kappa * nm));
        if (tm < kTiny) continue;  // only the normal loads this axis here: the cap is all
        TangentTerm t;
        t.c = amax / inplane;
        t.d = kappa / inplane;
        if (circle) {
          t.alpha = amax / tm;
          t.beta = kappa * nm / tm;
        }
        l.add(t);
      }
    linear_axes(g.linear);
  } else {
    // Poly: a_t·T_i + v²κ_max ≤ A_i with the sampled largest tangent share and curvature (additive:
    // a general curve's tangent and normal are not one phase apart).
    const Vec tmax = g.max_abs_tangent();
    const double kappa = g.max_curvature();
    for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
      if (tmax[i] < kTiny) continue;
      const double amax = lim.axis[i].a_max_mm_s2;
      v = std::min(v, lim.axis[i].v_max_mm_s / tmax[i]);
      TangentTerm t;
      t.alpha = amax / tmax[i];
      t.beta = kappa / tmax[i];
      l.add(t);
      if (kappa > 0) l.w_cap = std::min(l.w_cap, amax / kappa);
    }
  }
  c.v_max_mm_s = std::min(v, std::sqrt(l.w_cap));
  return c;
}

// rt-safe. The blend's law per axis is the better of the sweep and circle bounds (blend_limits).
CurveLaw blend_law(const BlendArc& b, const MachineLimits& lim) {
  CurveLaw c;
  TangentLaw& l = c.law;
  const double kappa = 1 / b.radius;
  double v = kInf;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    const double tm = max_abs_over(b.w[i], -b.u[i], b.sweep);
    const double nm = max_abs_over(b.u[i], b.w[i], b.sweep);
    if (tm < kTiny && nm < kTiny) continue;
    const double amax = lim.axis[i].a_max_mm_s2;
    if (nm >= kTiny) l.w_cap = std::min(l.w_cap, amax / (kappa * nm));  // a_t = 0, sweep bound
    if (tm < kTiny) continue;  // only the normal loads this axis: the cap is all
    v = std::min(v, lim.axis[i].v_max_mm_s / tm);
    TangentTerm t;
    t.alpha = amax / tm;
    t.beta = kappa * nm / tm;
    t.c = amax / std::hypot(b.u[i], b.w[i]);
    t.d = kappa;
    l.add(t);
  }
  c.v_max_mm_s = std::min(v, std::sqrt(l.w_cap));
  return c;
}

Planner::Planner(const MachineLimits& limits, std::size_t queue_capacity, const PlannerConfig& config)
    : limits_(limits), config_(config), queue_(queue_capacity), min_length_mm_(min_length_mm(limits)) {}

// The shortest piece that is planned as a block: a nanometre, or a twentieth of the least jerk per
// cycle, j·dt³, where that is smaller. A piece left out leaves its length as a step in the
// setpoints, a jerk of up to 2·δ/dt³: 10 times the limit for a nanometre at the floor
// motion::kMinJerkStep_mm, nothing on a machine with 1e-5 mm of jerk per cycle.
double Planner::min_length_mm(const MachineLimits& lim) {
  double m = kMinLength_mm;
  const double dt3 = lim.period_s * lim.period_s * lim.period_s;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (lim.present(i) && lim.axis[i].j_max_mm_s3 > 0) m = std::min(m, 0.05 * lim.axis[i].j_max_mm_s3 * dt3);
  return m;
}

// rt-safe. A blend the planner built lies inside every present axis's travel (P-9): the programmed
// moves were checked when pushed, a blend within P of them may still pass a limit they touch.
bool Planner::inside_travel(const Segment& g) const {
  Vec lo, hi;
  g.bounds(lo, hi);
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (limits_.present(i) && (lo[i] < limits_.axis[i].min_mm || hi[i] > limits_.axis[i].max_mm)) return false;
  return true;
}

// rt-safe
double Planner::plan_cap_mm_s(const Block& b) const {
  return std::min(b.v_cap_mm_s, b.feed_mm_s * config_.max_feed_override);
}

// rt-safe
PlanResult Planner::push(const PathRequest& req) {
  if (queue_.full()) return PlanResult::QueueFull;
  if (!req.rapid && !(req.feed_mm_s > 0)) return PlanResult::BadFeed;
  // Validate, then act: a segment that would leave the travel never enters the queue (P-9, arcs
  // included: bounds() holds the extreme points an arc passes over). Blends stay inside the convex
  // hull of the corner they cut, so checking the programmed curves covers them.
  Vec lo, hi;
  req.geom.bounds(lo, hi);
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    if (!limits_.present(i)) {
      if (lo[i] != 0 || hi[i] != 0) return PlanResult::OutsideTravel;  // an axis the machine lacks
      continue;
    }
    constexpr double kEps = 1e-9;
    if (lo[i] < limits_.axis[i].min_mm - kEps || hi[i] > limits_.axis[i].max_mm + kEps) return PlanResult::OutsideTravel;
  }
  if (!(req.geom.length > min_length_mm_)) return PlanResult::Ok;  // nothing to move
  const auto sl = segment_limits(req.geom, limits_, config_.centripetal_share);
  if (!std::isfinite(sl.v_max_mm_s) || !std::isfinite(sl.a_max_mm_s2) || !(sl.v_max_mm_s > 0) ||
      !(sl.a_max_mm_s2 > 0))
    return PlanResult::Infeasible;
  // Validated: now act. Lines pass through the merge stage; anything else first releases it.
  if (queue_.has_stage_ && merge(req)) return PlanResult::Ok;
  const PlanResult r = emit_stage();
  if (r != PlanResult::Ok) return r;
  const double tol = req.tolerance_mm < 0 ? config_.tolerance_mm : req.tolerance_mm;
  if (req.geom.kind == SegmentKind::Line && req.mergeable && tol > 0 && config_.merge_share > 0) {
    stage(req);
    return PlanResult::Ok;
  }
  return plan(req);
}

// rt-safe. Holds a line back: the next lines may still merge into it.
void Planner::stage(const PathRequest& req) {
  MergeStage& m = queue_.stage_;
  m.req = req;
  m.tag_last = std::max(req.tag, req.tag_last);
  m.q_mm = kInf;
  m.dev_mm = 0;
  m.n = 0;
  queue_.has_stage_ = true;
}

// rt-safe. Naive-CAM merge (LinuxCNC's G64 Q):
//
//   S ──●──●───●──● E ──► req          ● programmed corners, each within Q of the chord S → req's end,
//   S ────────────────────► end        every piece moving forward along it: the chord is planned instead
//
// Every point of the chord then lies within Q of the programmed polyline (its points project in
// order onto the chord, and between two corners the offset is a blend of theirs), and the blends at
// the chord's ends stay within P of the programmed corners S and E: the whole path within max(Q, P).
// Merging removes the short and noisy pieces of CAM polylines that otherwise force tiny blend radii.
bool Planner::merge(const PathRequest& req) {
  MergeStage& m = queue_.stage_;
  const double tol = req.tolerance_mm < 0 ? config_.tolerance_mm : req.tolerance_mm;
  if (req.geom.kind != SegmentKind::Line || !req.mergeable || !(tol > 0) || req.rapid != m.req.rapid || req.profile != m.req.profile ||
      (!req.rapid && req.feed_mm_s != m.req.feed_mm_s) || m.n + 1 >= MergeStage::kMaxPoints)
    return false;
  const double q = std::min(m.q_mm, config_.merge_share * tol);
  const Vec s = m.req.geom.start, e = req.geom.end;
  const Vec chord = e - s;
  const double len = core::norm(chord);
  if (!(len > min_length_mm_)) return false;
  const Vec c = chord * (1 / len);
  // The corner at the stage's end joins the merged points for the check. Each point's offset from
  // S is kept, so a push costs one dot product per point: the distance off the chord is
  // √(|d|² − (d·c)²), and the pieces move forward along it while d·c grows.
  m.offsets[m.n] = m.req.geom.end - s;
  m.offset2[m.n] = core::dot(m.offsets[m.n], m.offsets[m.n]);
  const double q2 = q * q;
  double prev = 0, dev2 = 0;
  for (std::size_t k = 0; k <= m.n; ++k) {
    const double along = core::dot(m.offsets[k], c);
    if (!(along > prev)) return false;
    dev2 = std::max(dev2, m.offset2[k] - along * along);
    if (dev2 > q2) return false;
    prev = along;
  }
  if (!(len > prev)) return false;
  ++m.n;
  m.q_mm = q;
  m.dev_mm = std::sqrt(std::max(0.0, dev2));
  // The merged line S → e, as make_line builds it (only its end, length and direction change).
  m.req.geom.end = e;
  m.req.geom.length = len;
  m.req.geom.dir = c;
  m.tag_last = std::max(req.tag, req.tag_last);
  return true;
}

// rt-safe. Plans the held-back line (merged or not).
PlanResult Planner::emit_stage() {
  if (!queue_.has_stage_) return PlanResult::Ok;
  queue_.has_stage_ = false;
  const MergeStage& m = queue_.stage_;
  return plan(m.req, m.dev_mm, m.tag_last);
}

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

// rt-safe. Plans a validated move in: blend with the pending block, commit, hold the new one pending.
PlanResult Planner::plan(const PathRequest& req, double merge_dev_mm, std::uint32_t tag_last) {
  const auto sl = segment_limits(req.geom, limits_, config_.centripetal_share, target_speed(req.rapid, req.feed_mm_s));
  if (!std::isfinite(sl.v_max_mm_s) || !std::isfinite(sl.a_max_mm_s2) || !(sl.v_max_mm_s > 0) ||
      !(sl.a_max_mm_s2 > 0))
    return PlanResult::Infeasible;

  Block b;
  b.seg = req.geom;
  b.rapid = req.rapid;
  b.tag = req.tag;
  b.tag_last = std::max({req.tag, req.tag_last, tag_last});
  b.length = req.geom.length;
  b.merge_q_mm = std::max(merge_dev_mm, req.offset_mm);
  set_limits(b, sl, req.profile == ProfileKind::Trapezoid ? kInf : sl.j_max_mm_s3, target_speed(req.rapid, req.feed_mm_s));
  set_law(b, [&] { return segment_law(req.geom, limits_); });
  b.feed_mm_s = req.rapid ? kInf : req.feed_mm_s;
  advance(b, req.tolerance_mm < 0 ? config_.tolerance_mm : req.tolerance_mm);
  return PlanResult::Ok;
}

// rt-safe. The next block b (as programmed, with tolerance p_mm) after the pending one: a held arc
// first becomes a fillet with b or is planned on its own; an arc that may become a fillet is held.
void Planner::advance(Block& b, double p_mm) {
  if (queue_.has_held_) {
    if (fillet(b, p_mm)) return;
    release_held();
  }
  if (holds_fillet(b, p_mm)) {
    queue_.held_ = b;
    queue_.held_p_mm_ = p_mm;
    queue_.has_held_ = true;
    return;
  }
  join(b, p_mm);
}

// rt-safe. Plans a held arc on its own: the next block was no line, or the fillet did not fit, or
// was slower.
void Planner::release_held() {
  if (!queue_.has_held_) return;
  queue_.has_held_ = false;
  Block h = queue_.held_;
  join(h, queue_.held_p_mm_);
}

// rt-safe. Blends the pending block's end with b's start (or kinks or stops there), commits the
// pending block and the blend, and holds b pending.
void Planner::join(Block& b, double p_mm) {
  const double full_length = b.length;
  if (queue_.has_pending_) {
    Block& a = queue_.pending_;
    // A merged line lies up to merge_q_mm off the program: the blend keeps the rest of P.
    const double tol = p_mm - std::max(a.merge_q_mm, b.merge_q_mm);
    Block blend;
    bool blended = false;
    if (tol > 0 && !a.is_blend && a.seg.kind == SegmentKind::Line && b.seg.kind == SegmentKind::Line) {
      // Deflection: 0 = straight on, π = reversal (from the chord |t2 − t1| = 2 sin(δ/2): exact near 0).
      const double chord = core::norm(b.seg.dir - a.seg.dir);
      const double delta = 2 * std::asin(std::min(1.0, chord / 2));
      // Within 2e-3 rad of a reversal, a stop, as kink() takes it: a blend there is crossed at a
      // few µm/s at best, and the corner quintic of a near-reversal degenerates into a cusp its
      // sampled curvature does not see (a fuzzer's line reversing onto a stub 1.3e-5 rad off it:
      // the quintic kept the axes' speed as its cap and was crossed at 0.45 mm/s, 10 % over Y's
      // acceleration).
      if (delta > config_.tangent_rad && delta < std::numbers::pi - 2e-3) {
        // Arc tangent to both lines whose midpoint lies `tol` from the corner:
        // tol = R·(1/cos h − 1), h = δ/2  →  R = tol·cos h / (1 − cos h); it touches the lines at
        // d = R·tan h from the corner. Each line gives at most half of its length to a blend, so
        // the blends at its two ends never overlap (then R shrinks and the deviation with it).
        const double h = delta / 2;
        const double one_minus_cos = 2 * std::sin(h / 2) * std::sin(h / 2);
        double r = tol * std::cos(h) / one_minus_cos;
        double d = r * std::tan(h);
        const double d_max = std::min(queue_.pending_full_length_ / 2, b.length / 2);
        if (d > d_max) {
          d = d_max;
          r = d / std::tan(h);
        }
        const bool jerk = !(std::isinf(a.j_mm_s3) && std::isinf(b.j_mm_s3));
        if (d > min_length_mm_ && r > min_length_mm_) {
          blend.is_blend = true;
          blend.blend = make_blend_arc(a.seg.end - a.seg.dir * d, a.seg.dir, b.seg.dir, r, delta);
          blend.length = r * delta;
          const auto bl = blend_limits(blend.blend, limits_, config_.centripetal_share);
          set_limits(blend, bl, jerk ? bl.j_max_mm_s3 : kInf);
          set_law(blend, [&] { return blend_law(blend.blend, limits_); });
        }
        if (jerk && delta >= config_.g2_blend_min_rad) {
          // Jerk mode: the arc's curvature steps at both ends limit it to the speed at which one
          // cycle's share of each axis's jerk takes the step (commit()); the curvature-continuous
          // quintic (make_corner_blend, its midpoint `tol` from the corner as the arc's, its shape
          // by the deflection) has no step but a higher peak curvature. It is taken
          // where its corner speed is well above the arc's (g2_blend_gain: a Poly piece keeps less of
          // the acceleration along the path than an arc, docs/planner.md, "Corner blends"); at most
          // half of each line, as the arc.
          const double v_arc =
              blend.length > 0
                  ? std::min(blend.v_cap_mm_s,
                             std::sqrt(curvature_step_v2(blend.blend.curvature(0), limits_, config_.curvature_step_share)))
                  : 0.0;
          double alpha = 0, beta = 0;
          corner_blend_shape(delta, alpha, beta);
          const double dq = std::min(tol / corner_blend_dev(chord, 1.0, alpha, beta), d_max);
          // Its cap never exceeds the target speed: where the arc is already that fast within the
          // gain, the quintic (tens of µs to build: its length table and sampled limits) is not.
          const double vq = target_speed(a.rapid && b.rapid, std::min(a.feed_mm_s, b.feed_mm_s));
          const bool worth = !(config_.g2_blend_gain * v_arc >= vq);
          const bool build = worth && dq > min_length_mm_;
          curves_tried_ += build ? 1 : 0;
          const SegmentResult q = build ? make_corner_blend(a.seg.end, a.seg.dir, b.seg.dir, dq, alpha, beta)
                                        : SegmentResult{CurveError::BadValue, {}};
          const SegmentLimits ql = q.ok() ? segment_limits(q.segment, limits_, config_.centripetal_share, vq, false) : SegmentLimits{};
          if (q.ok() && ql.v_max_mm_s > config_.g2_blend_gain * v_arc && ql.a_max_mm_s2 > 0 &&
              std::isfinite(ql.a_max_mm_s2)) {
            blend = Block{};
            blend.seg = q.segment;
            blend.length = q.segment.length;
            set_limits(blend, ql, ql.j_max_mm_s3, vq, false);
            set_law(blend, [&] { return segment_law(blend.seg, limits_); });
            d = dq;
          }
        }
        if (blend.length > 0) {
          // Blend or stop: a corner is crossed on its blend only where that is estimated quicker than
          // stopping on the corner and going on (kink() then makes it a stop). With a jerk limit a
          // sharp corner's blend is slow (a 90° quintic within P0.05 at 10 000 mm/s³: 3.7 mm/s),
          // and the path must slow down to it at the blend's lower jerk, then cross it and speed up
          // again: on zigzags of 1–10 mm lines a stop at each corner was up to 20 % quicker
          // (docs/planner.md, "Blend or stop"). Each side is timed from the corner to the middle of
          // its line (where the profiles of the corners at both ends meet) by side_time. The blend's
          // crossing speed: its cap, and an arc's curvature steps in jerk mode. With
          // corner_stop_when_quicker off, only a blend whose crossing lasts ten times a stop over its
          // own length is dropped, as before the choice (a return line almost onto its outgoing one:
          // 1e-8 mm/s over 2.6e-4 mm took hours of a review's fuzzing).
          double v_eff = blend.v_cap_mm_s;
          if (jerk && blend.is_blend)
            v_eff = std::min(v_eff, std::sqrt(curvature_step_v2(blend.blend.curvature(0), limits_,
                                                                config_.curvature_step_share)));
          const double acc = std::min(a.a_mm_s2, b.a_mm_s2), jk = std::min(a.j_mm_s3, b.j_mm_s3);
          const double jb = std::min(jk, blend.j_mm_s3);  // eased into the blend at its own jerk
          // The speed the lines run at: their feed at 100 % (the override is not known yet; rapids
          // carry an infinite feed, so their caps).
          const double vm = std::min({a.feed_mm_s, b.feed_mm_s, a.v_cap_mm_s, b.v_cap_mm_s});
          if (!config_.corner_stop_when_quicker) {
            const double t_stop = 2 * std::sqrt(blend.length / acc) + (std::isfinite(jk) ? 4 * std::cbrt(blend.length / jk) : 0.0);
            if (!(blend.length < 10 * t_stop * v_eff)) blend = Block{};
          } else if (!(v_eff >= vm)) {
            // A blend crossed at the lines' speed is always the quicker (and most are: CAM
            // polylines' slight turns, which cost no estimate then).
            const double la = queue_.pending_full_length_ / 2, lb = b.length / 2;
            const double t_stop = side_time(la, 0, vm, acc, jk, jk) + side_time(lb, 0, vm, acc, jk, jk);
            const double t_blend = v_eff > 0 ? side_time(la - d, v_eff, vm, acc, jb, jk) + side_time(lb - d, v_eff, vm, acc, jb, jk) +
                                                   blend.length / v_eff
                                             : kInf;
            if (!(t_blend < t_stop)) blend = Block{};
          }
        }
        if (blend.length > 0) {
          const Vec corner = a.seg.end;
          const Vec p1 = corner - a.seg.dir * d;
          const Vec p2 = corner + b.seg.dir * d;
          join_blend(blend, a, b);
          // Shorten both lines (same direction, so their limits stay).
          const Vec a_start = a.seg.start;
          a.seg = make_line(a_start, p1);
          a.length = a.seg.length;
          b.seg = make_line(p2, b.seg.end);
          b.length = b.seg.length;
          blended = true;
        }
      }
    }
    if (!blended && tol > 0 && (a.seg.kind == SegmentKind::Arc || b.seg.kind == SegmentKind::Arc))
      blended = blend_curves(a, b, tol, queue_.pending_full_length_ / 2, blend);
    if (!blended && p_mm > 0) kink(a, b);
    if (a.length > min_length_mm_) commit(a);
    if (blended) commit(blend);
  }
  queue_.pending_ = b;
  queue_.pending_full_length_ = full_length;
  queue_.has_pending_ = true;
}

namespace {
// rt-safe. Largest curvature of a block (1/mm).
double max_curvature(const Block& b) {
  if (b.is_blend) return 1 / b.blend.radius;
  if (b.seg.kind == SegmentKind::Arc) return b.seg.arc_bounds().kappa;
  if (b.seg.kind == SegmentKind::Poly) return b.seg.max_curvature();
  return 0;
}
}  // namespace

// rt-safe. A corner that is not blended (one side an arc or a curve, or lines under G64 with P too
// small) is crossed at speed when that speed turns every axis within one cycle's share of its
// acceleration (and jerk): v·|t_out,i − t_in,i| ≤ share·a_i·dt, the discrete form of grbl's junction
// deviation. The setpoints stay on the programmed path (deviation 0). Both neighbours give up that
// share of their acceleration and jerk, so the kink's one-cycle impulse never adds up past a limit.
double Planner::kink_speed(const Block& a, const Block& b) const {
  const Vec dt_vec = b.tangent(0) - a.tangent(a.length);
  const double turn = core::norm(dt_vec);
  if (turn <= config_.tangent_rad || !(config_.kink_share > 0)) return 0;
  const double dt = limits_.period_s;
  double v = kInf;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    const double d = std::abs(dt_vec[i]);
    if (d < 1e-15 || !limits_.present(i)) continue;
    double room = limits_.axis[i].a_max_mm_s2 * dt;
    const bool jerk = limits_.axis[i].j_max_mm_s3 > 0 && !(std::isinf(a.j_mm_s3) && std::isinf(b.j_mm_s3));
    if (jerk) room = std::min(room, limits_.axis[i].j_max_mm_s3 * dt * dt);
    v = std::min(v, config_.kink_share * room / d);
  }
  const double keep = 1 - config_.kink_share;
  // The one-cycle impulse adds to the neighbours' centripetal acceleration too: within the cycle
  // that crosses the kink (speed ≤ v + that cycle's gain), v²κ may use at most `keep` of the axes.
  double a_min = kInf, a_path = 0;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (limits_.present(i)) a_min = std::min(a_min, limits_.axis[i].a_max_mm_s2);
  for (const Block* n : {&a, &b}) a_path = std::max({a_path, n->a_mm_s2, n->law.at(0)});
  for (const Block* n : {&a, &b}) {
    const double k = max_curvature(*n);
    if (k > 0 && std::isfinite(a_min)) v = std::min(v, std::sqrt(keep * a_min / k) - a_path * dt);
  }
  if (!(v >= config_.min_kink_speed_mm_s)) return 0;  // too slow to be worth the lost acceleration: stop
  return v;
}

// rt-safe. Applies kink_speed: both neighbours give up the kink's share.
void Planner::kink(Block& a, Block& b) const {
  const double v = kink_speed(a, b);
  if (!(v > 0)) return;
  const double keep = 1 - config_.kink_share;
  a.a_mm_s2 *= keep;
  a.law.scale *= keep;
  a.j_mm_s3 *= keep;
  b.a_mm_s2 *= keep;
  b.law.scale *= keep;
  b.j_mm_s3 *= keep;
  b.v2_kink = v * v;
}

// rt-safe. Corners and curvature steps where an arc meets a line or another arc (docs/planner.md,
// "Corner blends"):
//
//   a ────────────●╮ corner        a's end and b's start are cut back by the arc length d each and
//        p0 ╰───╮  │ b (an arc)    joined by the quintic of make_g2_blend, which continues each with
//               ╰──● p1            its tangent and curvature: no kink, no acceleration step.
//
// The corner's tangent lines from p0 and p1 give the control legs, the deflection between t0 and
// t1 the shape. d starts where the lines' quintic would put its midpoint P from the corner (or, on a
// tangent junction, at √(24·P/Δκ): a transition curve that long shifts the arc by about P), at most
// half of either piece and one radian of an arc, and shrinks until every sample of the quintic lies
// within 0.95·P of a or b. It is taken where its speed cap beats the junction's speed without it
// (a kink or exact stop; on a tangent curvature step, the step's speed by g2_blend_gain).
bool Planner::blend_curves(Block& a, Block& b, double tol, double da_half, Block& blend) const {
  const auto curve = [](const Block& k) {
    return !k.is_blend && (k.seg.kind == SegmentKind::Line || k.seg.kind == SegmentKind::Arc);
  };
  if (!curve(a) || !curve(b)) return false;
  const bool jerk = !(std::isinf(a.j_mm_s3) && std::isinf(b.j_mm_s3));
  const auto unit = [](const Vec& v) { return v * (1 / core::norm(v)); };  // a spiral's |tangent| ≠ 1
  const double turn = core::norm(unit(b.seg.tangent(0)) - unit(a.seg.tangent(a.length)));
  if (turn > 2 * std::cos(1e-3)) return false;  // a reversal: stop
  const bool tangent = turn <= config_.tangent_rad;
  double v_alt = 0, gain = 1;  // the junction's speed without a blend, and the margin a blend must beat it by
  const Vec dk = b.seg.curvature(0) - a.seg.curvature(a.length);
  if (tangent) {
    if (!jerk) return false;  // a curvature step costs trapezoids nothing
    v_alt = std::sqrt(curvature_step_v2(dk, limits_, config_.curvature_step_share));
    gain = config_.g2_blend_gain;
  } else {
    v_alt = kink_speed(a, b);
  }
  const double vq = target_speed(a.rapid && b.rapid, std::min(a.feed_mm_s, b.feed_mm_s));
  if (!(gain * v_alt < std::min({vq, a.v_cap_mm_s, b.v_cap_mm_s}))) return false;  // as fast without

  const double delta = 2 * std::asin(std::min(1.0, turn / 2));
  double alpha = 0, beta = 0;
  corner_blend_shape(delta, alpha, beta);
  const double dkn = core::norm(dk);
  const double d0 = tangent ? (dkn > 0 ? std::sqrt(24 * tol / dkn) : kInf) : tol / corner_blend_dev(turn, 1.0, alpha, beta);
  // Each side gives at most half of its length (the blend at its other end takes the other half)
  // and one radian of an arc.
  const auto side_max = [](const Block& k, double half) {
    return k.seg.kind == SegmentKind::Arc ? std::min(half, k.seg.radius) : half;
  };
  const double da_max = side_max(a, da_half), db_max = side_max(b, b.length / 2);
  double da = std::min(d0, da_max), db = std::min(d0, db_max);
  std::array<Vec, 6> ctrl{};
  // The quintic from a's point da before its end to b's point db after its start (in `out`) and its
  // largest distance from a and b (or the first found past `above`, where only that is asked).
  const auto fit = [&](double ea, double eb, std::array<Vec, 6>& out, double above = kInf) {
    const double sa = a.length - ea;
    const Vec p0 = a.seg.point(sa), p1 = b.seg.point(eb);
    const Vec t0 = unit(a.seg.tangent(sa)), t1 = unit(b.seg.tangent(eb));
    // Control legs: p0 + x0·t0 ≈ p1 − x1·t1 (least squares; the tangent lines meet in a plane).
    const Vec w = p1 - p0;
    const double c = core::dot(t0, t1), det = 1 - c * c, chord = core::norm(w);
    double x0 = chord / 2, x1 = chord / 2;
    if (det > 1e-6) {
      const double u0 = core::dot(t0, w), u1 = core::dot(t1, w);
      const double y0 = (u0 - c * u1) / det, y1 = (u1 - c * u0) / det;
      if (y0 > 0 && y1 > 0 && y0 < 2 * chord && y1 < 2 * chord) {
        x0 = y0;
        x1 = y1;
      }
    }
    double al = 0, be = 0;
    corner_blend_shape(2 * std::asin(std::min(1.0, core::norm(t1 - t0) / 2)), al, be);
    out = g2_blend_points(p0, t0, a.seg.curvature(sa), x0, p1, t1, b.seg.curvature(eb), x1, al, be);
    const BezierPower curve(out);
    return peak_distance([&](double u, double floor) {
      const Vec q = curve.at(u);
      const double e = a.seg.distance_to(q);
      return e <= floor ? e : std::min(e, b.seg.distance_to(q));
    }, above);
  };
  ++curves_tried_;  // the fit below is the costly part, taken or not
  bool fits = false;
  for (int it = 0; it < 16 && std::min(da, db) > min_length_mm_ && !fits; ++it) {
    const double dev = fit(da, db, ctrl);
    fits = dev <= 0.95 * tol;
    if (!fits) {
      const double f = std::clamp(0.95 * std::sqrt(tol / dev), 0.3, 0.9);
      da *= f;
      db *= f;
    }
  }
  // One side held to its half (a short arc between two corners) while the other had room: that side
  // grows while the quintic still fits; a longer transition bends less sharply.
  if (fits && (da >= da_max) != (db >= db_max)) {
    const bool grow_a = db >= db_max;
    for (int it = 0; it < 4; ++it) {
      double& e = grow_a ? da : db;
      const double e_max = grow_a ? da_max : db_max;
      const double next = std::min(1.5 * e, e_max);
      if (!(next > e * (1 + 1e-9))) break;
      std::array<Vec, 6> c2{};
      const double dev = grow_a ? fit(next, db, c2, 0.95 * tol) : fit(da, next, c2, 0.95 * tol);
      if (!(dev <= 0.95 * tol)) break;
      e = next;
      ctrl = c2;
    }
  }
  if (!fits) return false;
  const SegmentResult q = make_bezier(ctrl);
  if (!q.ok()) return false;
  const SegmentLimits ql = segment_limits(q.segment, limits_, config_.centripetal_share, vq, false);
  // Worth it only where it saves time. Each side of a corner crossed at v loses about T·(v_s − v)/2v_s
  // against going on at v_s (its speed: cap and feed; T the ramp's time from v_s to v with its
  // tangential acceleration at low speed, where the speed-dependent law of trapezoid blocks gives
  // most of the axes', and its jerk), and the blend's length len costs len/v − len/v_s; a stop is
  // v = 0. Slow blends of sharp corners, where a stop costs little more, are not taken (a margin of
  // a tenth there covers what the model leaves out: the quintic's own, lower acceleration).
  const auto side = [&](const Block& k, double v) {
    const double vs = std::min(vq, k.v_cap_mm_s), as = std::max(k.a_mm_s2, k.law.at(0)), js = k.j_mm_s3;
    const double dv = std::max(0.0, vs - v);
    const double t = !std::isfinite(js) ? dv / as : dv >= as * as / js ? dv / as + as / js : 2 * std::sqrt(dv / js);
    return t * dv / (2 * vs);
  };
  const double v_f = std::min({vq, a.v_cap_mm_s, b.v_cap_mm_s});
  const auto loss = [&](double v, double len) {
    return side(a, v) + side(b, v) + (v > 0 ? len / v - len / v_f : 0.0);
  };
  if (!(ql.v_max_mm_s > gain * v_alt) || !(loss(ql.v_max_mm_s, q.segment.length) < (tangent ? 1.0 : 0.9) * loss(v_alt, 0)) || !(ql.a_max_mm_s2 > 0) || !std::isfinite(ql.a_max_mm_s2)) return false;
  // The quintic may bulge past the corner (an arc's side): it must stay inside the travel too.
  if (!inside_travel(q.segment)) return false;
  blend = Block{};
  blend.seg = q.segment;
  blend.length = q.segment.length;
  set_limits(blend, ql, jerk ? ql.j_max_mm_s3 : kInf, vq, false);
  set_law(blend, [&] { return segment_law(blend.seg, limits_); });
  join_blend(blend, a, b);
  a.seg = trimmed(a.seg, 0, a.length - da);
  a.length = a.seg.length;
  b.seg = trimmed(b.seg, db, b.length);
  b.length = b.seg.length;
  // Where the quintic meets the arc their curvatures differ: a kink like any other.
  kink(a, blend);
  kink(blend, b);
  return true;
}

// rt-safe. An arc is held as a fillet candidate (jerk mode, docs/planner.md "Fillets") when it
// leaves the pending line at most kFilletMaxTurn off its direction, is no helix (a spiral's end off
// the circle is; fillet() checks the distance to it), turns at most kFilletMaxRad and is slower
// than its feed asks: the line after it may make it one quintic.
bool Planner::holds_fillet(const Block& b, double p_mm) const {
  if (!(config_.fillet_share > 0) || !(p_mm > 0) || !queue_.has_pending_) return false;
  const Block& a = queue_.pending_;
  if (a.is_blend || a.seg.kind != SegmentKind::Line || b.seg.kind != SegmentKind::Arc || a.rapid != b.rapid) return false;
  if (!std::isfinite(b.j_mm_s3) || !std::isfinite(a.j_mm_s3)) return false;  // trapezoids take the curvature step at speed
  if (is_helix(b.seg)) return false;  // its lines rarely share a plane
  if (!(std::abs(b.seg.sweep) <= kFilletMaxRad)) return false;
  if (core::norm(b.seg.tangent(0) - a.seg.dir) > kFilletMaxTurn) return false;
  return b.v_cap_mm_s < target_speed(b.rapid, b.feed_mm_s);
}

// rt-safe. The held arc h between the pending line a and the line c as one fillet:
//
//   a ─────────────●──╮ V        the quintic corner blend of the two lines' corner V
//            V−d·t0 ╰─╮ │ h       (make_corner_blend), d as large as keeps every point of it
//                    ╰─●│ c       within 0.95·P of a, h or c; it replaces the arc and both
//                       │         curvature steps, so nothing on the corner runs slower than
//                   V+d·t1        its own cap.
// Taken where that cap is at least fillet_share of the arc's own (the arc is entered through
// transitions slower than it). On success a and the quintic are committed and c is pending.
bool Planner::fillet(Block& c, double p_mm) {
  Block& a = queue_.pending_;
  const Block& h = queue_.held_;
  if (c.seg.kind != SegmentKind::Line || c.rapid != h.rapid || !std::isfinite(c.j_mm_s3)) return false;
  const double tol = std::min(p_mm, queue_.held_p_mm_) - std::max(a.merge_q_mm, c.merge_q_mm);
  if (!(tol > 0)) return false;
  const Vec t0 = a.seg.dir, t1 = c.seg.dir;
  if (core::norm(t1 - h.seg.tangent(h.length)) > kFilletMaxTurn) return false;
  const double chord = core::norm(t1 - t0);
  const double delta = 2 * std::asin(std::min(1.0, chord / 2));
  if (!(delta > config_.tangent_rad) || delta > kFilletMaxRad) return false;
  // V: a's end + x·t0 = c's start − y·t1 (the two lines meet: the arc lies in their plane).
  const Vec w = c.seg.start - a.seg.end;
  const double cc = core::dot(t0, t1), det = 1 - cc * cc;
  if (!(det > 1e-12)) return false;
  const double u0 = core::dot(t0, w), u1 = core::dot(t1, w);
  const double x = (u0 - cc * u1) / det, y = (u1 - cc * u0) / det;
  const Vec v = a.seg.end + t0 * x;
  // V lies ahead of a's end and before c's start (a corner the arc rounds, not one it overshoots),
  // and the arc turns the way the corner does: else the quintic would leave the arc's far side.
  if (!(x >= 0) || !(y >= 0) || core::distance(v, c.seg.start - t1 * y) > 1e-6) return false;
  const Vec turn_dir = t1 - t0;  // the corner bends towards it; so must the arc's curvature
  if (!(core::dot(h.seg.curvature(h.length / 2), turn_dir) > 0)) return false;
  double alpha = 0, beta = 0;
  corner_blend_shape(delta, alpha, beta);
  const double coef = corner_blend_dev(chord, 1.0, alpha, beta);
  // The quintic starts on a and ends on c (d ≥ x, d ≥ y), each line giving at most half of itself
  // as programmed; d from where its midpoint meets the arc's to where it lies 0.95·P past it.
  const double room = std::min(x + std::min(queue_.pending_full_length_ / 2, a.length), y + c.length / 2);
  const double mid = core::distance(h.seg.point(h.length / 2), v);
  const double d_lo = std::max({x, y, mid / coef}), d_hi = std::min(room, (mid + 0.95 * tol) / coef);
  if (!(d_lo <= d_hi)) return false;
  const auto off = [&](double d) {
    const std::array<Vec, 6> ctrl{v - t0 * d, v - t0 * (alpha * d), v - t0 * (beta * d),
                                  v + t1 * (beta * d), v + t1 * (alpha * d), v + t1 * d};
    const BezierPower curve(ctrl);
    return peak_distance([&](double u, double floor) {
      const Vec q = curve.at(u);
      const double e = std::min(a.seg.distance_to(q), c.seg.distance_to(q));  // the lines first: cheaper
      return e <= floor ? e : std::min(e, h.seg.distance_to(q));
    }, 0.95 * tol);  // only compared with it below
  };
  ++curves_tried_;  // the search below is the costly part, taken or not
  double d = d_hi;
  if (!(off(d) <= 0.95 * tol)) {
    if (!(off(d_lo) <= 0.95 * tol)) return false;
    double lo = d_lo, hi = d_hi;  // the largest d that fits, to 1/256 of the span
    for (int it = 0; it < 8; ++it) {
      const double m = 0.5 * (lo + hi);
      (off(m) <= 0.95 * tol ? lo : hi) = m;
    }
    d = lo;
  }
  const SegmentResult q = make_corner_blend(v, t0, t1, d, alpha, beta);
  if (!q.ok()) return false;
  // And the other way: the arc (its ends and 15 points between) lies within P of the quintic, so the
  // program is as near the path as the path is to the program.
  for (int i = 0; i <= 16; ++i)
    if (!(q.segment.distance_to(h.seg.point(h.length * i / 16), tol) <= tol)) return false;
  const double vq = target_speed(h.rapid, std::min({a.feed_mm_s, h.feed_mm_s, c.feed_mm_s}));
  const SegmentLimits ql = segment_limits(q.segment, limits_, config_.centripetal_share, vq, false);
  if (!(ql.v_max_mm_s >= config_.fillet_share * std::min(h.v_cap_mm_s, vq)) || !(ql.a_max_mm_s2 > 0) ||
      !std::isfinite(ql.a_max_mm_s2))
    return false;
  if (!inside_travel(q.segment)) return false;  // within P of the program, it may still pass a soft limit it touches
  Block blend;
  blend.seg = q.segment;
  blend.length = q.segment.length;
  set_limits(blend, ql, ql.j_max_mm_s3, vq, false);
  set_law(blend, [&] { return segment_law(blend.seg, limits_); });
  join_blend(blend, a, c);
  blend.feed_mm_s = std::min(blend.feed_mm_s, h.feed_mm_s);  // never faster than the arc it replaces
  const double full_c = c.length;
  a.seg = make_line(a.seg.start, v - t0 * d);
  a.length = a.seg.length;
  c.seg = make_line(v + t1 * d, c.seg.end);
  c.length = c.seg.length;
  queue_.has_held_ = false;
  if (a.length > min_length_mm_) commit(a);
  commit(blend);
  queue_.pending_ = c;
  queue_.pending_full_length_ = full_c;
  return true;
}

// rt-safe
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

void Planner::flush() {
  emit_stage();  // validated when pushed: the merged line is inside the hull of what was checked
  release_held();
  if (!queue_.has_pending_) {
    queue_.back_open_ = false;
    return;
  }
  queue_.has_pending_ = false;
  if (queue_.pending_.length > min_length_mm_) commit(queue_.pending_);
  queue_.back_open_ = false;  // nothing follows for now: the interpolator may plan with the back too
}

// rt-safe. Caps b where the kDenseBlocks blocks ending with it (it included) are shorter than a
// cycle's travel at its cap; fewer blocks since the window was last empty cannot fill a cycle.
void Planner::dense_cap(Block& b) {
  const std::size_t slot = dense_n_ % kDenseBlocks;
  if (slot == 0) {  // the running sum taken afresh once per round, so rounding cannot pile up
    dense_sum_mm_ = 0;
    for (std::size_t k = 0; k < kDenseBlocks && k < dense_n_; ++k) dense_sum_mm_ += dense_len_[k];
  }
  if (dense_n_ >= kDenseBlocks) dense_sum_mm_ -= dense_len_[slot];
  dense_len_[slot] = b.length;
  dense_sum_mm_ += b.length;
  if (++dense_n_ < kDenseBlocks) return;
  const double cap = std::max(0.0, dense_sum_mm_) / limits_.period_s;
  if (cap < b.v_cap_mm_s) {
    b.v_cap_mm_s = cap;
    b.v_split_mm_s = std::min(b.v_split_mm_s, cap);
  }
}

namespace {
// rt-safe. The most speed a motion can have anywhere within L mm of rest (entering a block at rest,
// or leaving it at rest: time runs backwards) within the path acceleration A and jerk J: from rest at
// J up to A, then at A.
double reach_from_rest(double L, double A, double J) {
  const double d1 = A * A * A / (6 * J * J);
  if (L <= d1) {
    const double t = std::cbrt(6 * L / J);
    return 0.5 * J * t * t;
  }
  const double v1 = A * A / (2 * J);
  return std::sqrt(v1 * v1 + 2 * A * (L - d1));
}
}  // namespace

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

// rt-safe. Appends a block: its junction limit with the block before it, then the backward pass.
void Planner::commit(const Block& b) {
  auto& ring = queue_.ring_;
  // The block before b is final once the interpolator may plan with it (PlanQueue::visible: after
  // a flush), so the curvature step below must then leave its jerk alone.
  const bool prev_visible = !ring.empty() && !queue_.back_open_;
  ring.push(b);  // room was checked by push()
  queue_.back_open_ = true;
  ++blocks_committed_;
  Block& nb = ring.back();
  const bool from_rest = ring.size() == 1;
  if (from_rest) dense_n_ = 0;  // no block before it shares a cycle with it
  dense_cap(nb);
  if (from_rest) {
    nb.v2_junction = 0;  // the machine is at rest when the window is empty (its tail ends at rest)
  } else {
    Block& prev = ring.at(ring.size() - 2);
    // Tangent junctions keep the speed both neighbours allow; any other corner that was not blended
    // (G61, arcs, reversals) is an exact stop: a direction change at speed needs infinite acceleration.
    // |t_out − t_in| is the turning angle (chord of unit vectors), without acos's loss near 0.
    const double turn = core::norm(prev.tangent(prev.length) - nb.tangent(0));
    const double cap = std::min(plan_cap_mm_s(prev), plan_cap_mm_s(nb));
    nb.v2_junction = turn <= config_.tangent_rad ? cap * cap : std::min(cap * cap, nb.v2_kink);
    // A block without a jerk limit (axes with max_jerk 0, or a Trapezoid move) into one with a
    // limit: the trapezoid follower plans its exit with the backward pass's constant-deceleration
    // model, which knows nothing of the jerk follower's ramps, and handed it states it could not
    // brake from (a fuzzer's program on X, Y without jerk and Z with: X at 10× its acceleration where
    // the path reached the end of the program at 3 mm/s). The jerk follower starts from rest there.
    if (!std::isfinite(prev.j_mm_s3) && std::isfinite(nb.j_mm_s3)) nb.v2_junction = 0;
    // With jerk limits, a jump of the curvature vector (line into arc or blend) steps each axis's
    // acceleration by v²·Δκ_i within one cycle, on top of the path's own jerk in that cycle: the
    // step is kept within a share (curvature_step_share) of j_i·dt, and both neighbours give up the share the
    // step can actually take at the junction speed, so the two never add up past j_i.
    if (!std::isinf(nb.j_mm_s3) || !std::isinf(prev.j_mm_s3)) {
      const Vec dk = nb.curvature(0) - prev.curvature(prev.length);
      const double dt = limits_.period_s;
      nb.v2_junction = std::min(nb.v2_junction, curvature_step_v2(dk, limits_, config_.curvature_step_share));
      // The largest share of an axis's jerk budget the step takes, and what each neighbour keeps of
      // its path jerk; a junction that would leave a plane arc less than a quarter of what plain
      // shares keep (a stiff axis next to a soft one, a fast crossing onto a small radius) is crossed
      // slower instead.
      for (int halvings = 0;; ++halvings) {
        double used = 0;
        Vec step_j{};  // the jerk the step puts on each axis (mm/s³)
        for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
          const double d = std::abs(dk[i]);
          if (d < 1e-12 || !(limits_.axis[i].j_max_mm_s3 > 0)) continue;
          step_j[i] = nb.v2_junction * d / dt;
          used = std::max(used, step_j[i] / limits_.axis[i].j_max_mm_s3);
        }
        if (!(used > 0)) break;
        const double v = std::sqrt(nb.v2_junction);
        const double f_nb = jerk_left_by_step(step_j, nb, 0, v, limits_);
        const double f_prev = jerk_left_by_step(step_j, prev, prev.length, v, limits_);
        if (prev_visible && f_prev < 1) {  // (pushed after a flush before the path got there) a stop: the step at rest
          nb.v2_junction = 0;
          break;
        }
        if (std::min(f_nb, f_prev) < 0.25 * (1 - used)) {
          if (halvings == 40) {  // (never seen) a stop: the step then happens at rest
            nb.v2_junction = 0;
            break;
          }
          nb.v2_junction *= 0.5;
          continue;
        }
        nb.j_mm_s3 *= f_nb;
        prev.j_mm_s3 *= f_prev;
        break;
      }
    }
  }
  // An exact stop (or the window's start) before nb: the blocks on either side run from or to rest.
  if (config_.limit_to_reach) {
    // Past this reach from rest no block's cap can be met: the diagonal of every axis's speed.
    double v_top2 = 0;
    for (std::size_t i = 0; i < core::kMaxAxes; ++i)
      if (limits_.present(i)) v_top2 += limits_.axis[i].v_max_mm_s * limits_.axis[i].v_max_mm_s;
    const double v_top = std::sqrt(v_top2);
    // Forwards from the last rest point: nothing has planned into nb yet.
    if (nb.v2_junction == 0) reach_d_ = reach_a_ = reach_j_ = 0;
    if (reach_d_ >= 0) {
      if (limit_to_reach(nb, true, reach_d_, reach_a_, reach_j_)) nb.v2_junction = std::min(nb.v2_junction, nb.v_cap_mm_s * nb.v_cap_mm_s);
      reach_d_ += nb.length;
      reach_a_ = std::max(reach_a_, nb.a_mm_s2);
      reach_j_ = std::max(reach_j_, nb.j_mm_s3);
      if (!std::isfinite(reach_j_) || reach_from_rest(reach_d_, reach_a_, reach_j_) >= v_top) reach_d_ = -1;
    }
    // Backwards from a new stop, while a motion coming to rest there could still be below a cap.
    if (nb.v2_junction == 0 && !from_rest) {
      double d = 0, a_max = 0, j_max = 0;
      bool changed = false;
      for (std::size_t k = ring.size() - 1, walked = 0; k-- > 0 && walked++ < kReachBlocks;) {
        Block& pb = ring.at(k);
        if (limit_to_reach(pb, false, d, a_max, j_max)) {
          pb.v2_junction = std::min(pb.v2_junction, pb.v_cap_mm_s * pb.v_cap_mm_s);
          changed = true;
        }
        d += pb.length;
        a_max = std::max(a_max, pb.a_mm_s2);
        j_max = std::max(j_max, pb.j_mm_s3);
        if (pb.v2_junction == 0 || !std::isfinite(j_max) || reach_from_rest(d, a_max, j_max) >= v_top) break;
      }
      if (changed) ring.touch();  // readers that keep what they derived from the blocks begin again
    }
  }
  queue_.unsettled_ = std::min(queue_.unsettled_ + 1, ring.size());
}

}  // namespace softmc::motion
