// LinuxCNC's predefined named parameters (#<_x>, #<_motion_mode>, …; docs/gcode.md) from the
// interpreter's state, as LinuxCNC 2.9's rs274 gives them.
#pragma once

#include <string_view>

#include "core/axes.hpp"
#include "program/iso/modal_state.hpp"
#include "program/iso/parameters.hpp"

namespace softmc::program::iso {

// Whether a line names a global (#<_…>, spaces allowed after '<'): only such a line may read a
// predefined parameter, so they are worked out only before one.
bool may_read_predefined(std::string_view line);

// A position in mm as the program's units give it (linear axes in inches under G20; rotary axes
// in degrees): #5420…, #<_x>…, #<_abs_x>….
core::Vec in_program_units(core::Vec v, Units u);

// Sets every predefined parameter that the state gives; `tool` is where the tool is in machine
// coordinates (under cutter compensation the offset point, not the programmed one). The current
// position (#<_x>…) and the call level are answered by Parameters itself (from #5420… and its frames).
void set_predefined_parameters(Parameters& params, const ModalState& st, const core::Vec& tool);

}  // namespace softmc::program::iso
