// Line and arc/helix geometry, and the dispatch to polynomial curves.
#include "motion/geometry/segment.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <type_traits>

namespace softmc::motion {

// The planner's ring holds thousands of these; keep the value small enough to copy every cycle.
static_assert(sizeof(Segment) <= 1536, "Segment grew past 1.5 KB");  // 1328 bytes today
static_assert(std::is_trivially_copyable_v<Segment>, "queues copy Segments bytewise");

Segment make_line(const Vec& start, const Vec& end) {
  Segment s;
  set_line(s, start, end);
  return s;
}

void set_line(Segment& s, const Vec& start, const Vec& end) {
  s.kind = SegmentKind::Line;
  s.start = start;
  s.end = end;
  s.length = core::distance(start, end);
  s.dir = s.length > 0 ? (end - start) * (1.0 / s.length) : Vec{};
  s.axis0 = 0;
  s.axis1 = 1;
  s.c0 = s.c1 = s.radius = s.theta0 = s.sweep = s.dradius = 0;
  s.linear = Vec{};
}

Segment make_arc(const Vec& start, const Vec& end, std::uint8_t axis0, std::uint8_t axis1, double c0, double c1,
                 int turns) {
  constexpr double kTwoPi = 2 * std::numbers::pi;
  Segment s;
  s.kind = SegmentKind::Arc;
  s.start = start;
  s.end = end;
  s.axis0 = axis0;
  s.axis1 = axis1;
  s.c0 = c0;
  s.c1 = c1;
  s.radius = std::hypot(start[axis0] - c0, start[axis1] - c1);
  s.dradius = std::hypot(end[axis0] - c0, end[axis1] - c1) - s.radius;
  s.theta0 = std::atan2(start[axis1] - c1, start[axis0] - c0);
  const double theta1 = std::atan2(end[axis1] - c1, end[axis0] - c0);
  const int n = std::abs(turns);
  if (turns >= 0) {
    double d = theta1 - s.theta0;
    while (d <= 1e-12) d += kTwoPi;  // a closed arc is a full circle
    s.sweep = d + (n - 1) * kTwoPi;
  } else {
    double d = theta1 - s.theta0;
    while (d >= -1e-12) d -= kTwoPi;
    s.sweep = d - (n - 1) * kTwoPi;
  }
  Vec lin = end - start;
  lin[axis0] = 0;
  lin[axis1] = 0;
  // In-plane length of the spiral r(φ) = r0 + dr·φ/|sweep|: ∫ √(r² + (dr/sweep)²) dφ, by 8-point
  // Gauss–Legendre (the integrand is smooth and nearly constant: exact to rounding).
  double arc_len = s.radius * std::abs(s.sweep);
  if (s.dradius != 0) {
    static constexpr double kX[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
    static constexpr double kW[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
    const double rp = s.dradius / std::abs(s.sweep);
    arc_len = 0;
    for (int k = 0; k < 4; ++k)
      for (const double sg : {-1.0, 1.0}) {
        const double f = 0.5 * (1 + sg * kX[k]);
        arc_len += kW[k] * std::hypot(s.radius + s.dradius * f, rp);
      }
    arc_len *= 0.5 * std::abs(s.sweep);
  }
  const double lin_len = core::norm(lin);
  s.length = std::hypot(arc_len, lin_len);
  if (s.length > 0) s.linear = lin * (1.0 / s.length);
  return s;
}

// rt-safe
Segment trimmed(const Segment& g, double s0, double s1) {
  if (g.kind == SegmentKind::Poly || !(g.length > 0)) return g;
  s0 = std::clamp(s0, 0.0, g.length);
  s1 = std::clamp(s1, s0, g.length);
  if (g.kind == SegmentKind::Line) return make_line(g.point(s0), g.point(s1));
  Segment t = g;
  const double f0 = s0 / g.length, f = (s1 - s0) / g.length;
  t.start = g.point(s0);
  t.end = g.point(s1);
  t.theta0 = g.theta0 + g.sweep * f0;
  t.radius = g.radius + g.dradius * f0;
  t.sweep = g.sweep * f;
  t.dradius = g.dradius * f;
  t.length = s1 - s0;  // `linear` is per unit of s: unchanged
  return t;
}

// rt-safe
Vec Segment::point(double s) const {
  if (s <= 0) return start;
  if (s >= length) return end;
  if (kind == SegmentKind::Line) return start + dir * s;
  if (kind == SegmentKind::Poly) return poly.at(poly.param_at(s));
  const double th = theta0 + sweep * (s / length);
  const double r = radius + dradius * (s / length);
  Vec p = start + linear * s;
  p[axis0] = c0 + r * std::cos(th);
  p[axis1] = c1 + r * std::sin(th);
  return p;
}

// A stationary point (motion::stationary: tangent_curvature takes the direction of C''). At a
// curve's end (a piece split at a cusp) the curve arrives against C'': C'(1 − ε) = −ε·C''(1).

// rt-safe
Vec Segment::tangent(double s) const {
  if (kind == SegmentKind::Line) return dir;
  if (kind == SegmentKind::Poly) {
    const double u = poly.param_at(s);
    const CurveDerivs d = poly.derivs(u);
    return u >= 1 && stationary(d) ? unit_tangent(d) * -1.0 : unit_tangent(d);
  }
  if (length <= 0) return Vec{};
  const double f = std::clamp(s, 0.0, length) / length;
  const double th = theta0 + sweep * f;
  const double k = (radius + dradius * f) * sweep / length;  // r·dθ/ds, signed
  const double kr = dradius / length;                         // dr/ds
  Vec t = linear;
  t[axis0] = -std::sin(th) * k + std::cos(th) * kr;
  t[axis1] = std::cos(th) * k + std::sin(th) * kr;
  return t;
}

// rt-safe
Vec Segment::curvature(double s) const {
  Vec k{};
  if (kind == SegmentKind::Line || length <= 0) return k;
  if (kind == SegmentKind::Poly) return curvature_vector(poly.derivs(poly.param_at(s)));
  const double f = std::clamp(s, 0.0, length) / length;
  const double th = theta0 + sweep * f;
  const double w = sweep / length;  // d(angle)/ds
  const double r = radius + dradius * f;
  const double c = 2 * (dradius / length) * w;  // the spiral's 2·r'·θ' along the angle's direction
  k[axis0] = -r * w * w * std::cos(th) - c * std::sin(th);
  k[axis1] = -r * w * w * std::sin(th) + c * std::cos(th);
  return k;
}

double Segment::distance_to(const Vec& p, double enough) const {
  if (kind == SegmentKind::Line) {
    if (length <= 0) return core::distance(p, start);
    const double t = std::clamp(core::dot(p - start, dir), 0.0, length);
    return core::distance(p, start + dir * t);
  }
  if (kind == SegmentKind::Poly) return poly.distance_to(p);
  // Arc/helix: the parameter is found from the in-plane angle, unwrapped to each turn of the sweep,
  // then refined by Newton steps on the squared distance (helix pitch couples them). Every candidate
  // is a point of the curve, so the answer is never below the true distance. On a helix the nearest
  // point can lie far from p's angle (or inside the sweep while that angle is outside it), so Newton
  // also starts from both ends and from where the linear axes match p's.
  constexpr double kTwoPi = 2 * std::numbers::pi;
  const double ang = std::atan2(p[axis1] - c1, p[axis0] - c0);
  double best = std::min(core::distance(p, start), core::distance(p, end));
  const double lo = std::min(0.0, sweep), hi = std::max(0.0, sweep);
  double base = ang - theta0;
  base -= kTwoPi * std::floor((base - lo) / kTwoPi);  // in [lo, lo + 2π)
  // A circle in its plane (no spiral, no helix): the point at p's angle is the nearest, exactly.
  const double lin2 = core::dot(linear, linear);
  const bool circle = dradius == 0 && lin2 == 0;
  const auto refine = [&](double s) {  // true: done (best ≤ enough)
    for (int it = 0; it < 12; ++it) {  // Newton on f(s) = (P(s) - p)·P'(s)
      const CurveFrame fr = frame(s);
      const Vec d = fr.point - p;
      best = std::min(best, core::norm(d));
      if (best <= enough) return true;
      const double f = core::dot(d, fr.tangent);
      // f' = |P'|² + (P − p)·P'': a spiral's s is not its arc length, |P'| ≠ 1 (with 1 here Newton
      // converged only linearly and could stop microns short within its 12 steps; a review's find).
      const double df = core::dot(fr.tangent, fr.tangent) + core::dot(d, fr.curvature);
      if (!(df > 1e-12)) return false;  // not towards a minimum from here
      const double next = std::clamp(s - f / df, 0.0, length);
      if (std::abs(next - s) <= 1e-15 * length) break;
      s = next;
    }
    best = std::min(best, core::distance(p, point(s)));
    return best <= enough;
  };
  if (circle) {
    for (double rel = base; rel <= hi + 1e-12; rel += kTwoPi) best = std::min(best, core::distance(p, point(length * (rel / sweep))));
    return best;
  }
  if (best <= enough) return best;
  for (double rel = base; rel <= hi + 1e-12; rel += kTwoPi)
    if (refine(length * (rel / sweep))) return best;
  if (refine(0) || refine(length)) return best;
  if (lin2 > 0) refine(std::clamp(core::dot(p - start, linear) / lin2, 0.0, length));
  return best;
}

// rt-safe
void Segment::bounds(Vec& lo, Vec& hi) const {
  if (kind == SegmentKind::Poly) {  // computed once at construction (bernstein_range.hpp)
    lo = poly.box_lo;
    hi = poly.box_hi;
    return;
  }
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    lo[i] = std::min(start[i], end[i]);
    hi[i] = std::max(start[i], end[i]);
  }
  if (kind != SegmentKind::Arc) return;
  // The in-plane extremes lie at the quarter angles the sweep passes over (a spiral: within its
  // larger radius there).
  const double radius = this->radius + std::max(0.0, dradius);
  if (std::abs(sweep) >= 2 * std::numbers::pi) {
    lo[axis0] = std::min(lo[axis0], c0 - radius);
    hi[axis0] = std::max(hi[axis0], c0 + radius);
    lo[axis1] = std::min(lo[axis1], c1 - radius);
    hi[axis1] = std::max(hi[axis1], c1 + radius);
    return;
  }
  const double a0 = std::min(theta0, theta0 + sweep), a1 = std::max(theta0, theta0 + sweep);
  const double q = std::numbers::pi / 2;
  for (double k = std::ceil(a0 / q); k * q <= a1; k += 1) {
    const double x = c0 + radius * std::cos(k * q), y = c1 + radius * std::sin(k * q);
    lo[axis0] = std::min(lo[axis0], x);
    hi[axis0] = std::max(hi[axis0], x);
    lo[axis1] = std::min(lo[axis1], y);
    hi[axis1] = std::max(hi[axis1], y);
  }
}

// rt-safe
CurveFrame Segment::frame(double s) const {
  if (kind != SegmentKind::Poly) return {point(s), tangent(s), curvature(s)};
  CurveFrame f;
  if (s <= 0) {
    f.point = start;
  } else if (s >= length) {
    f.point = end;
  }
  const CurveDerivs d = poly.derivs(poly.param_at(s));
  if (s > 0 && s < length) f.point = d.c;
  tangent_curvature(d, poly.moving.data(), poly.n_moving, f.tangent, f.curvature);  // both in one pass, moving axes
  if (s >= length && stationary(d)) f.tangent = f.tangent * -1.0;
  return f;
}

namespace {
// Largest |sin| (phase = π/2) or |cos| (phase = 0) over the angles [a0, a1].
double max_abs_trig(double a0, double a1, double phase) {
  const double pi = std::numbers::pi;
  if (std::floor((a1 - phase) / pi) > std::floor((a0 - phase) / pi) || a1 - a0 >= pi) return 1;
  return std::max(std::abs(std::cos(a0 - phase)), std::abs(std::cos(a1 - phase)));
}
}  // namespace

// rt-safe
Vec Segment::max_abs_tangent() const {
  if (kind == SegmentKind::Poly) return poly.max_abs_tangent;
  Vec m;
  if (kind == SegmentKind::Line) {
    for (std::size_t i = 0; i < core::kMaxAxes; ++i) m[i] = std::abs(dir[i]);
    return m;
  }
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) m[i] = std::abs(linear[i]);
  if (length <= 0) return m;
  // The in-plane tangent is r·sweep/L·(-sin θ, cos θ) (+ dr/L·(cos θ, sin θ) on a spiral).
  const double k = arc_bounds().inplane;
  const double a0 = std::min(theta0, theta0 + sweep), a1 = std::max(theta0, theta0 + sweep);
  m[axis0] = k * max_abs_trig(a0, a1, std::numbers::pi / 2);
  m[axis1] = k * max_abs_trig(a0, a1, 0);
  return m;
}

// rt-safe
Vec Segment::max_abs_normal() const {
  Vec m;
  if (kind != SegmentKind::Arc) return m;
  const double a0 = std::min(theta0, theta0 + sweep), a1 = std::max(theta0, theta0 + sweep);
  m[axis0] = max_abs_trig(a0, a1, 0);  // the normal is −(cos θ, sin θ)
  m[axis1] = max_abs_trig(a0, a1, std::numbers::pi / 2);
  return m;
}

// rt-safe
double Segment::max_curvature() const {
  if (kind == SegmentKind::Poly) return poly.max_curvature;
  if (kind == SegmentKind::Line || length <= 0) return 0;
  return arc_bounds().kappa;
}

// rt-safe
Segment::ArcBounds Segment::arc_bounds() const {
  ArcBounds b;
  if (kind != SegmentKind::Arc || !(length > 0)) return b;
  const double w = std::abs(sweep) / length, rp = std::abs(dradius) / length;
  const double r_max = radius + std::max(0.0, dradius), r_min = radius + std::min(0.0, dradius);
  b.inplane = std::hypot(r_max * w, rp);
  b.kappa = r_max * w * w + 2 * rp * w;
  // p = r·e_r in the plane with θ' = ω, r' = rp: p''' = −3·r'·ω²·e_r − r·ω³·e_θ.
  b.k_speed = r_max * w * w * w + 3 * rp * w * w;
  // tangent·curvature = r·r'·θ'² (zero on a circle); |a_t·T + w·K|² ≤ (1 + η)(a_t²|T|² + w²|K|²)
  // with η = |T·K| / (|T|·|K|), so share = 1/√(1 + η).
  if (rp > 0 && r_min > 0) {
    const double eta = r_max * rp * w * w / (r_min * w * (r_min * w * w));
    b.share = 1 / std::sqrt(1 + eta);
  }
  return b;
}

}  // namespace softmc::motion
