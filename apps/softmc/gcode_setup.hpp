// The G-code interpreter's settings from the machine configuration ([gcode], [planner]): one mapping
// for run, check and moves, and for the tests that must read programs as the CLI does.
#pragma once

#include <memory>

#include "machine/config.hpp"
#include "program/iso/interp_config.hpp"

namespace softmc::app {

// [gcode] tool table, subroutine folders and P-10 M functions; G23's tolerance from [planner].
program::iso::InterpConfig interp_config(const machine::MachineConfig& cfg);

// The loaded setup (tool table read, M table configured); it owns the tables its options() point
// at. Throws machine::ConfigError listing every problem.
std::unique_ptr<program::iso::InterpSetup> gcode_setup(const machine::MachineConfig& cfg);

}  // namespace softmc::app
