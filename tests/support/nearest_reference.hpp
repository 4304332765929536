// The reference for Segment::distance_to in tests: the nearest of a dense sampling by arc length,
// refined by ternary search between that sample's neighbours.
#pragma once

#include <algorithm>

#include "core/axes.hpp"
#include "motion/geometry/segment.hpp"

namespace softmc::test {

inline double brute_distance(const motion::Segment& g, const core::Vec& p, int samples = 20000) {
  int k_best = 0;
  double brute = 1e300;
  for (int k = 0; k <= samples; ++k) {
    const double d = core::distance(p, g.point(g.length * k / samples));
    if (d < brute) brute = d, k_best = k;
  }
  double lo = g.length * std::max(0, k_best - 1) / samples, hi = g.length * std::min(samples, k_best + 1) / samples;
  for (int it = 0; it < 100; ++it) {
    const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
    if (core::distance(p, g.point(m1)) < core::distance(p, g.point(m2)))
      hi = m2;
    else
      lo = m1;
  }
  return std::min(brute, core::distance(p, g.point(0.5 * (lo + hi))));
}

}  // namespace softmc::test
