// The PLC→CNC signals that act on a channel's motion (P-2, P-5, P-8): the part of the PLC signal
// image a Channel reads each cycle (Channel::apply). Writes take effect at the next cycle boundary.
#pragma once

#include <array>
#include <cstdint>

#include "core/axes.hpp"

namespace softmc::control {

struct MotionSignals {
  // P-8: F_corrected = F_programmed × %F × multiplier; 1000 ‰ = the programmed feed. Rapids follow
  // up to 100 %; no axis ever exceeds its own speed limit, and the planner's max_feed_override caps it.
  std::uint16_t feed_override_permille = 1000;
  std::uint16_t feed_override_multiplier_permille = 1000;
  // P-8 feed limits: with the request bit set, the path speed of feed moves (rapids) is capped at
  // the limit, in mm/min, whatever the override and M49 (a limit of 0 caps nothing).
  bool feed_limit_request = false;
  std::uint16_t feed_limit_mm_min = 0;
  bool rapid_limit_request = false;
  std::uint16_t rapid_limit_mm_min = 0;
  // Feed hold: brake to rest on the path with the normal ramp; 0 resumes from there.
  bool feed_hold = false;
  // P-2: per axis; any axis of the channel at 0 brakes the path to rest with the normal ramp, all
  // back at 1 resume it on the path without a jump.
  std::array<bool, core::kMaxAxes> axis_enable = all_enabled();
  // P-5: a rising edge of stop_pulse stops the program like the STOP button (the PLC resets it);
  // stop_request and emergency_stop_request are acknowledged: the channel clears them when it takes
  // them. The emergency stop brakes with the emergency ramp ([planner] emergency_accel_scale).
  bool stop_pulse = false;
  bool stop_request = false;
  bool emergency_stop_request = false;

  double feed_override() const {
    return feed_override_permille / 1000.0 * (feed_override_multiplier_permille / 1000.0);
  }
  // The caps in mm/s; 0: none.
  double feed_limit_mm_s() const { return feed_limit_request ? feed_limit_mm_min / 60.0 : 0.0; }
  double rapid_limit_mm_s() const { return rapid_limit_request ? rapid_limit_mm_min / 60.0 : 0.0; }

 private:
  static constexpr std::array<bool, core::kMaxAxes> all_enabled() {
    std::array<bool, core::kMaxAxes> a{};
    a.fill(true);
    return a;
  }
};

}  // namespace softmc::control
