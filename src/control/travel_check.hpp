// Soft limits before motion (plc_interface.md P-9): the whole programmed path is checked against the
// axis travel before anything moves, arcs included, and every violation names its program line.
#pragma once

#include "core/diagnostic.hpp"
#include "motion/limits.hpp"
#include "program/ir/program.hpp"

namespace softmc::control {

// One diagnostic per motion instruction whose segment leaves the travel of an axis (or moves an
// axis the machine does not have): "X leaves the travel: 612.000 mm > max 600.000 mm".
core::Diagnostics check_travel(const program::Program& prog, const motion::MachineLimits& limits);

}  // namespace softmc::control
