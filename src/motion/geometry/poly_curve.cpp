// Evaluation, arc length and its inversion for polynomial and rational curves.
#include "motion/geometry/poly_curve.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "motion/geometry/bernstein_range.hpp"
#include "motion/geometry/golden.hpp"

namespace softmc::motion {

namespace {

// 16-point Gauss–Legendre on [-1, 1]: the positive nodes and their weights (the rule is symmetric).
// Exact for polynomials of degree 31; on 1/32 of a smooth curve it meets 1e-9 relative with room.
constexpr std::array<double, 8> kGlX{0.09501250983763744, 0.2816035507792589, 0.45801677765722737,
                                     0.6178762444026438,  0.755404408355003,  0.8656312023878318,
                                     0.9445750230732326,  0.9894009349916499};
constexpr std::array<double, 8> kGlW{0.18945061045506847, 0.1826034150449236, 0.16915651939500256,
                                     0.14959598881657682, 0.12462897125553395, 0.0951585116824929,
                                     0.062253523938647776, 0.027152459411754058};
// 8-point rule: where the curve's construction found it agrees with the 16-point one on every
// table interval (PolyCurve::gl8_ok), s → u integrates its partial interval with it.
constexpr std::array<double, 4> kGl8X{0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                      0.9602898564975363};
constexpr std::array<double, 4> kGl8W{0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                      0.1012285362903763};
// 4-point rule for the tiny corrections of the Newton iteration.
constexpr std::array<double, 2> kGl4X{0.3399810435848563, 0.8611363115940526};
constexpr std::array<double, 2> kGl4W{0.6521451548625461, 0.34785484513745374};

constexpr double kH = 1.0 / kArcTableIntervals;

// de Casteljau on homogeneous points down to the last three levels gives C, C', C'' together.
//   level n-2: Q0 Q1 Q2   →  H'' = n(n-1)(Q2 - 2Q1 + Q0)
//   level n-1: R0 R1      →  H'  = n(R1 - R0),  H = (1-u)R0 + uR1
// then the quotient rule for C = H / W.
// ax[0 … m): the axes the curve moves (PolyCurve::moving); m = 0 before finalize found them: all.
// One axis `a` of a polynomial Bézier of degree N ≥ 1: de Casteljau down to the last levels (the
// arithmetic of the loop over any degree below, unrolled for N).
template <std::size_t N>
void poly_axis(const PolyCurve::BezierData& b, std::size_t a, double u, double v, CurveDerivs& d) {
  std::array<double, N + 1> q;
#pragma GCC unroll 8
  for (std::size_t i = 0; i <= N; ++i) q[i] = b.hctrl[i][a];
  // (Unrolled: -O2 keeps the loops, at twice the instructions of the arithmetic.)
#pragma GCC unroll 8
  for (std::size_t lvl = N; lvl > 2; --lvl)
#pragma GCC unroll 8
    for (std::size_t i = 0; i < lvl; ++i) q[i] = q[i] * v + q[i + 1] * u;
  if constexpr (N >= 2) {
    d.d2[a] = (q[2] - 2 * q[1] + q[0]) * static_cast<double>(N * (N - 1));
    q[0] = q[0] * v + q[1] * u;
    q[1] = q[1] * v + q[2] * u;
  }
  d.d1[a] = (q[1] - q[0]) * static_cast<double>(N);
  d.c[a] = q[0] * v + q[1] * u;
}
// A polynomial Bézier of degree N on the axes ax[0 … m) it moves (PolyCurve::poly_axes); the others
// stay at the first control point, with no derivative.
template <std::size_t N>
CurveDerivs poly_derivs(const PolyCurve::BezierData& b, double u, const std::uint8_t* ax, std::size_t m) {
  const double v = 1 - u;
  CurveDerivs d;
  d.c = b.hctrl[0];
  for (std::size_t j = 0; j < m; ++j) poly_axis<N>(b, ax[j], u, v, d);
  return d;
}

CurveDerivs bezier_derivs(const PolyCurve::BezierData& b, std::size_t n, double u, const std::size_t* ax,
                          std::size_t m) {
  if (n == 3 && b.w[0] == 1 && b.w[1] == 1 && b.w[2] == 1 && b.w[3] == 1) {
    // A polynomial cubic (splines, G5, smoothed CAM runs): the Bernstein forms of C, C', C'' directly,
    // without copying the control arrays — the most frequent curve, evaluated thousands of times at
    // construction and once per cycle. An axis it does not move stays exactly where it is.
    const Vec& p0 = b.hctrl[0];
    const Vec& p1 = b.hctrl[1];
    const Vec& p2 = b.hctrl[2];
    const Vec& p3 = b.hctrl[3];
    const double v = 1 - u;
    CurveDerivs d;
    if (m == 0) m = core::kMaxAxes, ax = kEveryAxis.data();
    else d.c = p0;
    for (std::size_t j = 0; j < m; ++j) {
      const std::size_t a = ax[j];
      const double d0 = p1[a] - p0[a], d1 = p2[a] - p1[a], d2 = p3[a] - p2[a];
      d.c[a] = v * v * v * p0[a] + 3 * v * u * (v * p1[a] + u * p2[a]) + u * u * u * p3[a];
      d.d1[a] = 3 * (v * v * d0 + 2 * v * u * d1 + u * u * d2);
      d.d2[a] = 6 * (v * (d1 - d0) + u * (d2 - d1));
    }
    return d;
  }
  bool polynomial = n >= 1;
  for (std::size_t i = 0; polynomial && i <= n; ++i) polynomial = b.w[i] == 1;
  if (polynomial) {
    // Any other polynomial degree (the planner's quintic corner blends, G5.1, G5.2): the same de
    // Casteljau levels, axis by axis on scalars, with no rational quotient and no Vec temporaries.
    const double v = 1 - u, nn = static_cast<double>(n * (n - 1)), n1 = static_cast<double>(n);
    CurveDerivs d;
    for (std::size_t a = 0; a < core::kMaxAxes; ++a) {
      bool moves = false;
      for (std::size_t i = 1; i <= n; ++i) moves = moves || b.hctrl[i][a] != b.hctrl[0][a];
      if (!moves) {  // an axis the curve does not move (most of nine): no derivative
        d.c[a] = b.hctrl[0][a];
        continue;
      }
      std::array<double, kMaxBezierDegree + 1> q;
      for (std::size_t i = 0; i <= n; ++i) q[i] = b.hctrl[i][a];
      for (std::size_t lvl = n; lvl > 2; --lvl)
        for (std::size_t i = 0; i < lvl; ++i) q[i] = q[i] * v + q[i + 1] * u;
      if (n >= 2) {
        d.d2[a] = (q[2] - 2 * q[1] + q[0]) * nn;
        q[0] = q[0] * v + q[1] * u;
        q[1] = q[1] * v + q[2] * u;
      }
      d.d1[a] = (q[1] - q[0]) * n1;
      d.c[a] = q[0] * v + q[1] * u;
    }
    return d;
  }
  std::array<Vec, kMaxBezierDegree + 1> p = b.hctrl;
  std::array<double, kMaxBezierDegree + 1> w = b.w;
  const double v = 1 - u;
  Vec h, h1, h2;
  double wh = 0, w1 = 0, w2 = 0;
  if (n == 0) {
    h = p[0];
    wh = w[0];
  } else {
    for (std::size_t lvl = n; lvl > 2; --lvl) {  // reduce n+1 points to 3
      for (std::size_t i = 0; i + 1 < lvl + 1; ++i) {
        p[i] = p[i] * v + p[i + 1] * u;
        w[i] = w[i] * v + w[i + 1] * u;
      }
    }
    if (n >= 2) {
      const double nn = static_cast<double>(n * (n - 1));
      h2 = (p[2] - p[1] * 2.0 + p[0]) * nn;
      w2 = (w[2] - 2 * w[1] + w[0]) * nn;
      for (std::size_t i = 0; i < 2; ++i) {
        p[i] = p[i] * v + p[i + 1] * u;
        w[i] = w[i] * v + w[i + 1] * u;
      }
    }
    h1 = (p[1] - p[0]) * static_cast<double>(n);
    w1 = (w[1] - w[0]) * static_cast<double>(n);
    h = p[0] * v + p[1] * u;
    wh = w[0] * v + w[1] * u;
  }
  CurveDerivs d;
  const double iw = 1.0 / wh;
  d.c = h * iw;
  d.d1 = (h1 - d.c * w1) * iw;
  d.d2 = (h2 - d.d1 * (2 * w1) - d.c * w2) * iw;
  // An axis the curve does not move has no derivative: the quotient rule leaves the rounding of
  // p·w there, which near a stationary point (|C'| → 0 at a cusp) turned the tangent off the curve.
  if (m > 0) {
    std::array<bool, core::kMaxAxes> moves{};
    for (std::size_t j = 0; j < m; ++j) moves[ax[j]] = true;
    for (std::size_t a = 0; a < core::kMaxAxes; ++a)
      if (!moves[a]) {
        d.c[a] = b.hctrl[0][a] / b.w[0];
        d.d1[a] = d.d2[a] = 0;
      }
  }
  return d;
}

// p(x), p'(x), p''(x) of the Newton form by a Horner-like recurrence from the innermost term.
void newton_eval(const PolyCurve::NewtonData& nd, std::size_t n, double x, double& p, double& dp, double& ddp) {
  p = nd.coef[n];
  dp = 0;
  ddp = 0;
  for (std::size_t k = n; k-- > 0;) {
    const double t = x - nd.node_x[k];
    ddp = ddp * t + 2 * dp;
    dp = dp * t + p;
    p = p * t + nd.coef[k];
  }
}

}  // namespace

// rt-safe
CurveDerivs PolyCurve::derivs(double u) const {
  if (basis == PolyBasis::Bezier) {
    // A polynomial piece whose moving axes finalize listed (the cubic has its own path below).
    if (n_poly_axes != kAxesUnknown) {
      switch (degree) {
        case 1: return poly_derivs<1>(bez, u, poly_axes.data(), n_poly_axes);
        case 2: return poly_derivs<2>(bez, u, poly_axes.data(), n_poly_axes);
        case 4: return poly_derivs<4>(bez, u, poly_axes.data(), n_poly_axes);
        case 5: return poly_derivs<5>(bez, u, poly_axes.data(), n_poly_axes);
        default: break;
      }
    }
    return bezier_derivs(bez, degree, u, moving.data(), n_moving);
  }
  const double dx = newton.x_end - newton.x_begin;
  const double x = (1 - u) * newton.x_begin + u * newton.x_end;
  double p, dp, ddp;
  newton_eval(newton, degree, x, p, dp, ddp);
  CurveDerivs d;
  d.c = newton.base;
  d.c[newton.x_axis] = x;
  d.c[newton.y_axis] = p;
  d.d1[newton.x_axis] = dx;
  d.d1[newton.y_axis] = dp * dx;
  d.d2[newton.y_axis] = ddp * dx * dx;
  return d;
}

// rt-safe
Vec PolyCurve::at(double u) const { return derivs(u).c; }

// rt-safe
double PolyCurve::speed(double u) const {
  if (basis == PolyBasis::NewtonGraph) {
    const double dx = newton.x_end - newton.x_begin;
    double p, dp, ddp;
    newton_eval(newton, degree, (1 - u) * newton.x_begin + u * newton.x_end, p, dp, ddp);
    return std::abs(dx) * std::sqrt(1 + dp * dp);
  }
  return core::norm(derivs(u).d1);
}

namespace {

// Bernstein → monomial by forward differences: a_j = C(n, j)·Δʲb_0.
void to_monomial(std::size_t n, std::array<double, kMaxBezierDegree + 1> b, std::array<double, kMaxBezierDegree + 1>& a) {
  static_assert(kMaxBezierDegree == 5, "kBinom lists the rows up to the highest degree");
  static constexpr std::array<std::array<double, kMaxBezierDegree + 1>, kMaxBezierDegree + 1> kBinom{{
      {1, 0, 0, 0, 0, 0}, {1, 1, 0, 0, 0, 0}, {1, 2, 1, 0, 0, 0}, {1, 3, 3, 1, 0, 0}, {1, 4, 6, 4, 1, 0},
      {1, 5, 10, 10, 5, 1}}};
  for (std::size_t j = 0; j <= n; ++j) {
    a[j] = kBinom[n][j] * b[0];
    for (std::size_t i = 0; i + j < n; ++i) b[i] = b[i + 1] - b[i];
  }
}

// |C'|² of a polynomial Bézier of degree N over the given axes, its control points scaled by
// `scale`: the sum of the squares of the axes' derivatives, each converted to monomials
// (to_monomial's arithmetic, unrolled for the degree).
template <std::size_t N>
void speed2_over(PolyCurve& c, const std::uint8_t* axes, std::size_t n_axes, double scale) {
  static_assert(N >= 1 && N <= kMaxBezierDegree);
  for (std::size_t k = 0; k < n_axes; ++k) {
    const std::size_t a = axes[k];
    std::array<double, kMaxBezierDegree + 1> v{}, m{};
    for (std::size_t i = 0; i <= N; ++i) v[i] = c.bez.hctrl[i][a] * scale;
    to_monomial(N, v, m);
    std::array<double, N> dc;  // C_a'(u) = Σ (j + 1)·m_{j+1}·u^j
    for (std::size_t i = 0; i < N; ++i) dc[i] = static_cast<double>(i + 1) * m[i + 1];
    for (std::size_t i = 0; i < N; ++i)
      for (std::size_t j = 0; j < N; ++j) c.speed2[i + j] += dc[i] * dc[j];
  }
}

}  // namespace

// rt-safe (the store derives a compact piece's |C'|² with it as it reads the piece back).
void speed2_over_axes(PolyCurve& c, const std::uint8_t* axes, std::size_t n_axes, double scale) {
  c.speed2 = {};
  const std::size_t n = c.degree;
  switch (n) {
    case 1: speed2_over<1>(c, axes, n_axes, scale); break;
    case 2: speed2_over<2>(c, axes, n_axes, scale); break;
    case 3: speed2_over<3>(c, axes, n_axes, scale); break;
    case 4: speed2_over<4>(c, axes, n_axes, scale); break;
    case 5: speed2_over<5>(c, axes, n_axes, scale); break;
    default: break;  // degree 0: a point, no derivative
  }
  c.speed2_degree = static_cast<std::uint8_t>(n > 0 ? 2 * (n - 1) : 0);
  c.has_speed2 = true;
}

namespace {

// A polynomial Bézier's |C'|² as one polynomial of degree 2(n − 1): the sum over the moving axes of
// the squares of their derivatives (PolyCurve::speed2; rational curves and Newton graphs: none).
// The moving axes are poly_axes where finalize found them (weights of 1), else found here.
void fill_speed2(PolyCurve& c) {
  c.speed2 = {};
  c.speed2_degree = 0;
  c.has_speed2 = false;
  if (c.basis != PolyBasis::Bezier) return;
  const auto& b = c.bez;
  const std::size_t n = c.degree;
  for (std::size_t i = 1; i <= n; ++i)
    if (b.w[i] != b.w[0]) return;
  const double scale = 1.0 / b.w[0];
  if (c.n_poly_axes != PolyCurve::kAxesUnknown) return speed2_over_axes(c, c.poly_axes.data(), c.n_poly_axes, scale);
  std::array<std::uint8_t, core::kMaxAxes> moving{};
  std::size_t count = 0;
  for (std::size_t a = 0; a < core::kMaxAxes; ++a) {
    bool moves = false;
    for (std::size_t i = 1; i <= n; ++i) moves = moves || b.hctrl[i][a] != b.hctrl[0][a];
    if (moves) moving[count++] = static_cast<std::uint8_t>(a);  // a constant coordinate has no derivative
  }
  speed2_over_axes(c, moving.data(), count, scale);
}

// |C'(u)| for the integrals, the inner loop of s → u. A polynomial Bézier reads the curve's stored
// |C'|² (one Horner pass and a square root); a rational one converts the homogeneous control points
// of the axes that move (usually two or three of nine) and the weights to monomials at construction
// and then costs a Horner pass per axis. rt-safe: fixed arrays on the stack.
class SpeedEval {
 public:
  explicit SpeedEval(const PolyCurve& c) : c_(c) {
    if (c.basis != PolyBasis::Bezier) return;
    const auto& b = c.bez;
    n_ = c.degree;
    if (c.has_speed2) return;  // polynomial: |C'|² from the curve (PolyCurve::speed2, finalize)
    rational_ = true;         // (or not finalized: the quotient form holds for equal weights too)
    for (std::size_t a = 0; a < core::kMaxAxes; ++a) {
      bool moves = false;
      for (std::size_t i = 1; i <= n_; ++i) moves = moves || b.hctrl[i][a] * b.w[0] != b.hctrl[0][a] * b.w[i];
      if (!moves) continue;  // a constant coordinate has no derivative
      std::array<double, kMaxBezierDegree + 1> v{};
      for (std::size_t i = 0; i <= n_; ++i) v[i] = b.hctrl[i][a];
      to_monomial(n_, v, h_[dims_++]);
    }
    to_monomial(n_, b.w, w_);
  }

  double operator()(double u) const {
    if (c_.basis != PolyBasis::Bezier) return c_.speed(u);
    if (!rational_) {  // has_speed2
      const auto& q2 = c_.speed2;
      double q = q2[c_.speed2_degree];
      for (std::size_t j = c_.speed2_degree; j-- > 0;) q = q * u + q2[j];
      return std::sqrt(std::max(0.0, q));
    }
    double w = 1, dw = 0;
    horner(w_, u, w, dw);
    double sum = 0;
    for (std::size_t d = 0; d < dims_; ++d) {
      double h, dh;
      horner(h_[d], u, h, dh);
      const double num = dh * w - h * dw;  // (H'W - HW') / W²
      sum += num * num;
    }
    return std::sqrt(sum) / (w * w);
  }

 private:
  void horner(const std::array<double, kMaxBezierDegree + 1>& a, double u, double& p, double& dp) const {
    p = a[n_];
    dp = 0;
    for (std::size_t j = n_; j-- > 0;) {
      dp = dp * u + p;
      p = p * u + a[j];
    }
  }

  const PolyCurve& c_;
  std::size_t n_ = 0, dims_ = 0;
  bool rational_ = false;
  std::array<std::array<double, kMaxBezierDegree + 1>, core::kMaxAxes> h_;
  std::array<double, kMaxBezierDegree + 1> w_{};
};

// rt-safe: ∫_a^b f by the symmetric Gauss–Legendre rule with positive nodes x, weights w.
template <std::size_t N, class F>
double gauss(const std::array<double, N>& x, const std::array<double, N>& w, const F& f, double a, double b) {
  const double m = 0.5 * (a + b), r = 0.5 * (b - a);
  double sum = 0;
  for (std::size_t i = 0; i < N; ++i) sum += w[i] * (f(m - r * x[i]) + f(m + r * x[i]));
  return sum * r;
}
template <class F>
double gl16(const F& f, double a, double b) { return gauss(kGlX, kGlW, f, a, b); }
template <class F>
double gl8(const F& f, double a, double b) { return gauss(kGl8X, kGl8W, f, a, b); }
template <class F>
double gl4(const F& f, double a, double b) { return gauss(kGl4X, kGl4W, f, a, b); }

}  // namespace

void speed2_from_controls(PolyCurve& c) { fill_speed2(c); }

// rt-safe
double PolyCurve::arc(double a, double b) const { return gl16(SpeedEval(*this), a, b); }

namespace {
// |C'(u)| of a polynomial Bézier from its stored |C'|² of degree D (PolyCurve::speed2): SpeedEval's
// Horner pass and square root, unrolled for D (the same arithmetic, about half the instructions).
template <std::size_t D>
struct SpeedPoly {
  const double* q2;
  double operator()(double u) const {
    double q = q2[D];
#pragma GCC unroll 16
    for (std::size_t i = 1; i <= D; ++i) q = q * u + q2[D - i];
    return std::sqrt(std::max(0.0, q));
  }
};

// fn(speed_at) with the fastest |C'(u)| for c: a polynomial Bézier's stored |C'|² unrolled for its
// degree (the same values as SpeedEval), else SpeedEval.
template <class Fn>
auto with_speed(const PolyCurve& c, const Fn& fn) {
  if (c.basis == PolyBasis::Bezier && c.has_speed2) {
    switch (c.speed2_degree) {
      case 2: return fn(SpeedPoly<2>{c.speed2.data()});
      case 4: return fn(SpeedPoly<4>{c.speed2.data()});
      case 6: return fn(SpeedPoly<6>{c.speed2.data()});
      case 8: return fn(SpeedPoly<8>{c.speed2.data()});
      default: break;
    }
  }
  return fn(SpeedEval(c));
}

// PolyCurve::param_at with the speed |C'(u)| from speed_at.
template <class F>
double invert(const PolyCurve& c, double s, const F& speed_at) {
  const double len = c.length();
  if (!(s > 0) || len <= 0) return 0;
  if (s >= len) return 1;
  const auto& s_at = c.s_at;
  const auto it = std::upper_bound(s_at.begin(), s_at.end(), s);
  const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(it - s_at.begin()) - 1, kArcTableIntervals - 1);
  double lo = k * kH, hi = (k + 1) * kH;
  const double sa = s_at[k], sb = s_at[k + 1], ds = sb - sa;
  if (!(ds > 0)) return lo;
  const double t = (s - sa) / ds;
  double u = lo + t * kH;
  const double v0 = speed_at(lo), v1 = speed_at(hi);
  if (v0 > 1e-9 * ds / kH && v1 > 1e-9 * ds / kH) {
    const double t2 = t * t, t3 = t2 * t;
    const double hermite = (2 * t3 - 3 * t2 + 1) * lo + (t3 - 2 * t2 + t) * ds / v0 + (-2 * t3 + 3 * t2) * hi +
                           (t3 - t2) * ds / v1;
    if (hermite > lo && hermite < hi) u = hermite;
  }
  const auto part = [&](double from, double to) { return c.gl8_ok ? gl8(speed_at, from, to) : gl16(speed_at, from, to); };
  double acc = sa + part(lo, u);  // s(u)
  const double tol = 1e-12 * std::max(1.0, len);
  for (int iter = 0; iter < 64; ++iter) {
    const double f = acc - s;
    if (std::abs(f) <= tol) break;
    if (f < 0)
      lo = u;
    else
      hi = u;
    const double sp = speed_at(u);
    double un = sp > 0 ? u - f / sp : 0.5 * (lo + hi);
    if (!(un > lo && un < hi)) un = 0.5 * (lo + hi);  // safeguard: stay inside the bracket
    acc += std::abs(un - u) < 0.02 * kH ? gl4(speed_at, u, un) : part(u, un);
    u = un;
  }
  return u;
}
}  // namespace

// rt-safe: bounded work (a 5-step table search, at most 64 Newton/bisection steps: Newton ends
// in two or three, bisection takes more only next to a stationary end, as at a cusp: 8 left
// 1e-7 mm there, 2.8 times one cycle of a 60 mm/s³ jerk).
//
//   table:  s_at[k] ≤ s < s_at[k+1]  →  u in [k/32, (k+1)/32]
//   guess:  cubic Hermite of u(s) from du/ds = 1/|C'| at both ends (O(h⁴) for smooth curves)
//   Newton: u ← u - (s(u) - s)/|C'(u)|, s(u) kept up to date by integrating each step's small
//           interval; a step leaving the bracket falls back to bisection.
double PolyCurve::param_at(double s) const {
  return with_speed(*this, [&](const auto& speed_at) { return invert(*this, s, speed_at); });
}

// rt-safe
double PolyCurve::param_at_reference(double s) const { return invert(*this, s, SpeedEval(*this)); }

// rt-safe
bool stationary(const CurveDerivs& d) {
  double sp2 = 0, acc2 = 0;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    sp2 += d.d1[i] * d.d1[i];
    acc2 += d.d2[i] * d.d2[i];
  }
  return stationary_speed(sp2, acc2);
}

// rt-safe. Unit tangent and curvature vector d²C/ds² = (C'' − (C''·T) T) / |C'|² over the axes
// ax[0 … m) (the others 0: an axis the curve does not move has no derivative). At a stationary point
// (e.g. G5 with I = J = 0) the tangent is the limit direction of C'' and the curvature is left 0.
void tangent_curvature(const CurveDerivs& d, const std::size_t* ax, std::size_t m, Vec& t, Vec& k) {
  double sp2 = 0, acc2 = 0;
  for (std::size_t j = 0; j < m; ++j) {
    sp2 += d.d1[ax[j]] * d.d1[ax[j]];
    acc2 += d.d2[ax[j]] * d.d2[ax[j]];
  }
  t = Vec{};
  k = Vec{};
  const double sp = std::sqrt(sp2);
  if (!stationary_speed(sp2, acc2)) {
    for (std::size_t j = 0; j < m; ++j) t[ax[j]] = d.d1[ax[j]] * (1.0 / sp);
  } else if (const double ta = std::sqrt(acc2); ta > 0) {
    for (std::size_t j = 0; j < m; ++j) t[ax[j]] = d.d2[ax[j]] * (1.0 / ta);
  }
  if (stationary_speed(sp2, acc2)) return;
  const double inv = 1.0 / std::sqrt(sp2);
  double along = 0;
  for (std::size_t j = 0; j < m; ++j) along += d.d2[ax[j]] * (d.d1[ax[j]] * inv);
  for (std::size_t j = 0; j < m; ++j) k[ax[j]] = (d.d2[ax[j]] - d.d1[ax[j]] * inv * along) * (1.0 / sp2);
}

// rt-safe
Vec unit_tangent(const CurveDerivs& d) {
  Vec t, k;
  tangent_curvature(d, kEveryAxis.data(), kEveryAxis.size(), t, k);
  return t;
}

// rt-safe
Vec curvature_vector(const CurveDerivs& d) {
  Vec t, k;
  tangent_curvature(d, kEveryAxis.data(), kEveryAxis.size(), t, k);
  return k;
}

double PolyCurve::finalize(bool estimate) {
  // The axes the curve moves, first: everything below evaluates the curve through them.
  n_moving = 0;
  for (std::size_t a = 0; a < core::kMaxAxes; ++a) {
    bool moves = basis == PolyBasis::NewtonGraph && (a == newton.x_axis || a == newton.y_axis);
    // Control points equal up to the rounding of their weighting (p·w_i·w_0 against p·w_0·w_i: a
    // few ulps) do not move the axis.
    for (std::size_t i = 1; basis == PolyBasis::Bezier && i <= degree; ++i)
      moves = moves || std::abs(bez.hctrl[i][a] * bez.w[0] - bez.hctrl[0][a] * bez.w[i]) >
                           1e-14 * std::abs(bez.hctrl[0][a] * bez.w[i]);
    if (moves) moving[n_moving++] = a;
  }
  // A polynomial Bézier's axes whose control points differ at all (bezier_derivs' own test).
  n_poly_axes = kAxesUnknown;
  bool polynomial_piece = basis == PolyBasis::Bezier && degree >= 1 && degree <= kMaxBezierDegree;
  for (std::size_t i = 0; polynomial_piece && i <= degree; ++i) polynomial_piece = bez.w[i] == 1;
  if (polynomial_piece) {
    std::uint8_t np = 0;
    for (std::size_t a = 0; a < core::kMaxAxes; ++a) {
      bool moves = false;
      for (std::size_t i = 1; i <= degree; ++i) moves = moves || bez.hctrl[i][a] != bez.hctrl[0][a];
      if (moves) poly_axes[np++] = static_cast<std::uint8_t>(a);
    }
    n_poly_axes = np;
  }
  fill_speed2(*this);
  s_at[0] = 0;
  double err = 0, d8 = 0;
  // (|C'| as param_at takes it: unrolled for a polynomial's degree, the same values as SpeedEval's
  // loop for fewer instructions.)
  with_speed(*this, [&](const auto& speed_at) {
    for (std::size_t k = 0; k < kArcTableIntervals; ++k) {
      const double a = k * kH, b = (k + 1) * kH, m = 0.5 * (a + b);
      const double whole = gl16(speed_at, a, b);
      if (estimate) err += std::abs(whole - (gl16(speed_at, a, m) + gl16(speed_at, m, b)));
      d8 = std::max(d8, std::abs(gl8(speed_at, a, b) - whole));
      s_at[k + 1] = s_at[k] + whole;
    }
    return 0;
  });
  // A partial interval is shorter than a whole one, and the 8-point rule's error shrinks with it.
  gl8_ok = d8 <= 1e-14 * s_at.back();

  // Bounds: per axis, a Bernstein branch-and-bound range (guaranteed to contain the curve).
  if (basis == PolyBasis::Bezier) {
    std::array<double, kMaxBezierDegree + 1> num{};
    for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
      for (std::size_t j = 0; j <= degree; ++j) num[j] = bez.hctrl[j][i];
      const auto r = bernstein_range({num.data(), degree + 1u}, {bez.w.data(), degree + 1u});
      box_lo[i] = r.lo;
      box_hi[i] = r.hi;
    }
  } else {
    box_lo = newton.base;
    box_hi = newton.base;
    box_lo[newton.x_axis] = std::min(newton.x_begin, newton.x_end);
    box_hi[newton.x_axis] = std::max(newton.x_begin, newton.x_end);
    const auto bc = newton_to_bernstein(*this);
    std::array<double, kMaxNewtonDegree + 1> ones;
    ones.fill(1.0);
    const auto r = bernstein_range({bc.data(), degree + 1u}, {ones.data(), degree + 1u});
    box_lo[newton.y_axis] = r.lo;
    box_hi[newton.y_axis] = r.hi;
  }

  // Sampled maxima of |T_i| and |κ| for the planner.
  max_abs_tangent = Vec{};
  max_curvature = 0;
  max_dcurvature = 0;
  // Polynomial pieces (splines, G5, smoothed CAM runs, quintic corner blends: by far the most
  // built) vary slowly enough for 256; rational pieces (NURBS) keep 1024.
  bool polynomial = basis == PolyBasis::Bezier;
  for (std::size_t i = 0; polynomial && i <= degree; ++i) polynomial = bez.w[i] == 1;
  const int kSamples = polynomial ? 256 : 1024;
  // The samples work on the axes that move only (the same sums in the same order as over all
  // nine: the others add zeros).
  const auto& ax = moving;
  const std::size_t m = n_moving;
  // The samples keep C', C'', T and κ on the moving axes only, by their rank j (axis ax[j]), with
  // tangent_curvature's arithmetic in its order: the same values as evaluating the curve and
  // calling it, without the nine-axis temporaries (with the unrolled |C'| above, a smoothed piece's
  // construction went 194 000 → 98 000 instructions: callgrind on a 20 000-line raster).
  // C' and C'' at u: a polynomial cubic (the smoothing's pieces, by far the most built) takes
  // bezier_derivs' own expressions with the control differences taken once; other curves derivs(u).
  const bool cubic = polynomial && degree == 3;
  std::array<std::array<double, 3>, core::kMaxAxes> diff{};
  for (std::size_t j = 0; cubic && j < m; ++j) {
    const std::size_t a = ax[j];
    diff[j] = {bez.hctrl[1][a] - bez.hctrl[0][a], bez.hctrl[2][a] - bez.hctrl[1][a], bez.hctrl[3][a] - bez.hctrl[2][a]};
  }
  std::array<double, core::kMaxAxes> d1{}, d2{}, t{}, k{}, k_prev{};
  const auto eval = [&](double u) {
    if (!cubic) {
      const CurveDerivs d = derivs(u);
      for (std::size_t j = 0; j < m; ++j) {
        d1[j] = d.d1[ax[j]];
        d2[j] = d.d2[ax[j]];
      }
      return;
    }
    const double v = 1 - u;
    for (std::size_t j = 0; j < m; ++j) {
      const double e0 = diff[j][0], e1 = diff[j][1], e2 = diff[j][2];
      d1[j] = 3 * (v * v * e0 + 2 * v * u * e1 + u * u * e2);
      d2[j] = 6 * (v * (e1 - e0) + u * (e2 - e1));
    }
  };
  double sp_prev = 0, ds_max = 0;
  // One sample at u: tangent and curvature into t, k (tangent_curvature), and the secant |Δκ|/Δs
  // from the previous sample, du of u before it (Δs by the trapezoid rule on |C'|; 0 for the first).
  const auto sample = [&](double u, double du, bool first) {
    eval(u);
    double sp2 = 0, acc2 = 0;
    for (std::size_t j = 0; j < m; ++j) {
      sp2 += d1[j] * d1[j];
      acc2 += d2[j] * d2[j];
    }
    const double sp = std::sqrt(sp2);
    const bool still = stationary_speed(sp2, acc2);
    if (!still) {
      for (std::size_t j = 0; j < m; ++j) t[j] = d1[j] * (1.0 / sp);
    } else if (const double ta = std::sqrt(acc2); ta > 0) {
      for (std::size_t j = 0; j < m; ++j) t[j] = d2[j] * (1.0 / ta);
    } else {
      for (std::size_t j = 0; j < m; ++j) t[j] = 0;
    }
    if (still) {
      for (std::size_t j = 0; j < m; ++j) k[j] = 0;
    } else {
      const double inv = 1.0 / std::sqrt(sp2);
      double along = 0;
      for (std::size_t j = 0; j < m; ++j) along += d2[j] * (d1[j] * inv);
      for (std::size_t j = 0; j < m; ++j) k[j] = (d2[j] - d1[j] * inv * along) * (1.0 / sp2);
    }
    double dk2 = 0;
    for (std::size_t j = 0; j < m; ++j) dk2 += (k[j] - k_prev[j]) * (k[j] - k_prev[j]);
    const double ds = 0.5 * (sp + sp_prev) * du;
    if (!first) ds_max = std::max(ds_max, std::max(sp, sp_prev) * du);
    k_prev = k;
    sp_prev = sp;
    return !first && ds > 1e-300 ? std::sqrt(dk2) / ds : 0.0;
  };
  int i_peak = 0;  // the sample ending the interval with the largest secant
  for (int i = 0; i <= kSamples; ++i) {
    const double u = static_cast<double>(i) / kSamples;
    const double dk = sample(u, 1.0 / kSamples, i == 0);
    double k2 = 0;
    for (std::size_t j = 0; j < m; ++j) {
      max_abs_tangent[ax[j]] = std::max(max_abs_tangent[ax[j]], std::abs(t[j]));
      k2 += k[j] * k[j];
    }
    max_curvature = std::max(max_curvature, std::sqrt(k2));
    if (dk > max_dcurvature) {
      max_dcurvature = dk;
      i_peak = i;
    }
  }
  // A secant over 1/kSamples of u is the mean of |dκ/ds| there, below its peak by as much as the
  // peak is sharp (1.7–2.2× on near-cusp cubics): the intervals either side of the largest are
  // sampled 32 times finer, and the largest secant there is taken too.
  if (i_peak > 0) {
    constexpr int kFine = 32;
    const double u0 = static_cast<double>(i_peak - 1) / kSamples, du = 1.0 / (kSamples * kFine);
    const int steps = (i_peak < kSamples ? 2 : 1) * kFine;
    for (int i = 0; i <= steps; ++i) max_dcurvature = std::max(max_dcurvature, sample(u0 + i * du, du, i == 0));
  }
  // A tangent share peaks between samples: by at most ½·|T''|·(Δs/2)² over the sampled largest
  // (|T''| = |dκ/ds| ≤ max_dcurvature, Δs the longest interval). Without it a G5.2 along Y ran at
  // 2.2e-7 over Y's speed limit (a fuzzer's case).
  for (std::size_t j = 0; j < m; ++j)
    max_abs_tangent[ax[j]] = std::min(1.0, max_abs_tangent[ax[j]] + 0.125 * max_dcurvature * ds_max * ds_max);
  return err;
}

double PolyCurve::distance_to(const Vec& p, double enough) const {
  // Sample densely, then refine every local minimum of the sampled distance with Newton steps on
  // f(u) = (C - p)·C' (f' = |C'|² + (C - p)·C''), so a nearer lobe elsewhere is not missed.
  constexpr int kSamples = 256;
  std::array<double, kSamples + 1> d2{};
  const double enough2 = enough * enough;
  // Coarse to fine (every 32nd sample, then the 16ths between them, ...): every sample is a point of
  // the curve, so one within `enough` answers a caller that asks no more, and a coarse one usually
  // does (a fillet's check of the arc it replaces: about 10 samples instead of 128).
  for (int stride = 32; stride >= 1; stride /= 2) {
    for (int i = 0; i <= kSamples; i += stride) {
      if (stride < 32 && i % (2 * stride) == 0) continue;  // taken at the coarser stride
      const Vec e = at(static_cast<double>(i) / kSamples) - p;
      d2[i] = core::dot(e, e);
      if (d2[i] <= enough2) return std::sqrt(d2[i]);
    }
  }
  double best = std::sqrt(std::min(d2.front(), d2.back()));
  for (int i = 0; i <= kSamples; ++i) {
    const bool left = i == 0 || d2[i] <= d2[i - 1];
    const bool right = i == kSamples || d2[i] <= d2[i + 1];
    if (!(left && right)) continue;
    double u = static_cast<double>(i) / kSamples;
    bool stuck = false;
    for (int it = 0; it < 30; ++it) {
      const CurveDerivs d = derivs(u);
      const Vec e = d.c - p;
      const double f = core::dot(e, d.d1);
      const double df = core::dot(d.d1, d.d1) + core::dot(e, d.d2);
      if (!(df > 0)) {
        stuck = true;
        break;
      }
      const double un = std::clamp(u - f / df, 0.0, 1.0);
      // Settled: a step under 1e-15 of u, or under a picometre along the curve (the rounding of the
      // positions keeps Newton stepping by about that much; it ran all 30 steps before).
      const bool done = std::abs(un - u) < 1e-15 || std::abs(un - u) * std::sqrt(core::dot(d.d1, d.d1)) <= 1e-12;
      u = un;
      if (done) break;
    }
    best = std::min(best, core::distance(at(u), p));
    if (stuck) {
      // Newton cannot start where the curve stops (C' = 0: a doubled control point at an end, a
      // cusp): the distance there was that of the stationary point itself, and a setpoint 2.7e-6 mm
      // along a G5.2 that starts so was reported 2.5e-6 mm off it. A golden-section search over the
      // sample's neighbourhood instead (the distance is unimodal that near).
      const double lo = std::max(0.0, (i - 1.0) / kSamples), hi = std::min(1.0, (i + 1.0) / kSamples);
      const auto minus_dist2 = [&](double v) {
        const Vec e = at(v) - p;
        return -core::dot(e, e);
      };
      best = std::min(best, std::sqrt(-golden_max(minus_dist2, lo, hi, 80, 1e-16).f));
    }
    if (best <= enough) return best;
  }
  return best;
}

}  // namespace softmc::motion
