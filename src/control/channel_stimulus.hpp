// Stimulus files for `softmc run` on a G-code program: timed writes to the motion signals of the
// channel (P-2, P-5, P-8), as a PLC would make them while the program runs.
//
//   # time  signal                       value
//   2.0     feed_override_permille       500     %F in per mille (0..65535; 1000 = programmed feed)
//   2.0     feed_override_multiplier_permille 1000
//   3.0     feed_limit_mm_min            1200    P-8 cap on feed moves' path speed (0..65535 mm/min) ...
//   3.0     feed_limit_request           1       ... in force while the request is 1 (rapids:
//                                                rapid_limit_mm_min, rapid_limit_request)
//   3.5     feed_hold                    1       brake to rest on the path; 0 resumes
//   4.0     feed_hold                    0
//   5.0     axis_enable[Y]               0       P-2, per axis letter of the machine
//   5.5     axis_enable[Y]               1
//   7.0     stop_pulse                   1       P-5: a rising edge stops the program
//   7.0     stop_request                 1       P-5: acknowledged stop (only 1 can be written)
//   7.0     emergency_stop_request       1       P-5: acknowledged emergency stop
// Times never decrease; names are case-insensitive; `#` starts a comment. A write takes effect at
// the first cycle that starts at or after its time. Errors are `file:line:col: error: message`.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "control/motion_signals.hpp"
#include "core/axes.hpp"
#include "core/diagnostic.hpp"

namespace softmc::control {

enum class MotionSignal : std::uint8_t {
  FeedOverride,
  FeedOverrideMultiplier,
  FeedLimitRequest,
  FeedLimit,
  RapidLimitRequest,
  RapidLimit,
  FeedHold,
  AxisEnable,
  StopPulse,
  StopRequest,
  EmergencyStopRequest,
};
const char* to_string(MotionSignal s);

struct ChannelStimulusEvent {
  double t_s = 0;
  MotionSignal signal = MotionSignal::FeedOverride;
  std::uint8_t axis = 0;  // AxisEnable: the axis index
  std::uint16_t value = 0;
  std::uint32_t source_line = 0;
};

struct ChannelStimulus {
  std::vector<ChannelStimulusEvent> events;  // in time order
};

struct ChannelStimulusParseResult {
  std::optional<ChannelStimulus> stimulus;  // present only without errors
  core::Diagnostics diagnostics;
};

// Never throws on bad input. `axes`: the machine's axes (axis_enable[L] must name one of them).
ChannelStimulusParseResult parse_channel_stimulus(std::string_view text, const std::string& file_name,
                                                  core::AxisMask axes);
// Reads and parses a file; an unreadable file is one diagnostic.
ChannelStimulusParseResult load_channel_stimulus(const std::string& path, core::AxisMask axes);

// A few words for plots: "%F 50", "x 80 %", "hold", "release", "Y off", "stop", "e-stop"; empty
// for a write that does nothing by itself (stop_pulse 0).
std::string short_label(const ChannelStimulusEvent& e);

// rt-safe: writes one event into the signals.
void apply(const ChannelStimulusEvent& e, MotionSignals& s);

// Plays a parsed stimulus into the signals, cycle by cycle.
class ChannelStimulusPlayer {
 public:
  explicit ChannelStimulusPlayer(const ChannelStimulus& s) : s_(s) {}
  // rt-safe: applies every event with t_s ≤ now_s not applied yet; returns how many it applied.
  int apply(double now_s, MotionSignals& signals);
  bool finished() const { return next_ >= s_.events.size(); }

 private:
  const ChannelStimulus& s_;
  std::size_t next_ = 0;
};

}  // namespace softmc::control
