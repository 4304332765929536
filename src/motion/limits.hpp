// Axis limits as a plain value: machine/ fills it in from configuration, the planner obeys it.
#pragma once

#include <array>

#include "core/axes.hpp"

namespace softmc::motion {

// The least distance one cycle of an axis's jerk may move, j·dt³: the jerk follower's tolerances
// (stops landing on their point, the guard's rounding slack) are tested down to it, and keep the axis
// jerk within 1e-4 of its limit there (PlannerJerk.AxesWithATinyJerkPerCycleKeepItAtRestOnAPoint).
// Below it they are coarser than a cycle of jerk: the configuration refuses such an axis. Raised
// from 2e-10 mm: `bench/fuzz_run.py --floor` found axes up to 6× over their jerk below 2e-9 mm
// (third differences 1e-10 to 1.5e-9 mm over j·dt³), none above it (docs/planner.md, "Tiny jerk
// per cycle").
inline constexpr double kMinJerkStep_mm = 2e-9;

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
