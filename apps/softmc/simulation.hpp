// The composition root of a simulated run: machine + planner + interpolator + channel + drives,
// wired as cycle functions on a virtual clock; records the trace the reports are made from.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "machine/config.hpp"
#include "program/ir/program.hpp"
#include "report/trace.hpp"

namespace softmc::app {

struct SimOptions {
  bool record = true;                        // keep one TraceRow per cycle
  double max_time_s = 24 * 3600.0;           // a program still running then is reported as a timeout
  std::function<void(double fraction)> on_progress;  // called now and then with 0..1
};

struct SimResult {
  bool ok = false;
  std::string result = "ok";  // "ok", or what stopped the run (with the program line)
  report::Trace trace;
  std::uint64_t cycles = 0;
};

// Runs `prog` from its start position to its end on the simulated machine, in virtual time.
SimResult simulate(const program::Program& prog, const machine::MachineConfig& cfg, const SimOptions& opt = {});

// The cycle order, as documented in docs/code_flow.md (for tests and `softmc run --verbose`).
std::vector<std::string> cycle_order();

}  // namespace softmc::app
