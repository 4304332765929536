// ISO/RS274 G-code: text in, a checked Program (canonical instructions) or diagnostics out.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "core/diagnostic.hpp"
#include "program/ir/program.hpp"

namespace softmc::program::iso {

struct ParseOptions {
  core::Vec start;  // machine position at program start (the interpreter's initial state)
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
