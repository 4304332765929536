// The peak speed of a rest-to-rest or moving-to-moving move whose shape is two ramps (v0 → vp → v1)
// and a cruise: shared by the S-curve and the sine-squared profile, which differ only in their ramps.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

namespace softmc::motion::profile_detail {

// Inputs a move can be planned with: finite length, v0, v1 and a_max; length, v0, v1 ≥ 0; v_max,
// a_max > 0; j_max ≥ 0 or +∞ (no jerk limit, returned as 0).
inline std::optional<double> move_jerk(double length, double v0, double v1, double v_max, double a_max, double j_max) {
  if (!std::isfinite(length) || !std::isfinite(v0) || !std::isfinite(v1) || !std::isfinite(a_max)) return std::nullopt;
  if (!(length >= 0) || !(v_max > 0) || !(a_max > 0) || v0 < 0 || v1 < 0 || std::isnan(j_max) || j_max < 0)
    return std::nullopt;
  return std::isinf(j_max) ? 0.0 : j_max;
}

// The highest peak speed vp ≤ v_max (at least max(v0, v1)) whose two ramps, of length
// `ramps_length(vp)` (increasing in vp), fit in `length`: bisection to 1e-15 of vp. nullopt when
// even the ramps through max(v0, v1) are longer (v1 cannot be reached; rounding slack 1e-9 of the
// length).
template <class RampsLength>
std::optional<double> peak_speed(double length, double v0, double v1, double v_max, const RampsLength& ramps_length) {
  const double tol = 1e-9 * length + 1e-12;  // rounding slack on reachability
  double lo = std::max(v0, v1);
  if (ramps_length(lo) > length + tol) return std::nullopt;  // v1 unreachable
  double hi = std::max(lo, std::isinf(v_max) ? lo : v_max);
  if (ramps_length(hi) <= length) return hi;
  // Invariant: ramps_length(lo) ≤ length (up to tol) < ramps_length(hi).
  for (int i = 0; i < 80 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (ramps_length(mid) <= length ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace softmc::motion::profile_detail
