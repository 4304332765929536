// What a segment allows: its speed, acceleration and jerk limits from the axes' (segment_limits,
// blend_limits) and its tangential law (segment_law, blend_law) (docs/planner.md, "Jerk").
#include "motion/planner/planner.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "motion/planner/planner_detail.hpp"

namespace softmc::motion {

using namespace planner_detail;

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

// Axes moving at v·|rate_i| (a line's direction, an arc's axes outside its plane): the path speed is
// limited by v_max_i / |rate_i|, likewise acceleration and jerk.
void linear_limits(SegmentLimits& l, const MachineLimits& lim, const Vec& rate) {
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    const double d = std::abs(rate[i]);
    if (d < 1e-12) continue;
    l.v_max_mm_s = std::min(l.v_max_mm_s, lim.axis[i].v_max_mm_s / d);
    l.a_max_mm_s2 = std::min(l.a_max_mm_s2, lim.axis[i].a_max_mm_s2 / d);
    if (lim.axis[i].j_max_mm_s3 > 0) l.j_max_mm_s3 = std::min(l.j_max_mm_s3, lim.axis[i].j_max_mm_s3 / d);
  }
}

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
    linear_limits(l, lim, g.dir);
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
    linear_limits(l, lim, g.linear);  // the axes outside the plane
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
}  // namespace softmc::motion
