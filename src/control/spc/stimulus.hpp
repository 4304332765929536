// Input stimulus files for `softmc run` on an SPC machine: timed writes to the controller's input terminals.
//
//   # comment (also after a value)
//   0       ENABLE  1        time in seconds, a signal name or an input address, a value
//   0       STOP    1
//   10.5    START   1
//   10.52   START   0
//   11      I2.3    1
//   12      LINE    17       B0..B4 at once (0..31)
// Times never decrease. A write takes effect at the first cycle whose time is ≥ its time, and then
// passes the input filter like any other input. Outputs (READY, Q2.1, ...) cannot be written.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "control/spc/io_image.hpp"
#include "core/diagnostic.hpp"

namespace softmc::control::spc {

struct StimulusEvent {
  double t_s = 0;
  IoAddress addr{};      // the input written (for LINE: I0.0, the first of the five bits)
  bool line = false;     // LINE: value is a line number 0..31 on B0..B4
  std::uint8_t value = 0;
  std::uint32_t source_line = 0;  // where it came from, for messages
};

struct Stimulus {
  std::vector<StimulusEvent> events;  // in time order
};

struct StimulusParseResult {
  std::optional<Stimulus> stimulus;  // present only without errors
  core::Diagnostics diagnostics;     // `file:line:col: error: message`
};

// Never throws on bad input.
StimulusParseResult parse_stimulus(std::string_view text, const std::string& file_name);
// Reads and parses a file; an unreadable file is one diagnostic.
StimulusParseResult load_stimulus(const std::string& path);

// Plays a parsed stimulus into the terminals, cycle by cycle.
class StimulusPlayer {
 public:
  explicit StimulusPlayer(const Stimulus& s) : s_(s) {}
  // rt-safe: applies every event with t_s ≤ now_s not applied yet; returns how many it applied.
  int apply(double now_s, IoImage& terminals);
  bool finished() const { return next_ >= s_.events.size(); }

 private:
  const Stimulus& s_;
  std::size_t next_ = 0;
};

}  // namespace softmc::control::spc
