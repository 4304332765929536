// The sampled state of a 1-D profile at one instant: position, speed, acceleration, jerk.
#pragma once

namespace softmc::motion {

struct ProfileState {
  double s = 0;  // mm (path length for path profiles, axis position for point-to-point)
  double v = 0;  // mm/s
  double a = 0;  // mm/s²
  double j = 0;  // mm/s³ (0 where the profile has no jerk, e.g. a trapezoid)
};

}  // namespace softmc::motion
