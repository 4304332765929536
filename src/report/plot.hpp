// Cairo plots of a run: the table with its cut and rapid paths, and path speed over time beneath.
#pragma once

#include <string>

#include "machine/config.hpp"
#include "program/ir/program.hpp"
#include "report/trace.hpp"

namespace softmc::report {

// Writes an SVG or PNG by the file's extension; throws std::runtime_error on an unknown extension
// or a file that cannot be written.
void write_plot(const std::string& path, const program::Program& prog, const machine::MachineConfig& cfg,
                const Trace& trace);

}  // namespace softmc::report
