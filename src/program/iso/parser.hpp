// ISO/RS274 G-code: text in, a checked Program (canonical instructions) or diagnostics out.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/diagnostic.hpp"
#include "program/ir/program.hpp"
#include "program/iso/m_functions.hpp"
#include "program/iso/tool_table.hpp"

namespace softmc::program::iso {

struct ParseOptions {
  core::Vec start;  // machine position at program start (the interpreter's initial state)
  // Directories searched, in order, for "o<name> call" of a subroutine not defined in the program:
  // the file <name>.ngc there must define o<name> sub … endsub. The main file's directory comes last.
  std::vector<std::string> subroutine_path;
  const ToolTable* tools = nullptr;  // for H and D words; null = no tool table
  const MTable* m_table = nullptr;   // P-10 groups incl. user M functions; null = the fixed table
  double g23_tolerance_mm = 0.05;    // G23 = G64 P<this> (plc_interface.md P-12)
  std::size_t max_loop_iterations = 100000;  // per loop entry: more is an endless loop
  std::size_t max_blocks = 10000000;         // blocks executed in all (loops unrolled): bounds the time
  std::size_t max_call_depth = 32;           // nested subroutine calls
};

struct ParseResult {
  std::optional<Program> program;  // present only when there is no error
  core::Diagnostics diagnostics;   // every error found, in source order (and warnings)
};

// Parses and interprets a whole program. Never throws on bad input: every problem becomes a
// Diagnostic with file:line:col, and no Program is returned when there is any error.
ParseResult parse(std::string_view text, const std::string& file_name, const ParseOptions& opt = {});

// Reads the file first; a missing or unreadable file is a diagnostic at line 0.
ParseResult parse_file(const std::string& path, const ParseOptions& opt = {});

}  // namespace softmc::program::iso
