// The interpreter's machine settings (tool table file, subroutine folders, user M functions) made into ParseOptions.
//
// The machine configuration's [gcode] table (machine/config.hpp) is copied into an InterpConfig by
// the composition root; InterpSetup loads and checks everything once, then hands out ParseOptions
// that point at its tables. Kept here, not in machine/, because the tables are the interpreter's.
#pragma once

#include <string>
#include <vector>

#include "core/diagnostic.hpp"
#include "program/iso/m_functions.hpp"
#include "program/iso/parser.hpp"
#include "program/iso/tool_table.hpp"

namespace softmc::program::iso {

struct InterpConfig {
  std::string tool_table;                    // LinuxCNC .tbl file; "" = none (H and D words then name no tool)
  std::vector<std::string> subroutine_path;  // folders searched for <name>.ngc, in order
  double g23_tolerance_mm = 0.05;            // G23 = G64 P<this> (P-12)
  std::vector<MConfig> m_functions;          // P-10 user entries; group 0 = the function's own group (fixed) or 14
  std::string source = "machine configuration";  // named in error messages (the TOML file)
};

// Owns the tool table and M table that the ParseOptions it makes point at: keep it alive (and in
// place: it is neither copied nor moved) while those options are used.
class InterpSetup {
 public:
  InterpSetup() = default;
  InterpSetup(const InterpSetup&) = delete;
  InterpSetup& operator=(const InterpSetup&) = delete;

  // Reads the tool table and configures the M functions; every problem is a diagnostic (tool table
  // lines as file:line:col, M functions naming their key gcode.m.<n>). Validate all, then use.
  core::Diagnostics load(const InterpConfig& cfg);
  ParseOptions options() const;
  const ToolTable* tools() const { return has_tools_ ? &tools_ : nullptr; }
  const MTable& m_table() const { return m_table_; }

 private:
  ToolTable tools_;
  bool has_tools_ = false;
  MTable m_table_;
  std::vector<std::string> subroutine_path_;
  double g23_tolerance_mm_ = 0.05;
};

}  // namespace softmc::program::iso
