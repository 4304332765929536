// Golden-section search for the peak of a function that is unimodal on a bracket.
#pragma once

namespace softmc::motion {

struct GoldenPeak {
  double u = 0;  // the middle of the last bracket
  double f = 0;  // the larger of the last two values
};

// rt-safe. The largest f on [lo, hi] (f unimodal there): at most `steps` steps, and none once the
// bracket is `width` wide or less. A minimum is the peak of −f.
template <class F>
GoldenPeak golden_max(const F& f, double lo, double hi, int steps, double width = 0) {
  constexpr double kG = 0.6180339887498949;
  double m1 = hi - kG * (hi - lo), m2 = lo + kG * (hi - lo), f1 = f(m1), f2 = f(m2);
  for (int it = 0; it < steps && hi - lo > width; ++it) {
    if (f1 > f2) {
      hi = m2, m2 = m1, f2 = f1, m1 = hi - kG * (hi - lo), f1 = f(m1);
    } else {
      lo = m1, m1 = m2, f1 = f2, m2 = lo + kG * (hi - lo), f2 = f(m2);
    }
  }
  return {0.5 * (lo + hi), f1 > f2 ? f1 : f2};
}

}  // namespace softmc::motion
