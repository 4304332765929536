// Cairo plots of a run: the table with its cut and rapid paths, and path speed over time beneath.
#pragma once

#include <string>
#include <vector>

#include "machine/config.hpp"
#include "program/ir/program.hpp"
#include "report/trace.hpp"

namespace softmc::report {

// A moment marked on the time panels (a PLC signal written during the run: "hold", "%F 50").
struct PlotEvent {
  double t_s = 0;
  std::string label;
};

// Writes an SVG or PNG by the file's extension; throws std::runtime_error on an unknown extension
// or a file that cannot be written. `events` are drawn as marked lines on the speed panel.
void write_plot(const std::string& path, const program::Program& prog, const machine::MachineConfig& cfg,
                const Trace& trace, const std::vector<PlotEvent>& events = {});

}  // namespace softmc::report
