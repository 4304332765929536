// Guaranteed value range of a 1-D (rational) Bernstein polynomial, for curve bounding boxes.
//
//   f(u) = Σ B_i(u)·num_i / Σ B_i(u)·w_i,  w_i > 0,  u in [0, 1]
//   The curve lies in the hull of the points num_i / w_i; bisecting (de Casteljau at ½) shrinks
//   the hull towards the true extremes quadratically; a piece whose hull cannot beat the best
//   value seen by more than a tolerance is not split further. rt-safe: bounded work (depth 60), a
//   fixed-size stack, no allocation.
#pragma once

#include <array>
#include <span>

#include "motion/geometry/poly_curve.hpp"

namespace softmc::motion {

struct ValueRange {
  double lo = 0, hi = 0;
};

// [lo, hi] contains every f(u); each end is within 1e-10·max(1, |f|) of the true extreme.
// num.size() == w.size() ≤ kMaxNewtonDegree + 1.
ValueRange bernstein_range(std::span<const double> num, std::span<const double> w);

// Bernstein coefficients (degree = curve.degree) of y(u) for a NewtonGraph curve.
std::array<double, kMaxNewtonDegree + 1> newton_to_bernstein(const PolyCurve& curve);

}  // namespace softmc::motion
