// Lexer: one line of RS274/NGC text into words (values evaluated), parameter assignments, an O-word
// and operator messages, each with the column it came from.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "program/ir/iso_ops.hpp"
#include "program/iso/line_error.hpp"
#include "program/iso/parameters.hpp"

namespace softmc::program::iso {

// A letter and its value (program units, no modal meaning yet).
struct Word {
  char letter = 0;        // upper case A..Z, or '@' / '^' (LinuxCNC's polar radius and angle)
  double value = 0;       // finite, |value| <= kMaxNumberMagnitude for literal numbers
  std::uint32_t col = 0;  // 1-based column of the letter
};

// Numbers beyond this are refused as out of range: no sane machine coordinate, feed or time comes
// near it, and the bound keeps every later product and sum finite.
inline constexpr double kMaxNumberMagnitude = 1e9;

// #n = value / #<name> = value. Values are read before any assignment of the line takes effect
// (LinuxCNC: "#1=2 #2=#1" sets #2 to the old #1).
struct Assignment {
  bool named = false;
  long long number = 0;
  std::string name;
  double value = 0;
  std::uint32_t col = 0;
};

// Program and ProgramEnd are not written as keywords: they are a Fanuc-style subprogram's "O1000"
// line and the M99 line that closes it (the control-flow index finds them; docs/gcode.md).
enum class OKeyword : std::uint8_t {
  Sub, EndSub, Call, Return, If, ElseIf, Else, EndIf, While, EndWhile, Do, Repeat, EndRepeat, Break, Continue,
  Program, ProgramEnd
};
const char* to_string(OKeyword k);

// "O<name> keyword [args]": name lower case ("<name>" or the number as written, e.g. "100").
struct OWord {
  std::string name;
  OKeyword keyword = OKeyword::Sub;
  std::uint32_t col = 0;          // of the O
  std::vector<double> args;       // call arguments, or the single value of if/while/repeat/return
};

// (MSG, …), (DEBUG, …), (PRINT, …): the text after the comma, as written (format_message
// substitutes the parameters of DEBUG and PRINT when the block runs).
struct LineMessage {
  MessageKind kind = MessageKind::Msg;
  std::string text;
};

// What a line holds once comments and white space are gone.
enum class LineKind : std::uint8_t {
  Empty,        // blank or comments only
  Percent,      // a '%' tape delimiter line
  BlockDelete,  // starts with '/': skipped (the block delete switch is always on)
  Block,        // words, assignments, messages or an O-word
};

struct LexedLine {
  LineKind kind = LineKind::Empty;
  std::vector<Word> words;          // in source order
  std::vector<Assignment> assignments;
  std::optional<OWord> o;
  std::vector<LineMessage> messages;
  std::optional<std::string> abort;  // (ABORT, text): the text as written (LinuxCNC 2.9 stops the program)
  std::uint32_t abort_col = 0;       // of its '(' 
  std::optional<LineError> error;   // the first error; the rest of the line is then incomplete
};

// Lexes one line (without its '\n'), evaluating values with `params`. Never throws on any bytes.
// `out` is reused (its buffers keep their capacity).
void lex_line(std::string_view line, const Parameters& params, LexedLine& out);
// Convenience for tests and tools: parameters all zero, no named ones.
LexedLine lex_line(std::string_view line);

// The text of a DEBUG or PRINT message with its parameters' values, as LinuxCNC prints them: #
// and the digits right after it (#12, not "# 12" nor #[12]) or #<name> become the value with six
// decimals (0.000000 under 0.0001); a parameter that does not exist becomes "######"; any other
// '#' stays as it is.
std::string format_message(std::string_view text, const Parameters& params);


// Reads only the O-word header (name, keyword, column) of a line, without evaluating anything:
// the control-flow index is built from it before the program runs.
std::optional<OWord> scan_o_word(std::string_view line);

// A bare O-number line ("O1000", after an optional N word, nothing after it but spaces and
// comments): its number as O-word names are kept ("1000": no leading zeros) and the O's column.
struct ProgramNumber {
  std::string name;
  std::uint32_t col = 0;
};
std::optional<ProgramNumber> scan_program_number(std::string_view line);

// The column of an M99 word on the line (outside comments and #<names>), 0 where there is none or
// the line is a block-delete line ("/M99"): a quick scan for the control-flow index; the line is
// lexed in full when it runs.
std::uint32_t scan_m99(std::string_view line);

}  // namespace softmc::program::iso
