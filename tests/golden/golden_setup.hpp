// The golden programs' interpreter setup: tests/golden/machine.toml's [gcode] table (the tool table).
#pragma once

#include <gtest/gtest.h>

#include <filesystem>

#include "gcode_setup.hpp"
#include "machine/config.hpp"
#include "program/iso/interp_config.hpp"

namespace softmc::golden {

// The interpreter as `softmc run/check/moves --machine tests/golden/machine.toml` sets it up (the
// [gcode] table mapped by app::interp_config, as the CLI does): its tool table tool_mm.tbl holds
// the tools of tool.tbl, which regen.sh gives rs274 (in inches), so G43 H and G41/G42 D are compared
// with LinuxCNC's through the configuration.
inline const program::iso::InterpSetup& setup() {
  static const auto* setup = [] {
    const auto file = std::filesystem::path(SOFTMC_SOURCE_DIR) / "tests" / "golden" / "machine.toml";
    const auto cfg = machine::load_machine(file.string());
    auto* s = new program::iso::InterpSetup;
    for (const auto& d : s->load(app::interp_config(cfg))) ADD_FAILURE() << d.format();
    return s;
  }();
  return *setup;
}

}  // namespace softmc::golden
