// One row per interpolation cycle: what the simulation recorded, for summaries, CSV traces and plots.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/axes.hpp"
#include "program/ir/iso_ops.hpp"

namespace softmc::report {

struct TraceRow {
  double t_s = 0;        // time at the end of the cycle
  core::Vec cmd;         // commanded (interpolated) position, mm
  core::Vec act;         // measured (encoder) position, mm
  core::Vec vel;         // commanded velocity, mm/s
  double path_v = 0;     // commanded path speed, mm/s
  std::uint32_t tag = 0; // index of the program instruction being executed
  std::uint32_t tag_last = 0; // a merged line: the last instruction it stands for
  bool moving = false;   // a motion segment is being interpolated
  bool rapid = false;    // ... and it is a rapid
  bool tool_on = false;  // torch/spindle output
  std::uint64_t dout = 0;  // digital outputs 0…63 (bit n: output n; M62…M65)
  std::array<double, program::kAnalogOutputs> aout{};  // analog outputs 0…3 (M67/M68)
  bool stopped = false;  // a P-5 stop has brought the path to rest here, inside a motion (the run ends)
};

struct Trace {
  double period_s = 0.001;
  core::AxisMask axes = 0;  // which axes the machine has
  std::vector<TraceRow> rows;
};

}  // namespace softmc::report
