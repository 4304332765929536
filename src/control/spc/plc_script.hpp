// Orders files for the reference PLC (S-10) in `softmc run --plc FILE`: when the PLC queues which order.
//
//   # time  task  line          the PLC queues `line` (0..31) for task A or B at that time; it gives the
//   10.2    A     17            order (line bits, CLK, ACK, RC) itself, as the S-10 sequence says
//   10.2    B     3
//   12.0    STOP                the PLC's own stop (operator button): STOP=0 for a moment, MemStop
//   12.5    ENABLE 0            the PLC's ENABLE output (0/1)
// Times never decrease; `#` starts a comment. Errors are `file:line:col: error: message`.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "control/spc/plc_client.hpp"
#include "core/diagnostic.hpp"

namespace softmc::control::spc {

struct PlcScriptEntry {
  enum class Kind : std::uint8_t { Order, Stop, Enable };
  double t_s = 0;
  Kind kind = Kind::Order;
  std::uint8_t task = 0;  // Order: 0 = A, 1 = B
  std::uint8_t value = 0; // Order: line 0..31; Enable: 0/1
  std::uint32_t source_line = 0;
};

struct PlcScript {
  std::vector<PlcScriptEntry> entries;  // in time order
};

struct PlcScriptParseResult {
  std::optional<PlcScript> script;  // present only without errors
  core::Diagnostics diagnostics;
};

// Never throws on bad input.
PlcScriptParseResult parse_plc_script(std::string_view text, const std::string& file_name);
PlcScriptParseResult load_plc_script(const std::string& path);

// Feeds a script into a PlcClient as its time comes.
class PlcScriptPlayer {
 public:
  explicit PlcScriptPlayer(const PlcScript& s) : s_(s) {}
  // rt-safe (PlcClient::order pushes into its preallocated queue): applies the entries due at now_s;
  // returns how many orders the PLC's queue refused (full).
  int apply(double now_s, PlcClient& plc);
  bool finished() const { return next_ >= s_.entries.size(); }

 private:
  const PlcScript& s_;
  std::size_t next_ = 0;
};

}  // namespace softmc::control::spc
