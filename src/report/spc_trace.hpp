// The trace of an SPC run: per cycle the four SPC axes and the system signals at the terminals, as CSV and plot.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "control/spc/io_image.hpp"
#include "program/ir/spc_ops.hpp"

namespace softmc::report {

using program::kSpcAxes;

struct SpcTraceRow {
  double t_s = 0;                                 // time at the end of the cycle
  std::array<double, kSpcAxes> cmd{};             // setpoint, mm
  std::array<double, kSpcAxes> act{};             // measured position, mm
  std::array<std::uint16_t, control::spc::kIoModules> in{};   // input terminals (as wired, before the filter)
  std::array<std::uint16_t, control::spc::kIoModules> out{};  // output terminals
  bool ready = false;                             // READY (also in `out`; kept for quick checks)
};

struct SpcTrace {
  double period_s = 0.001;
  std::uint8_t axes = 0;  // bit i: SPC axis i (X Y Z U) is configured
  bool record_select = false;
  std::vector<SpcTraceRow> rows;
};

// A named system signal of the first module, in the trace's mode (S-8 / S-9 names).
struct SpcSignal {
  const char* name;
  control::spc::IoAddress addr;
};
// The signals the trace shows, outputs first: READY, MC/RC A/B, SYNC_O or ACK A/B, then STOP, START/RESET,
// ENABLE, SYNC_I or CLK A/B.
std::vector<SpcSignal> spc_signals(bool record_select);

// One CSV line per cycle: t_s, <axis>_cmd, <axis>_act per axis, each signal (0/1), LINE (B0..B4), and the
// input and output words of every module in hex. Throws std::runtime_error when the file cannot be written.
void write_spc_trace_csv(const std::string& path, const SpcTrace& trace);

// Axis positions over time and a timing diagram of the system signals (SVG or PNG by extension).
void write_spc_plot(const std::string& path, const SpcTrace& trace, const std::string& title);

}  // namespace softmc::report
