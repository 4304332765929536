// Values in RS274/NGC words: numbers, #parameters, [expressions] and functions, as LinuxCNC reads them.
//
//   value      := number | '#' param | '[' expr ']' | func | ('+'|'-') value
//   expr       := value (binop value)*         precedence (LinuxCNC): ** > * / MOD > + - >
//                                              EQ NE GT GE LT LE > AND OR XOR; all left-associative
//   func       := ABS ACOS ASIN COS EXP FIX FUP ROUND LN SIN SQRT TAN '[' expr ']'
//               | ATAN '[' expr ']' '/' '[' expr ']' | EXISTS '[' '#<' name '>' ']'
// Angles are in degrees. Every result is checked finite, so NaN and overflow are errors at the
// operator that made them, never values.
#pragma once

#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>

#include "program/iso/line_error.hpp"
#include "program/iso/parameters.hpp"

namespace softmc::program::iso {

inline constexpr int kMaxExpressionDepth = 64;  // nested brackets and functions
inline constexpr double kEqualTolerance = 0.0001;  // LinuxCNC TOLERANCE_EQUAL for EQ and NE
// Radians in a degree: the angles of sin, cos, tan, asin, acos, atan and of G10 L2 R rotations.
// (Polar coordinates convert as LinuxCNC's D2R does, deg·π/180: polar_radians.)
inline constexpr double kDeg = std::numbers::pi / 180.0;

// A parameter reference: #n or #<name> (name lower case, spaces removed).
struct ParamRef {
  bool named = false;
  long long number = 0;
  std::string name;
};

// Reads from text[i]; on success i is past what was read. Errors carry the column of the offending
// character (1-based).
class ValueReader {
 public:
  ValueReader(std::string_view text, const Parameters& params) : s_(text), params_(params) {}

  std::optional<LineError> value(std::size_t& i, double& out) { return read_value(i, out, 0); }
  // The reference after a '#' at text[i] (i at the '#').
  std::optional<LineError> param_ref(std::size_t& i, ParamRef& out) { return read_ref(i, out, 0); }

 private:
  std::optional<LineError> read_value(std::size_t& i, double& out, int depth);
  std::optional<LineError> read_bracketed(std::size_t& i, double& out, int depth);
  std::optional<LineError> read_binary(std::size_t& i, double& out, int min_prec, int depth);
  std::optional<LineError> read_function(std::size_t& i, double& out, int depth);
  std::optional<LineError> read_ref(std::size_t& i, ParamRef& out, int depth);
  std::optional<LineError> read_number_at(std::size_t& i, double& out);

  std::string_view s_;
  const Parameters& params_;
};

// Reads an RS274 number (sign, digits, one point; spaces inside ignored) from s[i]. `letter` names
// the word in "X word has no number". Shared by the lexer and the value reader.
std::optional<std::string> read_number(std::string_view s, std::size_t& i, char letter, double& out);

// The number as CAM programs write it ("-12.3456" followed by the next word, spaces or the line
// end), read in one pass: what read_number gives for it, with i past the spaces after it. False
// (i untouched) for anything else (spaces inside, more than 15 significant digits, an 'e',
// errors): read_number then reads it.
bool read_plain_number(std::string_view s, std::size_t& i, double& out);

std::uint32_t col_of(std::size_t i);
bool is_space(char c);

}  // namespace softmc::program::iso
