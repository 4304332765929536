// Machine configuration → interpreter setup.
#include "gcode_setup.hpp"

namespace softmc::app {

program::iso::InterpConfig interp_config(const machine::MachineConfig& cfg) {
  program::iso::InterpConfig ic;
  ic.tool_table = cfg.gcode.tool_table;
  ic.subroutine_path = cfg.gcode.subroutine_path;
  ic.g23_tolerance_mm = cfg.planner.tolerance_mm;
  for (const auto& m : cfg.gcode.m)
    ic.m_functions.push_back({m.number, m.group, m.break_path_start, m.break_path_end, m.changes_position});
  ic.source = "machine configuration";
  return ic;
}

std::unique_ptr<program::iso::InterpSetup> gcode_setup(const machine::MachineConfig& cfg) {
  auto setup = std::make_unique<program::iso::InterpSetup>();
  const auto diags = setup->load(interp_config(cfg));
  if (core::has_errors(diags)) {
    std::string text;
    for (const auto& d : diags)  // "file: error: message" where there is no line (ConfigError's style)
      text += (text.empty() ? "" : "\n") + (d.line ? d.format() : d.file + ": error: " + d.message);
    throw machine::ConfigError(text);
  }
  return setup;
}

}  // namespace softmc::app
