// Reusable trace checker: differentiates per-cycle setpoints and measures speed, acceleration, jerk
// (per axis, as a fraction of its limit) and the distance from the programmed path.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "motion/geometry/segment.hpp"
#include "motion/limits.hpp"

namespace softmc::motion::testing {

struct TraceFigures {
  double v_ratio = 0, a_ratio = 0, j_ratio = 0;  // largest |d^k pos_i / dt^k| / limit_i over axes
  std::size_t v_axis = 0, a_axis = 0, j_axis = 0;
  std::size_t a_sample = 0, j_sample = 0;
  double deviation_mm = 0;  // largest distance of a setpoint from the programmed path
  std::size_t samples = 0;
  std::size_t dev_sample = 0;
  std::uint32_t dev_tag = 0;
  bool finite = true;

  std::string describe() const {
    std::ostringstream o;
    o.precision(12);
    o << "v " << v_ratio << " (axis " << v_axis << "), a " << a_ratio << " (axis " << a_axis << ", sample "
      << a_sample << "), j " << j_ratio << " (axis " << j_axis << ", sample " << j_sample << "), deviation " << deviation_mm << " mm (sample " << dev_sample << ", tag " << dev_tag << ") over "
      << samples << " samples";
    return o.str();
  }
};

class TraceChecker {
 public:
  // `path[k]` is the programmed segment with tag k (the tag the setpoints carry).
  TraceChecker(const MachineLimits& lim, double dt, std::vector<Segment> path)
      : lim_(lim), dt_(dt), path_(std::move(path)) {}

  void add(const core::Vec& pos, std::uint32_t tag) {
    for (std::size_t i = 0; i < core::kMaxAxes; ++i)
      if (!std::isfinite(pos[i])) f_.finite = false;
    hist_[0] = hist_[1];
    hist_[1] = hist_[2];
    hist_[2] = hist_[3];
    hist_[3] = pos;
    ++n_;
    for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
      if (!lim_.present(i)) continue;
      const auto& L = lim_.axis[i];
      if (n_ >= 2) take(f_.v_ratio, f_.v_axis, std::abs(hist_[3][i] - hist_[2][i]) / dt_ / L.v_max_mm_s, i);
      if (n_ >= 3) {
        const double a = std::abs(hist_[3][i] - 2 * hist_[2][i] + hist_[1][i]) / (dt_ * dt_) / L.a_max_mm_s2;
        if (a > f_.a_ratio) f_.a_sample = n_;
        take(f_.a_ratio, f_.a_axis, a, i);
      }
      if (n_ >= 4 && L.j_max_mm_s3 > 0) {
        const double j = hist_[3][i] - 3 * hist_[2][i] + 3 * hist_[1][i] - hist_[0][i];
        const double jr = std::abs(j) / (dt_ * dt_ * dt_) / L.j_max_mm_s3;
        if (jr > f_.j_ratio) f_.j_sample = n_;
        take(f_.j_ratio, f_.j_axis, jr, i);
      }
    }
    if (!path_.empty()) {
      const std::size_t k = std::min<std::size_t>(tag, path_.size() - 1);
      // Only whether it is beyond the largest so far matters: a point at or below it ends the search.
      const double enough = f_.deviation_mm;
      double d = path_[k].distance_to(pos, enough);
      for (std::size_t m = (k >= 2 ? k - 2 : 0); d > enough && m <= std::min(path_.size() - 1, k + 2); ++m)
        d = std::min(d, path_[m].distance_to(pos, enough));
      if (d > enough) {
        double all = d;  // a blend may carry a neighbour's tag: look at the whole path before blaming
        for (std::size_t m = 0; all > enough && m < path_.size(); ++m) all = std::min(all, path_[m].distance_to(pos, enough));
        d = all;
      }
      if (d > f_.deviation_mm) f_.dev_sample = n_, f_.dev_tag = tag;
      f_.deviation_mm = std::max(f_.deviation_mm, d);
    }
    f_.samples = n_;
  }

  const TraceFigures& figures() const { return f_; }

 private:
  static void take(double& best, std::size_t& axis, double x, std::size_t i) {
    if (x > best) {
      best = x;
      axis = i;
    }
  }
  MachineLimits lim_;
  double dt_;
  std::vector<Segment> path_;
  core::Vec hist_[4]{};
  std::size_t n_ = 0;
  TraceFigures f_;
};

}  // namespace softmc::motion::testing
