// ISO/RS274 G-code: text in, a checked Program (canonical instructions) or diagnostics out.
#pragma once

#include <cstddef>
#include <functional>
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
  // Work limits. Every line of the files read may run once; loops and calls may add `max_blocks`
  // more executed blocks, and the program may make two instructions per line plus
  // `max_instructions` more (loops, canned-cycle repeats and pecks). Any input therefore ends in a
  // time and memory proportional to its length plus a constant (about 0.2 s and 300 MB at most
  // for a short program); passing a limit is an error. docs/gcode.md lists them.
  std::size_t max_loop_iterations = 100000;  // per loop entry: more is an endless loop
  std::size_t max_blocks = 1000000;          // executed blocks beyond one pass over the text
  std::size_t max_instructions = 1000000;    // instructions beyond two per line of text
  std::size_t max_call_depth = 32;           // nested subroutine calls
  // Plain straight-move lines take a one-pass path (fast_block.hpp) with the same result; off, every
  // line goes through the lexer, block check and interpreter (the fuzz target compares the two).
  bool fast_path = true;

  // Streaming (optional): when set, the instructions go to `sink` in batches of about `sink_batch`
  // while the program is read, instead of into ParseResult::program (whose instruction list then
  // stays empty; files and start are filled in). The batch's `files` are those known so far. The
  // sink still sees instructions of a program that turns out to have errors: a caller that must
  // act only on good programs keeps what it gets until parse() has returned without errors.
  std::function<void(const Program& batch)> sink;
  std::size_t sink_batch = 4096;
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
