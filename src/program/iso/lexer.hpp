// Lexer: one line of RS274 text into letter/number words, each with the column of its letter.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "program/iso/line_error.hpp"

namespace softmc::program::iso {

// A letter and the number after it, exactly as written (program units, no modal meaning yet).
struct Word {
  char letter = 0;        // upper case A..Z
  double value = 0;       // finite, |value| <= kMaxNumberMagnitude
  std::uint32_t col = 0;  // 1-based column of the letter
};

// Numbers beyond this are refused as out of range: no sane machine coordinate, feed or time comes
// near it, and the bound keeps every later product and sum finite.
inline constexpr double kMaxNumberMagnitude = 1e9;

// What a line holds once comments and white space are gone.
enum class LineKind : std::uint8_t {
  Empty,        // blank or comments only
  Percent,      // a '%' tape delimiter line
  BlockDelete,  // starts with '/': skipped (the block delete switch is always on)
  Block,        // one block of words
};

struct LexedLine {
  LineKind kind = LineKind::Empty;
  std::vector<Word> words;          // for LineKind::Block, in source order
  std::optional<LineError> error;   // the first lexical error; `words` is then incomplete
};

// Lexes one line (without its '\n'). Dialect-neutral: any letter makes a word; which letters and
// codes mean something is decided by the block check. Never throws on any bytes.
LexedLine lex_line(std::string_view line);

}  // namespace softmc::program::iso
