// Axis limits as a plain value: machine/ fills it in from configuration, the planner obeys it.
#pragma once

#include <array>

#include "core/axes.hpp"

namespace softmc::motion {

struct AxisLimits {
  double v_max_mm_s = 0;    // 0 = axis not present
  double a_max_mm_s2 = 0;
  double j_max_mm_s3 = 0;   // 0 = no jerk limit
  double min_mm = -1e9, max_mm = 1e9;  // travel (soft limits)
};

struct MachineLimits {
  std::array<AxisLimits, core::kMaxAxes> axis{};
  double period_s = 0.001;  // interpolation period

  bool present(std::size_t i) const { return axis[i].v_max_mm_s > 0; }
};

}  // namespace softmc::motion
