// Branch-and-bound range of Bernstein polynomials; Newton form → Bernstein form.
#include "motion/geometry/bernstein_range.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace softmc::motion {

namespace {

constexpr std::size_t kMaxCoef = kMaxNewtonDegree + 1;

// No default member initializers: min_bound's fixed stack of 62 pieces (62 × 2 × 17 doubles) would
// otherwise be zeroed on every call, 16 000 instructions a call and most of a blend's construction;
// every piece is written (depth and the first n + 1 coefficients, all that is read) before use.
struct Piece {
  std::array<double, kMaxCoef> num, w;
  int depth;
};

// Smallest value of f: the best sampled value, lowered to the hull minimum of every piece left.
double min_bound(std::span<const double> num, std::span<const double> w) {
  const std::size_t n = num.size() - 1;
  Piece root;
  root.depth = 0;
  std::copy(num.begin(), num.end(), root.num.begin());
  std::copy(w.begin(), w.end(), root.w.begin());
  double best = std::min(num[0] / w[0], num[n] / w[n]);  // values at u = 0 and 1
  double floor = best;
  // Depth first: each level leaves at most one piece waiting, so the stack never holds more than
  // the depth limit + 1 pieces; fixed-size, no allocation (the planner builds its blends with this
  // inside Planner::push).
  constexpr int kMaxDepth = 60;
  std::array<Piece, kMaxDepth + 2> stack;
  std::size_t top = 0;
  stack[top++] = root;
  while (top > 0) {
    Piece p = stack[--top];
    double lo = p.num[0] / p.w[0];
    for (std::size_t i = 1; i <= n; ++i) lo = std::min(lo, p.num[i] / p.w[i]);
    const double tol = 1e-10 * std::max(1.0, std::abs(best));
    if (lo >= best - tol || p.depth >= kMaxDepth) {
      floor = std::min(floor, lo);
      continue;
    }
    // Split at ½: the left piece collects the first point of each level, the right one the last.
    Piece l, r;
    l.depth = r.depth = p.depth + 1;
    for (std::size_t lvl = 0; lvl <= n; ++lvl) {
      l.num[lvl] = p.num[0];
      l.w[lvl] = p.w[0];
      r.num[n - lvl] = p.num[n - lvl];
      r.w[n - lvl] = p.w[n - lvl];
      for (std::size_t i = 0; i + lvl < n; ++i) {
        p.num[i] = 0.5 * (p.num[i] + p.num[i + 1]);
        p.w[i] = 0.5 * (p.w[i] + p.w[i + 1]);
      }
    }
    best = std::min(best, l.num[n] / l.w[n]);  // the value at the split point
    stack[top++] = l;
    stack[top++] = r;
  }
  return std::min(best, floor);
}

}  // namespace

ValueRange bernstein_range(std::span<const double> num, std::span<const double> w) {
  ValueRange r;
  r.lo = min_bound(num, w);
  std::array<double, kMaxCoef> neg{};
  for (std::size_t i = 0; i < num.size(); ++i) neg[i] = -num[i];
  r.hi = -min_bound({neg.data(), num.size()}, w);
  return r;
}

// q(u) = p(x(u)) with x(u) = (1-u)·xa + u·xb, built from the innermost Newton term outwards:
// q ← q·(x(u) - x_k) + c_k, where the linear factor is the degree-1 Bernstein [xa - x_k, xb - x_k]
// and the product raises the degree by one: b'_j = (b_j·l0·(m+1-j) + b_{j-1}·l1·j) / (m+1).
std::array<double, kMaxNewtonDegree + 1> newton_to_bernstein(const PolyCurve& curve) {
  const auto& nd = curve.newton;
  const std::size_t n = curve.degree;
  std::array<double, kMaxCoef> b{};
  b[0] = nd.coef[n];
  for (std::size_t k = n; k-- > 0;) {
    const std::size_t m = n - 1 - k;  // current degree of b
    const double l0 = nd.x_begin - nd.node_x[k], l1 = nd.x_end - nd.node_x[k];
    std::array<double, kMaxCoef> nb{};
    for (std::size_t j = 0; j <= m + 1; ++j) {
      double v = 0;
      if (j <= m) v += b[j] * l0 * static_cast<double>(m + 1 - j);
      if (j >= 1) v += b[j - 1] * l1 * static_cast<double>(j);
      nb[j] = v / static_cast<double>(m + 1) + nd.coef[k];
    }
    b = nb;
  }
  return b;
}

}  // namespace softmc::motion
