// Lexer: one line of RS274 text into letter/number words, each with the column of its letter.
#include "program/iso/lexer.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

namespace softmc::program::iso {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_letter(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
char to_upper(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c; }

std::uint32_t col_of(std::size_t i) {
  constexpr std::size_t kMax = std::numeric_limits<std::uint32_t>::max();
  return i >= kMax ? static_cast<std::uint32_t>(kMax) : static_cast<std::uint32_t>(i + 1);
}

void skip_spaces(std::string_view s, std::size_t& i) {
  while (i < s.size() && is_space(s[i])) ++i;
}

// Names a stray character so that binary garbage gives a readable message.
std::string unexpected(char c) {
  if (is_digit(c) || c == '.' || c == '+' || c == '-') return "number without a word letter in front of it";
  switch (c) {
    case '#': return "parameters (#) are not supported yet";
    case '[': return "expressions ([...]) are not supported yet";
    case ')': return "')' without an opening '('";
    case '%': return "'%' must be alone on its line";
    case '/': return "'/' (block delete) must be the first character of the line";
    default: break;
  }
  const auto u = static_cast<unsigned char>(c);
  if (u >= 0x21 && u < 0x7f) return fmt::format("unexpected character '{}'", c);
  return fmt::format("unexpected byte 0x{:02X}", u);
}

// Converts the collected characters; from_chars is locale-independent and exact.
std::optional<std::string> convert(const std::string& text, double& out) {
  double v = 0;
  const auto* first = text.data();
  const auto* last = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(first, last, v, std::chars_format::general);
  if (ec == std::errc::result_out_of_range) return "number out of range";
  if (ec != std::errc() || ptr != last || !std::isfinite(v)) return "malformed number";
  if (std::fabs(v) > kMaxNumberMagnitude) return fmt::format("number out of range (magnitude above {:g})", kMaxNumberMagnitude);
  out = v;
  return std::nullopt;
}

// Reads the number after a word letter from s[i]. RS274 numbers are an optional sign, then digits
// with at most one decimal point; white space inside is ignored, as RS274 ignores it everywhere
// outside comments (so "X 1 0.5" is X10.5). RS274 has no exponent form: "1e3" is refused, and
// reported as out of range when its value would be.
std::optional<std::string> read_number(std::string_view s, std::size_t& i, char letter, double& out) {
  std::string text;  // digits and point, spaces removed: what from_chars reads (it takes no '+')
  bool negative = false, sign = false, point = false;
  std::size_t digits = 0;
  std::size_t after_number = i;  // just past the last digit or point, where an exponent would start
  skip_spaces(s, i);
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) {
    sign = true;
    negative = s[i] == '-';
    ++i;
    skip_spaces(s, i);
  }
  for (; i < s.size(); ++i) {
    const char c = s[i];
    if (is_digit(c)) {
      text += c;
      ++digits;
      after_number = i + 1;
    } else if (c == '.') {
      if (point) return std::string("malformed number: two decimal points");
      point = true;
      text += c;
      after_number = i + 1;
    } else if (!is_space(c)) {
      break;
    }
  }
  if (digits == 0) {
    if (!sign && !point && i < s.size() && (s[i] == '#' || s[i] == '[')) return unexpected(s[i]);
    if (!sign && !point) return fmt::format("{} word has no number", letter);
    return std::string("malformed number: no digits");
  }
  // "1e3" written together is an exponent attempt; "X1 E3" is an X word and an E word.
  if (after_number < s.size() && (s[after_number] == 'e' || s[after_number] == 'E')) {
    std::size_t j = after_number + 1;
    std::string exp = "e";
    if (j < s.size() && (s[j] == '+' || s[j] == '-')) exp += s[j++];
    if (j < s.size() && is_digit(s[j])) {
      while (j < s.size() && is_digit(s[j])) exp += s[j++];
      i = j;
      double ignored = 0;
      if (auto err = convert(text + exp, ignored); err && *err != "malformed number") return err;
      return std::string("malformed number: RS274 has no exponent notation (write the number out in full)");
    }
  }
  double v = 0;
  if (auto err = convert(text, v)) return err;
  out = (negative && v != 0.0) ? -v : v;  // "-0" reads as 0, not as a negative zero in dumps
  return std::nullopt;
}

}  // namespace

LexedLine lex_line(std::string_view s) {
  LexedLine out;
  std::size_t i = 0;
  skip_spaces(s, i);
  if (i < s.size() && s[i] == '%') {
    out.kind = LineKind::Percent;  // text after a tape delimiter is ignored, as on tape readers
    return out;
  }
  if (i < s.size() && s[i] == '/') {
    out.kind = LineKind::BlockDelete;
    return out;
  }
  while (true) {
    skip_spaces(s, i);
    if (i >= s.size()) break;
    const char c = s[i];
    if (c == ';') break;  // comment to end of line
    if (c == '(') {
      const std::size_t open = i;
      for (++i; i < s.size() && s[i] != ')'; ++i) {
        if (s[i] == '(') {
          out.error = LineError{col_of(i), "nested comment: '(' inside a comment"};
          break;
        }
      }
      if (out.error) break;
      if (i >= s.size()) {
        out.error = LineError{col_of(open), "comment has no closing ')'"};
        break;
      }
      ++i;
      continue;
    }
    if (is_letter(c)) {
      Word w;
      w.letter = to_upper(c);
      w.col = col_of(i);
      ++i;
      if (auto err = read_number(s, i, w.letter, w.value)) {
        out.error = LineError{w.col, std::move(*err)};
        break;
      }
      out.words.push_back(w);
      continue;
    }
    out.error = LineError{col_of(i), unexpected(c)};
    break;
  }
  out.kind = (out.words.empty() && !out.error) ? LineKind::Empty : LineKind::Block;
  return out;
}

}  // namespace softmc::program::iso
