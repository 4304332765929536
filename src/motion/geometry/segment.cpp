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

namespace {

// A spiral arc, r(φ) = r0 + b·φ for the angle φ ∈ [0, |sweep|] turned from the start (b ≠ 0).
// In-plane length from φ = 0 to φ: [r·q + b²·ln(r + q)] / (2b) between r0 and r(φ), q = √(r² + b²),
// written without the cancellation of its two large terms when b is small (r·q − r0·q0 =
// b·φ·(r + r0)·(r² + r0² + b²) / (r·q + r0·q0), and ln((r + q)/(r0 + q0)) as a log1p). rt-safe.
double spiral_length(double r0, double q0, double b, double phi, double r1, double q1) {
  const double den = r1 * q1 + r0 * q0;
  if (!(den > 0)) return 0;
  return phi * (r1 + r0) * (r1 * r1 + r0 * r0 + b * b) / (2 * den) +
         0.5 * b * std::log1p(b * phi * (1 + (r1 + r0) / (q1 + q0)) / (r0 + q0));
}
double spiral_length(double r0, double q0, double b, double phi) {
  const double r1 = r0 + b * phi;
  return spiral_length(r0, q0, b, phi, r1, std::sqrt(r1 * r1 + b * b));
}

struct SpiralAngle {
  double phi, r, q;  // angle turned, radius there, √(r² + b²) = dσ/dφ
};
// The angle at in-plane length σ: on slight spirals the root of a quadratic (below), otherwise
// Newton on spiral_length from the root of its second-order expansion r0·φ + b·φ²/2 = σ, which is
// already within (b/r)² of it (a step or two, a few on strong spirals). Newton's next error is at most |b|·d²/(2q) for a step d: the loop
// ends when that is below rounding. rt-safe.
SpiralAngle spiral_angle(double r0, double b, double sigma, double phi_max) {
  const double r1 = r0 + b * phi_max, r_min = std::min(r0, r1);
  if (std::abs(b) <= 1e-4 * r_min && std::abs(r1 - r0) <= 1e-3 * r_min) {
    // G-code's slight spirals (the program's rounding): with ε = b/r within 1e-4 and x = b·φ/r0
    // within 1e-3, σ = (r0 + b²/2r0)·φ + (b/2 − b³/4r0²)·φ² to 2e-15 of itself (the next terms
    // are ε⁴/8 and ε²·x²/6 of it): a quadratic, whose root is the angle.
    const double B = r0 + 0.5 * b * b / r0, C = 0.5 * b - 0.25 * b * b * b / (r0 * r0);
    const double phi = std::clamp(2 * sigma / (B + std::sqrt(B * B + 4 * C * sigma)), 0.0, phi_max);
    const double r = r0 + b * phi;
    return {phi, r, std::sqrt(r * r + b * b)};
  }
  const double q0 = std::sqrt(r0 * r0 + b * b);
  const double den = r0 + std::sqrt(std::max(0.0, r0 * r0 + 2 * b * sigma));
  double phi = std::clamp(den > 0 ? 2 * sigma / den : sigma / q0, 0.0, phi_max);
  double r = r0 + b * phi, q = std::sqrt(r * r + b * b);
  for (int it = 0; it < 16; ++it) {
    const double d = (spiral_length(r0, q0, b, phi, r, q) - sigma) / q;
    const double next = std::clamp(phi - d, 0.0, phi_max);
    r = r0 + b * next;
    if (std::abs(b) * d * d <= 1e-17 * q * phi_max) {  // converged: q moves by its slope r·b/q
      q += (next - phi) * r * b / q;
      phi = next;
      break;
    }
    phi = next;
    q = std::sqrt(r * r + b * b);
  }
  return {phi, r, q};
}

}  // namespace

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
  s.dir = line_direction(start, end, s.length);
  s.axis0 = 0;
  s.axis1 = 1;
  s.c0 = s.c1 = s.radius = s.theta0 = s.sweep = s.dradius = s.plane_rate = 0;
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
  // In-plane length of the spiral r(φ) = r0 + dr·φ/|sweep| in closed form (a circle's r·|sweep|).
  double arc_len = s.radius * std::abs(s.sweep);
  if (s.dradius != 0) {
    const double b = s.dradius / std::abs(s.sweep);
    arc_len = spiral_length(s.radius, std::sqrt(s.radius * s.radius + b * b), b, std::abs(s.sweep));
  }
  const double lin_len = core::norm(lin);
  s.length = std::hypot(arc_len, lin_len);
  if (s.length > 0) {
    s.linear = lin * (1.0 / s.length);
    s.plane_rate = arc_len / s.length;
  }
  return s;
}

namespace {
// An arc at s: angle, radius and the in-plane derivatives d(angle)/ds-related terms, from one
// angle search. On a circle the angle is linear in s (the formulas of before spirals were exact).
struct ArcAt {
  double th, r;
  double dphi = 0, ddphi = 0, b = 0, sg = 1;  // spirals: dφ/ds, d²φ/ds², dr/dφ, direction of turn
  double c = 1, sn = 0;                        // cos θ, sin θ: one sincos for point, tangent and curvature
};
ArcAt arc_at(const Segment& g, double s) {
  const double f = std::clamp(s, 0.0, g.length) / g.length;
  ArcAt a{g.theta0 + g.sweep * f, g.radius};
  if (g.dradius != 0) {
    const double sweep = std::abs(g.sweep), b = g.dradius / sweep, sg = g.sweep > 0 ? 1.0 : -1.0;
    const SpiralAngle sa = spiral_angle(g.radius, b, g.plane_rate * std::clamp(s, 0.0, g.length), sweep);
    const double dphi = g.plane_rate / sa.q;
    a = {g.theta0 + sg * sa.phi, sa.r, dphi, -dphi * dphi * sa.r * b / (sa.q * sa.q), b, sg};
  }
  a.c = std::cos(a.th);
  a.sn = std::sin(a.th);
  return a;
}
// rt-safe. The point at s from its angle and radius (the linear axes move with s).
Vec arc_point(const Segment& g, const ArcAt& a, double s) {
  Vec p = g.start + g.linear * s;
  p[g.axis0] = g.c0 + a.r * a.c;
  p[g.axis1] = g.c1 + a.r * a.sn;
  return p;
}
// rt-safe. The in-plane parts: on a spiral dp/dφ = b·e_r + sg·r·e_θ and
// d²p/dφ² = 2·b·sg·e_θ − r·e_r, with e_r = (cos θ, sin θ), e_θ = (−sin θ, cos θ).
Vec arc_tangent(const Segment& g, const ArcAt& a) {
  const double c = a.c, sn = a.sn;
  Vec t = g.linear;
  if (g.dradius == 0) {
    const double k = g.radius * g.sweep / g.length;  // r·dθ/ds, signed
    t[g.axis0] = -sn * k;
    t[g.axis1] = c * k;
    return t;
  }
  const double rt = a.sg * a.r;
  t[g.axis0] = a.dphi * (a.b * c - rt * sn);
  t[g.axis1] = a.dphi * (a.b * sn + rt * c);
  return t;
}

Vec arc_curvature(const Segment& g, const ArcAt& a) {
  const double c = a.c, sn = a.sn;
  Vec k{};
  if (g.dradius == 0) {
    const double w = g.sweep / g.length;  // d(angle)/ds
    k[g.axis0] = -g.radius * w * w * c;
    k[g.axis1] = -g.radius * w * w * sn;
    return k;
  }
  const double d2 = a.dphi * a.dphi, rt = a.sg * a.r, bt = 2 * a.b * a.sg;
  k[g.axis0] = d2 * (-bt * sn - a.r * c) + a.ddphi * (a.b * c - rt * sn);
  k[g.axis1] = d2 * (bt * c - a.r * sn) + a.ddphi * (a.b * sn + rt * c);
  return k;
}
}  // namespace

// rt-safe
Segment trimmed(const Segment& g, double s0, double s1) {
  if (g.kind == SegmentKind::Poly || !(g.length > 0)) return g;
  s0 = std::clamp(s0, 0.0, g.length);
  s1 = std::clamp(s1, s0, g.length);
  if (g.kind == SegmentKind::Line) return make_line(g.point(s0), g.point(s1));
  Segment t = g;
  t.start = g.point(s0);
  t.end = g.point(s1);
  t.length = s1 - s0;  // `linear` and `plane_rate` are per unit of s: unchanged
  if (g.dradius == 0) {
    const double f0 = s0 / g.length, f = (s1 - s0) / g.length;
    t.theta0 = g.theta0 + g.sweep * f0;
    t.sweep = g.sweep * f;
    return t;
  }
  const ArcAt a0 = arc_at(g, s0), a1 = arc_at(g, s1);
  t.theta0 = a0.th;
  t.radius = a0.r;
  t.sweep = a1.th - a0.th;
  t.dradius = a0.b * std::abs(t.sweep);  // the same dr/dφ, so the same curve
  return t;
}

// rt-safe
Vec Segment::point(double s) const {
  if (s <= 0) return start;
  if (s >= length) return end;
  if (kind == SegmentKind::Line) return start + dir * s;
  if (kind == SegmentKind::Poly) return poly.at(poly.param_at(s));
  return arc_point(*this, arc_at(*this, s), s);
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
  return arc_tangent(*this, arc_at(*this, s));
}

// rt-safe
Vec Segment::curvature(double s) const {
  Vec k{};
  if (kind == SegmentKind::Line || length <= 0) return k;
  if (kind == SegmentKind::Poly) return curvature_vector(poly.derivs(poly.param_at(s)));
  return arc_curvature(*this, arc_at(*this, s));
}

// rt-safe
Vec line_direction(const Vec& start, const Vec& end, double length) {
  return length > 0 ? (end - start) * (1.0 / length) : Vec{};
}

double line_distance(const Vec& start, const Vec& dir, double length, const Vec& p) {
  if (length <= 0) return core::distance(p, start);
  const double t = std::clamp(core::dot(p - start, dir), 0.0, length);
  return core::distance(p, start + dir * t);
}

double Segment::distance_to(const Vec& p, double enough) const {
  if (kind == SegmentKind::Line) return line_distance(start, dir, length, p);
  if (kind == SegmentKind::Poly) return poly.distance_to(p, enough);
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
  bool settled = false;  // a Newton start came to rest on a minimum of the distance
  const auto refine = [&](double s) {  // true: done (best ≤ enough)
    for (int it = 0; it < 12; ++it) {  // Newton on f(s) = (P(s) - p)·P'(s)
      const CurveFrame fr = frame(s);
      const Vec d = fr.point - p;
      best = std::min(best, core::norm(d));
      if (best <= enough) return true;
      const double f = core::dot(d, fr.tangent);
      // f' = |P'|² + (P − p)·P'' (|P'| = 1 to rounding on lines and arcs; Poly curves too).
      const double df = core::dot(fr.tangent, fr.tangent) + core::dot(d, fr.curvature);
      if (!(df > 1e-12)) return false;  // not towards a minimum from here
      const double next = std::clamp(s - f / df, 0.0, length);
      if (std::abs(next - s) <= std::max(1e-15 * length, 1e-12)) {  // (a picometre: the rounding of the positions)
        settled = true;
        break;
      }
      s = next;
    }
    best = std::min(best, core::distance(p, point(s)));
    return best <= enough;
  };
  if (circle) {
    // The nearest point of the whole circle, where p's angle lies within the sweep: at p's in-plane
    // distance ρ from the centre, |ρ − R| in the plane, and the other axes are the start's (no
    // point to evaluate: a fillet's search asks this ~1 500 times a try).
    if (base <= hi + 1e-12) {
      double off2 = 0;
      for (std::size_t i = 0; i < core::kMaxAxes; ++i)
        if (i != axis0 && i != axis1) off2 += (p[i] - start[i]) * (p[i] - start[i]);
      const double dr = std::hypot(p[axis0] - c0, p[axis1] - c1) - radius;
      best = std::min(best, std::sqrt(dr * dr + off2));
    }
    return best;
  }
  if (best <= enough) return best;
  // The arc length at an angle turned from the start (a spiral's is not linear in it).
  const auto s_at = [&](double rel) {
    if (dradius == 0 || !(plane_rate > 0)) return length * (rel / sweep);
    const double b = dradius / std::abs(sweep);
    return std::clamp(spiral_length(radius, std::sqrt(radius * radius + b * b), b, std::abs(rel)) / plane_rate, 0.0, length);
  };
  for (double rel = base; rel <= hi + 1e-12; rel += kTwoPi)
    if (refine(s_at(rel))) return best;
  // A slight spiral in its plane (a G-code arc whose end is off its circle by the rounding, at most
  // 1 % of the radius) is a circle to within that: its distance has a minimum only at p's angle on
  // each turn (found above) and at the ends (in best). Where Newton settled there, starting it again
  // from the ends finds nothing nearer (a blend's fit asks this ~150 times a try: 7·10⁶ instructions
  // a cycle at plasma.ngc's arc-to-arc corners without it).
  if (settled && lin2 == 0 && std::abs(dradius) <= 0.01 * std::min(radius, radius + dradius)) return best;
  if (refine(0) || refine(length)) return best;
  if (lin2 > 0) refine(std::clamp(core::dot(p - start, linear) / lin2, 0.0, length));
  return best;
}

// rt-safe
void line_bounds(const Vec& a, const Vec& b, Vec& lo, Vec& hi) {
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    lo[i] = std::min(a[i], b[i]);
    hi[i] = std::max(a[i], b[i]);
  }
}

void Segment::bounds(Vec& lo, Vec& hi) const {
  if (kind == SegmentKind::Poly) {  // computed once at construction (bernstein_range.hpp)
    lo = poly.box_lo;
    hi = poly.box_hi;
    return;
  }
  line_bounds(start, end, lo, hi);
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
  if (kind == SegmentKind::Line) return {point(s), dir, Vec{}};
  if (kind == SegmentKind::Arc) {
    if (!(length > 0)) return {start, Vec{}, Vec{}};
    const ArcAt a = arc_at(*this, s);
    const Vec p = s <= 0 ? start : s >= length ? end : arc_point(*this, a, s);
    return {p, arc_tangent(*this, a), arc_curvature(*this, a)};
  }
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
  // The in-plane tangent is plane_rate·(-sin θ, cos θ) on a circle turning positively.
  const double k = arc_bounds().inplane;
  if (dradius == 0) {
    const double a0 = std::min(theta0, theta0 + sweep), a1 = std::max(theta0, theta0 + sweep);
    m[axis0] = k * max_abs_trig(a0, a1, std::numbers::pi / 2);
    m[axis1] = k * max_abs_trig(a0, a1, 0);
    return m;
  }
  const auto [a0, a1] = tangent_angles();
  m[axis0] = k * max_abs_trig(a0, a1, 0);
  m[axis1] = k * max_abs_trig(a0, a1, std::numbers::pi / 2);
  return m;
}

// rt-safe
Vec Segment::max_abs_normal() const {
  Vec m;
  if (kind != SegmentKind::Arc) return m;
  if (dradius == 0) {
    const double a0 = std::min(theta0, theta0 + sweep), a1 = std::max(theta0, theta0 + sweep);
    m[axis0] = max_abs_trig(a0, a1, 0);  // the normal is −(cos θ, sin θ)
    m[axis1] = max_abs_trig(a0, a1, std::numbers::pi / 2);
    return m;
  }
  const auto [a0, a1] = tangent_angles();  // the normal is the tangent turned by a right angle
  m[axis0] = max_abs_trig(a0, a1, std::numbers::pi / 2);
  m[axis1] = max_abs_trig(a0, a1, 0);
  return m;
}

// rt-safe. The range of the in-plane tangent's direction ψ: θ ± π/2 on a circle; on a spiral
// dp/dφ = b·e_r + sg·r·e_θ points at θ + atan2(sg·r, b), whose second term runs monotonically
// between its values at the two radii (a range that holds both sums is a bound).
std::pair<double, double> Segment::tangent_angles() const {
  const double a0 = std::min(theta0, theta0 + sweep), a1 = std::max(theta0, theta0 + sweep);
  const double sg = sweep > 0 ? 1.0 : -1.0;
  if (dradius == 0) return {a0 + sg * std::numbers::pi / 2, a1 + sg * std::numbers::pi / 2};
  const double b = dradius / std::abs(sweep);
  const double d0 = std::atan2(sg * radius, b), d1 = std::atan2(sg * (radius + dradius), b);
  return {a0 + std::min(d0, d1), a1 + std::max(d0, d1)};
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
  if (dradius == 0) {  // a circle (or a circular helix)
    const double w = std::abs(sweep) / length;
    b.inplane = radius * w;
    b.kappa = radius * w * w;
    b.k_speed = radius * w * w * w;
    return b;
  }
  // A spiral r = r0 + β·φ of in-plane arc length σ = plane_rate·s: its curvature in σ is
  // f(r) = (r² + 2β²)/(r² + β²)^{3/2}, largest at the smallest radius (f' < 0), and
  // |d³p/dσ³| = √(f'² (β/q)² + f⁴) ≤ f² + |β|·r(r² + 4β²)/(r² + β²)³, bounded with the largest r
  // above and the smallest below. Each s-derivative adds a factor plane_rate.
  const double beta = std::abs(dradius) / std::abs(sweep), b2 = beta * beta;
  const double r_max = radius + std::max(0.0, dradius), r_min = std::max(0.0, radius + std::min(0.0, dradius));
  const double q_min2 = r_min * r_min + b2;
  const double f_max = (r_min * r_min + 2 * b2) / (q_min2 * std::sqrt(q_min2));
  const double c = plane_rate;
  b.inplane = c;
  b.kappa = c * c * f_max;
  b.k_speed = c * c * c * (f_max * f_max + beta * r_max * (r_max * r_max + 4 * b2) / (q_min2 * q_min2 * q_min2));
  return b;
}

}  // namespace softmc::motion
