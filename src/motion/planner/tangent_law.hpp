// How much tangential acceleration a curved block leaves at each speed: a_t ≤ g(v²).
//
//   a_t ^                              On a curve the centripetal part v²κ takes a share of every axis's
//   A/T |‾‾‾‾‾‾‾‾‾\___                 acceleration that grows with speed; what is left drives the path
//       |             ‾‾\__            along it. A fixed split (0.8 centripetal, 0.6 tangential) wastes
//       |                  \           both ends: slow, the curve could brake at nearly full a; at its
//       |___________________\___> v²   speed cap it needs no tangential acceleration at all.
//                           w_cap
//
// Per axis i the law is the better of two bounds, both exact on the block:
//   sweep   a_t·T_i + v²κ·N_i ≤ A_i      (T_i, N_i the largest |tangent|, |normal| share over the block)
//           → a_t ≤ α_i − β_i·w          (α = A/T, β = κN/T)
//   circle  |a_t·t_i + v²κ·n_i| ≤ amp_i·√(a_t² + (v²κ)²) ≤ A_i   (t_i, n_i one phase apart)
//           → a_t ≤ √(c_i² − d_i²·w²)
// and the block's law is the smallest over its axes (lines: one constant). g falls as w rises, so a
// ramp whose highest speed² is w may use g(w) all along it: every point of it is then within every
// axis's limit. The backward pass and the interpolator both solve w − x = k·g(w) for the largest
// speed² w from which a distance k/2 brakes to x (closed forms below).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "core/axes.hpp"

namespace softmc::motion {

struct TangentTerm {
  double alpha = -std::numeric_limits<double>::infinity(), beta = 0;  // sweep bound α − β·w (off: −∞)
  double c = 0, d = 0;                                                  // circle bound √(c² − d²w²) (off: 0)
  // rt-safe. The axis's bound at speed² w (≥ 0), and the root of w − x = k·bound(w).
  double at(double w) const;
  double root(double x, double k) const;
};

struct TangentLaw {
  // Curves moving more axes than this (rare on the machines softmc runs) keep the fixed split: every
  // Block carries a law, and a smaller one keeps the look-ahead window's copies cheap.
  static constexpr std::size_t kMaxTerms = 4;
  std::array<TangentTerm, kMaxTerms> term{};
  std::uint8_t n = 0;
  double a_const = std::numeric_limits<double>::infinity();  // constant bounds (line axes, helix axes)
  double w_cap = std::numeric_limits<double>::infinity();    // (mm/s)²: speed² where no axis may go faster
  double scale = 1;  // share kept after a kink (Planner::kink)

  // A law that is one constant: lines, and blocks the jerk follower executes.
  static TangentLaw constant(double a_mm_s2) {
    TangentLaw l;
    l.a_const = a_mm_s2;
    return l;
  }
  // False (and nothing added) when the law is full.
  bool add(const TangentTerm& t);
  bool full = false;  // a term did not fit: the law is incomplete and must not be used

  // rt-safe. Largest speed² at which the law still leaves `share` of what it allows at rest (the
  // speed cap that keeps a brake always possible; closed form per bound, ≤ w_cap).
  double reserve_w(double share) const;
  // rt-safe. Tangential acceleration allowed at speed² w (mm/s²).
  double at(double w) const;
  // rt-safe. Largest speed² w ≥ x with w − x ≤ k·at(w): the entry speed² from which a distance k/2
  // brakes to x (backward pass, k = 2L), or the peak of a ramp between two ends (k = distance,
  // x = the mean of the two ends' speed²). Never above w_cap.
  double root(double x, double k) const;
};

}  // namespace softmc::motion
