// `softmc moves`: the interpreter's canonical output as JSON Lines (one object per instruction).
#pragma once

#include <cstdio>
#include <string>

#include "core/axes.hpp"
#include "core/diagnostic.hpp"
#include "program/ir/program.hpp"
#include "program/iso/parser.hpp"

namespace softmc::app {

// Writes every instruction of `prog`, in program order, as one JSON object per line (schema in
// docs/moves.md). Positions are printed for the axes in `axes` (the machine's axes), with the
// shortest decimal that reads back as the same double. Buffered; one fwrite per MiB.
void write_moves(std::FILE* out, const program::Program& prog, core::AxisMask axes);

// `softmc moves PROGRAM`: parses the file with `opt` and streams its instructions into the same
// JSON Lines as they are made (the IR of a million-line program is never held whole). On any
// error nothing is written: output that can be cut back (a file, /dev/null) is written as it
// comes and truncated to where it began; a pipe or terminal gets the text only once the whole
// program is known to be good. Returns the diagnostics (errors and warnings).
core::Diagnostics write_program_moves(std::FILE* out, const std::string& path, program::iso::ParseOptions opt,
                                      core::AxisMask axes);

// The same text as a string (tests, small programs).
std::string moves_jsonl(const program::Program& prog, core::AxisMask axes);

}  // namespace softmc::app
