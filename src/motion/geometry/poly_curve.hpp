// Parametric polynomial curves C(u), u in [0, 1], and their arc-length parameterisation s → u.
//
//   C(u) ──► |C'(u)| ──► s(u) = ∫0^u |C'| du      table: s at u = k/32 (16-point Gauss–Legendre each)
//                         s ──► u                  table lookup, then safeguarded Newton on s(u) - s
//
// Two bases share that machinery:
//   Bezier       rational Bézier of degree ≤ kMaxBezierDegree in all axes (weights 1 = polynomial):
//                cubic pieces of splines and G5, quadratic G5.1, the pieces of a NURBS.
//   NewtonGraph  the graph y = p(x) of a Newton interpolating polynomial (divided differences) of
//                degree ≤ kMaxNewtonDegree: x moves linearly with u, other axes stay put.
// The curve is evaluated exactly at every query (no polygon); only s → u is iterative, converged to
// 1e-12 mm of arc length. A value type of fixed size: copying it never allocates.
#pragma once

#include <algorithm>

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/axes.hpp"

namespace softmc::motion {

using core::Vec;

inline constexpr std::size_t kMaxBezierDegree = 5;   // G5.2 order L ≤ 6
inline constexpr std::size_t kMaxNewtonDegree = 15;  // 16 nodes; the thesis found > 5 unstable anyway
inline constexpr std::size_t kArcTableIntervals = 32;
inline constexpr double kTableTolerance = 1e-10;  // relative length error a piece may have

enum class PolyBasis : std::uint8_t { Bezier, NewtonGraph };

// Position and its first two derivatives with respect to u.
struct CurveDerivs {
  Vec c, d1, d2;
};

struct PolyCurve {
  PolyBasis basis = PolyBasis::Bezier;
  std::uint8_t degree = 0;

  struct BezierData {
    std::array<Vec, kMaxBezierDegree + 1> hctrl{};   // weighted control points w_i·P_i
    std::array<double, kMaxBezierDegree + 1> w{};    // weights (all > 0)
  };
  struct NewtonData {
    std::array<double, kMaxNewtonDegree + 1> node_x{};  // x_0..x_n
    std::array<double, kMaxNewtonDegree + 1> coef{};    // divided differences f[x_0..x_k]
    double x_begin = 0, x_end = 0;                      // x(u) = (1-u)·x_begin + u·x_end
    Vec base;                                            // the axes outside (x, y)
    std::uint8_t x_axis = 0, y_axis = 1;
  };
  union {
    BezierData bez{};
    NewtonData newton;
  };

  // s at u = k / kArcTableIntervals; s_at.back() is the curve's length.
  std::array<double, kArcTableIntervals + 1> s_at{};
  // Axis-aligned box guaranteed to contain the curve (within 1e-9 mm), computed at construction.
  Vec box_lo, box_hi;
  // Largest |dC_i/ds| per axis and largest curvature, sampled densely at construction (for the
  // planner's speed limits; a sampled maximum, not a proof).
  Vec max_abs_tangent;
  double max_curvature = 0;
  double max_dcurvature = 0;  // largest |dκ/ds| of the curvature vector (1/mm²), sampled likewise
  // The speed term of the path jerk per v³ (1/mm²): |dκ/ds| of the curvature vector, whose tangential
  // part is exactly −κ², so never below κ² whatever the samples missed.
  double jerk_speed_term() const { return std::max(max_dcurvature, max_curvature * max_curvature); }
  // A polynomial Bézier's |C'(u)|² in powers of u (degree 2·(degree − 1)), filled by finalize: the
  // speed in the arc-length integrals is one Horner pass and a square root (rational curves and
  // Newton graphs: has_speed2 false).
  std::array<double, 2 * kMaxBezierDegree - 1> speed2{};
  std::uint8_t speed2_degree = 0;
  bool has_speed2 = false;
  // The 8-point rule agrees with the 16-point one within 1e-14 of the length on every table
  // interval (finalize): s → u then integrates its partial interval with 8 points (half the work).
  bool gl8_ok = false;
  // The axes the curve moves, ascending (finalize): the others have no derivative, and the
  // tangent and curvature are summed over these only (the same sums: the others add zeros).
  std::array<std::size_t, core::kMaxAxes> moving{};
  std::size_t n_moving = 0;
  // The axes whose control points differ at all from the first one, ascending (finalize, polynomial
  // Béziers of degree ≥ 1; kAxesUnknown otherwise): a polynomial piece other than the cubic fast
  // path is evaluated on these only, instead of comparing every axis's control points at every
  // evaluation (the same values: the others are constant). kAxesUnknown keeps the comparisons (the
  // reference, for tests).
  static constexpr std::uint8_t kAxesUnknown = 0xFF;
  std::array<std::uint8_t, core::kMaxAxes> poly_axes{};
  std::uint8_t n_poly_axes = kAxesUnknown;

  PolyCurve() {}

  double length() const { return s_at.back(); }

  // rt-safe: C, C', C'' at u in [0, 1].
  CurveDerivs derivs(double u) const;
  // rt-safe: C(u).
  Vec at(double u) const;
  // rt-safe: |C'(u)|.
  double speed(double u) const;
  // rt-safe: ∫_a^b |C'| du (16-point Gauss–Legendre; b may be below a).
  double arc(double a, double b) const;
  // rt-safe: the parameter u at arc length s (clamped to [0, length]).
  double param_at(double s) const;
  // rt-safe: the same through the general speed evaluation (param_at unrolls a polynomial's |C'|²
  // for its degree: the reference for tests).
  double param_at_reference(double s) const;

  // Fills s_at, the box and the sampled maxima. Called once by every constructor (allocates).
  // Returns the estimated error of the length table (mm): the sum over its intervals of
  // |one 16-point rule - two 16-point rules on the halves|. Constructors split a curve whose
  // estimate exceeds kTableTolerance·length into pieces. Without `estimate` (a constructor that
  // does not split) the halves are not integrated (a third of the work) and 0 is returned; the
  // table is the same.
  double finalize(bool estimate = true);
  // Distance from p to the curve: dense sampling, then Newton on (C - p)·C' = 0 (rt-safe; the
  // planner's blend checks ask it in the cycle). As Segment::distance_to, a distance at or below
  // `enough` to some point of the curve is returned as soon as one is found.
  double distance_to(const Vec& p, double enough = 0) const;
};

// Sets speed2, speed2_degree and has_speed2 from the control points and weights, as finalize does (a
// compact store of pieces derives them so instead of keeping them). rt-safe.
void speed2_from_controls(PolyCurve& c);
// |C'|² of a polynomial Bézier (degree 0…5) from its control points scaled by `scale` over the given
// axes (the moving ones, ascending): speed2, speed2_degree, has_speed2. rt-safe.
void speed2_over_axes(PolyCurve& c, const std::uint8_t* axes, std::size_t n_axes, double scale);

// |C'|² = sp2 and |C''|² = acc2 at a stationary point: C' zero, or below a billionth of C'' (the
// rounding of a rational piece whose end leg collapsed at a cusp: 1e-14 mm per unit of u against
// ~1, whose direction is noise). The tangent is then along ±C''.
inline bool stationary_speed(double sp2, double acc2) { return !(sp2 > 1e-300) || sp2 <= 1e-18 * acc2; }
// rt-safe. C' is zero or negligible against C'' there (stationary_speed).
bool stationary(const CurveDerivs& d);
// Unit tangent and curvature vector d²C/ds² from the u-derivatives (rt-safe).
Vec unit_tangent(const CurveDerivs& d);
Vec curvature_vector(const CurveDerivs& d);
// Both, over the axes ax[0 … m) only (the others 0): construction samples the axes that move.
static_assert(core::kMaxAxes == 9, "kEveryAxis lists every axis");
inline constexpr std::array<std::size_t, core::kMaxAxes> kEveryAxis{0, 1, 2, 3, 4, 5, 6, 7, 8};
void tangent_curvature(const CurveDerivs& d, const std::size_t* ax, std::size_t m, Vec& t, Vec& k);

}  // namespace softmc::motion
