// A checked SPC program: the IR plus its N line numbers, so jumps through registers find their line.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "program/ir/program.hpp"

namespace softmc::program::spc {

inline constexpr int kMaxLine = 999;        // N000..N999 (S-1)
inline constexpr int kPrograms = 100;       // P0..P99
inline constexpr int kRecordMaxLine = 31;   // Record Select programs: N000..N031 (S-9)

struct SpcProgram {
  int number = -1;                      // n of P<n>; -1 when parsed from an unnamed text
  Program ir;                           // SPC payloads only
  std::vector<std::uint16_t> lines;     // N number of each instruction
  std::array<std::int16_t, kMaxLine + 1> index_of_line;  // instruction index of line N, or -1

  SpcProgram() { index_of_line.fill(-1); }
  // rt-safe: instruction index of line N, or -1 when the program has no such line.
  int index(int line) const { return line >= 0 && line <= kMaxLine ? index_of_line[line] : -1; }
  std::size_t size() const { return ir.instructions.size(); }
};

}  // namespace softmc::program::spc
