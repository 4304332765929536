// `softmc moves`: the interpreter's canonical output as JSON Lines (one object per instruction).
#pragma once

#include <cstdio>
#include <string>

#include "core/axes.hpp"
#include "program/ir/program.hpp"

namespace softmc::app {

// Writes every instruction of `prog`, in program order, as one JSON object per line (schema in
// docs/moves.md). Positions are printed for the axes in `axes` (the machine's axes), with the
// shortest decimal that reads back as the same double. Buffered; one fwrite per 64 KiB.
void write_moves(std::FILE* out, const program::Program& prog, core::AxisMask axes);

// The same text as a string (tests, small programs).
std::string moves_jsonl(const program::Program& prog, core::AxisMask axes);

}  // namespace softmc::app
