// Speed-dependent tangential acceleration on curves: evaluation and closed-form roots.
#include "motion/planner/tangent_law.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace softmc::motion {

// rt-safe
double TangentTerm::at(double w) const {
  const double lin = alpha - beta * w;
  const double circ = d > 0 ? std::sqrt(std::max(0.0, c * c - d * d * w * w)) : c;
  return std::max(0.0, std::max(lin, circ));
}

// rt-safe. The bound is a max of two falling functions, so the root is the larger of their roots.
double TangentTerm::root(double x, double k) const {
  double w = x;
  if (std::isfinite(alpha)) w = std::max(w, (x + k * alpha) / (1 + k * beta));  // w − x = k(α − βw)
  if (c > 0) {
    if (d > 0) {
      // (w − x)² = k²(c² − d²w²), w ≥ x  →  w = (x + k·√(c²(1 + k²d²) − d²x²)) / (1 + k²d²)
      const double kd2 = k * k * d * d;
      const double disc = c * c * (1 + kd2) - d * d * x * x;
      if (disc > 0) w = std::max(w, (x + k * std::sqrt(disc)) / (1 + kd2));
    } else {
      w = std::max(w, x + k * c);
    }
  }
  return w;
}

bool TangentLaw::add(const TangentTerm& t) {
  if (n >= kMaxTerms) {
    full = true;
    return false;
  }
  term[n++] = t;
  return true;
}

// rt-safe
double TangentLaw::at(double w) const {
  if (w > w_cap) return 0;
  double g = a_const;
  for (std::size_t i = 0; i < n; ++i) g = std::min(g, term[i].at(w));
  return scale * std::max(0.0, g);
}

// rt-safe. Each bound is ≥ r·g(0) up to its own point (the larger of its two parts'); the law up to
// the smallest of those.
double TangentLaw::reserve_w(double share) const {
  const double g0 = at(0) / scale;
  const double r = share * g0;
  double w = w_cap;
  for (std::size_t i = 0; i < n; ++i) {
    const TangentTerm& t = term[i];
    double wi = 0;
    if (std::isfinite(t.alpha) && t.alpha >= r) wi = t.beta > 0 ? (t.alpha - r) / t.beta : std::numeric_limits<double>::infinity();
    if (t.c >= r) wi = std::max(wi, t.d > 0 ? std::sqrt(t.c * t.c - r * r) / t.d : std::numeric_limits<double>::infinity());
    w = std::min(w, wi);
  }
  return w;
}

// rt-safe. The law is a min of falling bounds, so its root is the smallest of theirs.
double TangentLaw::root(double x, double k) const {
  const double ks = k * scale;
  double w = std::isfinite(a_const) ? x + ks * a_const : std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) w = std::min(w, term[i].root(x, ks));
  return std::max(x, std::min(w, w_cap));
}

}  // namespace softmc::motion
