// SPC positioning language (spc200.md S-1..S-7): text in, a checked SpcProgram or diagnostics out.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "core/diagnostic.hpp"
#include "program/spc/spc_program.hpp"

namespace softmc::program::spc {

struct ParseOptions {
  bool record_select = false;  // S-9: only motion and motion-specification lines, N000..N031
  int number = -1;             // the program's number (P<n>), for messages and the result
};

struct ParseResult {
  std::optional<SpcProgram> program;  // present only when there is no error
  core::Diagnostics diagnostics;      // every error, in source order
};

// Never throws on bad input: every problem is a Diagnostic `file:line:col: error: message`.
ParseResult parse(std::string_view text, const std::string& file_name, const ParseOptions& opt = {});

}  // namespace softmc::program::spc
