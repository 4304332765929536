// Natural and clamped cubic splines by the tridiagonal slope system (Thomas algorithm).
#include "motion/geometry/cubic_spline.hpp"

#include <array>
#include <cmath>
#include <vector>

#include "motion/geometry/bezier.hpp"

namespace softmc::motion {

CurveResult cubic_spline(std::span<const Vec> points, const SplineEnds& ends, std::optional<std::uint8_t> param_axis) {
  const std::size_t np = points.size();
  if (np < 2) return {CurveError::TooFewPoints, {}};
  if (param_axis && *param_axis >= core::kMaxAxes) return {CurveError::BadValue, {}};
  for (const auto& p : points)
    for (std::size_t a = 0; a < core::kMaxAxes; ++a)
      if (!std::isfinite(p[a])) return {CurveError::BadValue, {}};
  const std::size_t n = np - 1;  // intervals
  std::vector<double> h(n);
  for (std::size_t i = 0; i < n; ++i) {
    h[i] = param_axis ? points[i + 1][*param_axis] - points[i][*param_axis] : core::distance(points[i], points[i + 1]);
    if (h[i] == 0) return {CurveError::RepeatedPoint, {}};
    if (param_axis && (h[i] > 0) != (h[0] > 0)) return {CurveError::NotMonotonic, {}};
  }
  const auto* clamped = std::get_if<ClampedEnds>(&ends);
  if (clamped)
    for (std::size_t a = 0; a < core::kMaxAxes; ++a)
      if (!std::isfinite(clamped->d0[a]) || !std::isfinite(clamped->d1[a])) return {CurveError::BadValue, {}};

  // Rows: sub[i]·D[i-1] + diag[i]·D[i] + sup[i]·D[i+1] = rhs[i].
  std::vector<double> sub(np, 0), diag(np, 0), sup(np, 0);
  std::vector<Vec> rhs(np);
  auto delta = [&](std::size_t i) { return (points[i + 1] - points[i]) * (1.0 / h[i]); };  // chord slope
  if (clamped) {
    diag[0] = 1;
    rhs[0] = clamped->d0;
    diag[n] = 1;
    rhs[n] = clamped->d1;
  } else {
    diag[0] = 2;
    sup[0] = 1;
    rhs[0] = delta(0) * 3.0;
    sub[n] = 1;
    diag[n] = 2;
    rhs[n] = delta(n - 1) * 3.0;
  }
  for (std::size_t i = 1; i < n; ++i) {
    sub[i] = h[i];
    diag[i] = 2 * (h[i - 1] + h[i]);
    sup[i] = h[i - 1];
    rhs[i] = (delta(i - 1) * h[i] + delta(i) * h[i - 1]) * 3.0;
  }
  // Thomas algorithm: diagonally dominant, so no pivoting is needed.
  for (std::size_t i = 1; i <= n; ++i) {
    const double m = sub[i] / diag[i - 1];
    diag[i] -= m * sup[i - 1];
    rhs[i] = rhs[i] - rhs[i - 1] * m;
  }
  std::vector<Vec> d(np);
  d[n] = rhs[n] * (1.0 / diag[n]);
  for (std::size_t i = n; i-- > 0;) d[i] = (rhs[i] - d[i + 1] * sup[i]) * (1.0 / diag[i]);

  CurveResult r;
  r.segments.reserve(n);
  const std::array<double, 4> ones{1, 1, 1, 1};
  for (std::size_t i = 0; i < n; ++i) {
    const double k = h[i] / 3;
    const std::array<Vec, 4> c{points[i], points[i] + d[i] * k, points[i + 1] - d[i + 1] * k, points[i + 1]};
    const CurveError e = append_rational_bezier(r.segments, c, ones);
    if (e != CurveError::Ok) return {e, {}};
  }
  return r;
}

}  // namespace softmc::motion
