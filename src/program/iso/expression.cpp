// Values in RS274/NGC words: numbers, #parameters, [expressions] and functions, as LinuxCNC reads them.
#include "program/iso/expression.hpp"

#include <charconv>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "program/iso/lexer.hpp"

namespace softmc::program::iso {
namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_alpha(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

void skip(std::string_view s, std::size_t& i) {
  while (i < s.size() && is_space(s[i])) ++i;
}

// Up to 8 letters, lower case, for function and operator names.
std::string_view alpha_run(std::string_view s, std::size_t i, char (&buf)[8]) {
  std::size_t n = 0;
  while (i + n < s.size() && n < sizeof buf && is_alpha(s[i + n])) {
    buf[n] = lower(s[i + n]);
    ++n;
  }
  return {buf, n};
}

enum class Op : std::uint8_t { None, Pow, Mul, Div, Mod, Add, Sub, Eq, Ne, Gt, Ge, Lt, Le, And, Or, Xor };

int precedence(Op op) {
  switch (op) {
    case Op::Pow: return 6;
    case Op::Mul: case Op::Div: case Op::Mod: return 5;
    case Op::Add: case Op::Sub: return 4;
    case Op::Eq: case Op::Ne: case Op::Gt: case Op::Ge: case Op::Lt: case Op::Le: return 3;
    case Op::And: case Op::Or: case Op::Xor: return 2;
    case Op::None: break;
  }
  return 0;
}

// The binary operator at s[i] and its length, or None.
Op peek_op(std::string_view s, std::size_t i, std::size_t& len) {
  if (i >= s.size()) return Op::None;
  len = 1;
  switch (s[i]) {
    case '*':
      if (i + 1 < s.size() && s[i + 1] == '*') {
        len = 2;
        return Op::Pow;
      }
      return Op::Mul;
    case '/': return Op::Div;
    case '+': return Op::Add;
    case '-': return Op::Sub;
    default: break;
  }
  char buf[8];
  const auto w = alpha_run(s, i, buf);
  len = w.size();
  if (w.starts_with("mod")) { len = 3; return Op::Mod; }
  if (w.starts_with("and")) { len = 3; return Op::And; }
  if (w.starts_with("xor")) { len = 3; return Op::Xor; }
  if (w.starts_with("or")) { len = 2; return Op::Or; }
  len = 2;
  if (w.starts_with("eq")) return Op::Eq;
  if (w.starts_with("ne")) return Op::Ne;
  if (w.starts_with("gt")) return Op::Gt;
  if (w.starts_with("ge")) return Op::Ge;
  if (w.starts_with("lt")) return Op::Lt;
  if (w.starts_with("le")) return Op::Le;
  return Op::None;
}

std::optional<std::string> apply(Op op, double a, double b, double& out) {
  switch (op) {
    case Op::Pow:
      if (a < 0 && b != std::floor(b)) return "negative number raised to a non-integer power";
      if (a == 0 && b < 0) return "zero raised to a negative power";
      out = std::pow(a, b);
      break;
    case Op::Mul: out = a * b; break;
    case Op::Div:
      if (b == 0) return "division by zero";
      out = a / b;
      break;
    case Op::Mod:
      if (b == 0) return "modulo by zero";
      out = std::fmod(a, b);
      if (out < 0) out += std::fabs(b);  // LinuxCNC: the result takes the sign of neither: 0 <= r < |b|
      break;
    case Op::Add: out = a + b; break;
    case Op::Sub: out = a - b; break;
    case Op::Eq: out = std::fabs(a - b) < kEqualTolerance ? 1 : 0; break;
    case Op::Ne: out = std::fabs(a - b) >= kEqualTolerance ? 1 : 0; break;
    case Op::Gt: out = a > b ? 1 : 0; break;
    case Op::Ge: out = a >= b ? 1 : 0; break;
    case Op::Lt: out = a < b ? 1 : 0; break;
    case Op::Le: out = a <= b ? 1 : 0; break;
    case Op::And: out = (a != 0 && b != 0) ? 1 : 0; break;
    case Op::Or: out = (a != 0 || b != 0) ? 1 : 0; break;
    case Op::Xor: out = ((a != 0) != (b != 0)) ? 1 : 0; break;
    case Op::None: return "missing operator";
  }
  if (!std::isfinite(out)) return "expression result is not a finite number";
  return std::nullopt;
}

}  // namespace

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::uint32_t col_of(std::size_t i) {
  constexpr std::size_t kMax = std::numeric_limits<std::uint32_t>::max();
  return i >= kMax ? static_cast<std::uint32_t>(kMax) : static_cast<std::uint32_t>(i + 1);
}

std::optional<LineError> ValueReader::read_number_at(std::size_t& i, double& out) {
  const std::size_t at = i;
  if (auto e = read_number(s_, i, '?', out)) return LineError{col_of(at), std::move(*e)};
  return std::nullopt;
}

std::optional<LineError> ValueReader::read_value(std::size_t& i, double& out, int depth) {
  if (depth > kMaxExpressionDepth)
    return LineError{col_of(i), fmt::format("expression nested too deeply (more than {} levels)", kMaxExpressionDepth)};
  skip(s_, i);
  if (i >= s_.size()) return LineError{col_of(i), "value missing at the end of the line"};
  const char c = s_[i];
  if (c == '[') return read_bracketed(i, out, depth + 1);
  if (c == '#') {
    const std::size_t at = i;
    ParamRef ref;
    if (auto e = read_ref(i, ref, depth + 1)) return e;
    const auto err = ref.named ? params_.read_named(ref.name, out) : params_.read(ref.number, out);
    if (err) return LineError{col_of(at), *err};
    return std::nullopt;
  }
  if (c == '+' || c == '-') {
    std::size_t j = i + 1;
    skip(s_, j);
    if (j < s_.size() && !is_digit(s_[j]) && s_[j] != '.') {
      i = j;
      if (auto e = read_value(i, out, depth + 1)) return e;
      if (c == '-' && out != 0.0) out = -out;
      return std::nullopt;
    }
  }
  if (is_alpha(c)) return read_function(i, out, depth + 1);
  return read_number_at(i, out);
}

std::optional<LineError> ValueReader::read_bracketed(std::size_t& i, double& out, int depth) {
  const std::size_t open = i;
  ++i;  // '['
  if (auto e = read_binary(i, out, 1, depth)) return e;
  skip(s_, i);
  if (i >= s_.size()) return LineError{col_of(open), "'[' has no closing ']'"};
  if (s_[i] != ']') {
    std::size_t len = 0;
    if (peek_op(s_, i, len) == Op::None) return LineError{col_of(i), fmt::format("unknown operator '{}' in expression", s_[i])};
    return LineError{col_of(i), "expected ']'"};
  }
  ++i;
  return std::nullopt;
}

std::optional<LineError> ValueReader::read_binary(std::size_t& i, double& out, int min_prec, int depth) {
  if (depth > kMaxExpressionDepth)
    return LineError{col_of(i), fmt::format("expression nested too deeply (more than {} levels)", kMaxExpressionDepth)};
  if (auto e = read_value(i, out, depth)) return e;
  while (true) {
    skip(s_, i);
    std::size_t len = 0;
    const Op op = peek_op(s_, i, len);
    if (op == Op::None || precedence(op) < min_prec) return std::nullopt;
    const std::size_t at = i;
    i += len;
    double rhs = 0;
    if (auto e = read_binary(i, rhs, precedence(op) + 1, depth + 1)) return e;
    if (auto err = apply(op, out, rhs, out)) return LineError{col_of(at), std::move(*err)};
  }
}

std::optional<LineError> ValueReader::read_function(std::size_t& i, double& out, int depth) {
  const std::size_t at = i;
  char buf[8];
  const auto name = alpha_run(s_, i, buf);
  i += name.size();
  std::size_t j = i;
  skip(s_, j);
  const bool bracket = j < s_.size() && s_[j] == '[';
  static constexpr std::string_view kNames[] = {"abs", "acos", "asin", "atan", "cos", "exp", "fix", "fup",
                                                "round", "ln", "sin", "sqrt", "tan", "exists"};
  bool known = false;
  for (auto n : kNames) known = known || n == name;
  if (!known || !bracket) {
    if (known) return LineError{col_of(at), fmt::format("function {} needs its argument in [ ]", name)};
    return LineError{col_of(at), fmt::format("unknown function or word '{}' in a value", name)};
  }
  i = j;
  if (name == "exists") {
    ++i;
    skip(s_, i);
    if (i >= s_.size() || s_[i] != '#') return LineError{col_of(i), "EXISTS needs a named parameter: EXISTS[#<name>]"};
    ParamRef ref;
    if (auto e = read_ref(i, ref, depth)) return e;
    if (!ref.named) return LineError{col_of(at), "EXISTS needs a named parameter: EXISTS[#<name>]"};
    skip(s_, i);
    if (i >= s_.size() || s_[i] != ']') return LineError{col_of(i), "expected ']'"};
    ++i;
    out = params_.exists(ref.name) ? 1 : 0;
    return std::nullopt;
  }
  double a = 0;
  if (auto e = read_bracketed(i, a, depth)) return e;
  std::optional<std::string> err;
  if (name == "atan") {
    skip(s_, i);
    if (i >= s_.size() || s_[i] != '/') return LineError{col_of(at), "ATAN needs two arguments: ATAN[y]/[x]"};
    ++i;
    skip(s_, i);
    if (i >= s_.size() || s_[i] != '[') return LineError{col_of(at), "ATAN needs two arguments: ATAN[y]/[x]"};
    double b = 0;
    if (auto e = read_bracketed(i, b, depth)) return e;
    out = std::atan2(a, b) / kDeg;
  } else if (name == "abs") out = std::fabs(a);
  else if (name == "acos" || name == "asin") {
    if (a < -1 || a > 1) err = fmt::format("{} argument {:g} outside -1 … 1", name == "acos" ? "ACOS" : "ASIN", a);
    else out = (name == "acos" ? std::acos(a) : std::asin(a)) / kDeg;
  } else if (name == "cos") out = std::cos(a * kDeg);
  else if (name == "sin") out = std::sin(a * kDeg);
  else if (name == "tan") out = std::tan(a * kDeg);
  else if (name == "exp") out = std::exp(a);
  else if (name == "fix") out = std::floor(a);
  else if (name == "fup") out = std::ceil(a);
  else if (name == "round") out = std::round(a);  // halves away from zero, as LinuxCNC
  else if (name == "ln") {
    if (a <= 0) err = fmt::format("LN of {:g}: the argument must be greater than zero", a);
    else out = std::log(a);
  } else if (name == "sqrt") {
    if (a < 0) err = fmt::format("SQRT of the negative number {:g}", a);
    else out = std::sqrt(a);
  }
  if (!err && !std::isfinite(out)) err = "expression result is not a finite number";
  if (err) return LineError{col_of(at), std::move(*err)};
  return std::nullopt;
}

std::optional<LineError> ValueReader::read_ref(std::size_t& i, ParamRef& out, int depth) {
  const std::size_t at = i;
  ++i;  // '#'
  skip(s_, i);
  if (i < s_.size() && s_[i] == '<') {
    out.named = true;
    out.name.clear();
    for (++i; i < s_.size() && s_[i] != '>'; ++i) {
      const auto u = static_cast<unsigned char>(s_[i]);
      if (is_space(s_[i])) continue;
      if (u < 0x21 || u >= 0x7f || s_[i] == '<' || s_[i] == '#')
        return LineError{col_of(i), "bad character in a parameter name"};
      out.name += lower(s_[i]);
    }
    if (i >= s_.size()) return LineError{col_of(at), "parameter name has no closing '>'"};
    ++i;
    if (out.name.empty()) return LineError{col_of(at), "empty parameter name #<>"};
    return std::nullopt;
  }
  double v = 0;
  if (auto e = read_value(i, v, depth + 1)) return e;
  const double r = std::round(v);
  if (std::fabs(v - r) > kEqualTolerance) return LineError{col_of(at), fmt::format("parameter number {:g} is not a whole number", v)};
  out.named = false;
  out.number = static_cast<long long>(r);  // |v| <= finite; range is checked on access
  if (std::fabs(r) > 1e9) out.number = -1;
  return std::nullopt;
}

// Reads the number after a word letter from s[i]. RS274 numbers are an optional sign, then digits
// with at most one decimal point; white space inside is ignored, as RS274 ignores it everywhere
// outside comments (so "X 1 0.5" is X10.5). RS274 has no exponent form: "1e3" is refused, and
// reported as out of range when its value would be.
namespace {

constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                             1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

}  // namespace

// Up to 15 significant digits make an integer below 2^53, and dividing it by an exact power of
// ten rounds correctly, as from_chars does.
bool read_plain_number(std::string_view s, std::size_t& i, double& out) {
  const char* p = s.data() + i;
  const char* const end = s.data() + s.size();
  bool negative = false;
  if (p < end && (*p == '+' || *p == '-')) negative = *p++ == '-';
  const auto digit = [](char c) { return static_cast<unsigned>(c - '0') < 10u; };
  const char* const digits_start = p;
  while (p < end && *p == '0') ++p;  // leading zeros: not significant
  std::uint64_t mantissa = 0;  // wraps only when there are too many digits: then refused below
  const char* const int_start = p;
  while (p < end && digit(*p)) mantissa = mantissa * 10 + static_cast<std::uint64_t>(*p++ - '0');
  std::ptrdiff_t significant = p - int_start;
  bool any = p > digits_start;
  std::ptrdiff_t fraction = 0;
  if (p < end && *p == '.') {
    const char* const frac_start = ++p;
    while (p < end && digit(*p)) {
      mantissa = mantissa * 10 + static_cast<std::uint64_t>(*p++ - '0');
      if (mantissa != 0) ++significant;  // zeros right after the point are not significant
    }
    fraction = p - frac_start;
    any = any || fraction > 0;
  }
  if (!any || significant > 15 || fraction > 22) return false;
  const char* q = p;
  while (q < end && is_space(*q)) ++q;
  if (q < end && (digit(*q) || *q == '.')) return false;  // "1 0.5": the number goes on
  if (p < end && (*p == 'e' || *p == 'E' || *p == '.')) return false;
  const double v = static_cast<double>(mantissa) / kPow10[fraction];
  if (v > kMaxNumberMagnitude) return false;
  out = (negative && v != 0.0) ? -v : v;  // "-0" reads as 0
  i = static_cast<std::size_t>(q - s.data());
  return true;
}

std::optional<std::string> read_number(std::string_view s, std::size_t& i, char letter, double& out) {
  if (read_plain_number(s, i, out)) return std::nullopt;
  char text[64];  // digits kept: leading zeros are dropped and digits beyond 40 significant ones add nothing
  std::size_t n = 0, int_digits_dropped = 0;
  bool negative = false, sign = false, point = false, significant = false;
  std::size_t digits = 0;
  // The usual number ("12.3456") is read exactly on the way: up to 15 significant digits make an
  // integer below 2^53, and dividing it by an exact power of ten rounds correctly, as from_chars does.
  std::uint64_t mantissa = 0;
  int mantissa_digits = 0, fraction_digits = 0;
  std::size_t after_number = i;
  skip(s, i);
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) {
    sign = true;
    negative = s[i] == '-';
    ++i;
    skip(s, i);
  }
  for (; i < s.size(); ++i) {
    const char c = s[i];
    if (is_digit(c)) {
      ++digits;
      after_number = i + 1;
      if (point) ++fraction_digits;
      if (mantissa != 0 || c != '0') ++mantissa_digits;
      if (mantissa_digits <= 15) mantissa = mantissa * 10 + static_cast<std::uint64_t>(c - '0');
      if (!significant && c == '0' && !point) continue;  // leading zeros
      significant = true;
      if (n < 48) text[n++] = c;
      else if (!point) ++int_digits_dropped;
    } else if (c == '.') {
      if (point) return std::string("malformed number: two decimal points");
      point = true;
      if (n < 48) text[n++] = '.';
      after_number = i + 1;
    } else if (!is_space(c)) {
      break;
    }
  }
  if (digits == 0) {
    if (!sign && !point) return fmt::format("{} word has no number", letter);
    return std::string("malformed number: no digits");
  }
  // "1e3" written together is an exponent attempt; "X1 E3" is an X word and an E word.
  if (after_number < s.size() && (s[after_number] == 'e' || s[after_number] == 'E')) {
    std::size_t j = after_number + 1;
    bool exp_negative = false;
    if (j < s.size() && (s[j] == '+' || s[j] == '-')) exp_negative = s[j++] == '-';
    if (j < s.size() && is_digit(s[j])) {
      long long e = 0;
      while (j < s.size() && is_digit(s[j])) {
        e = std::min<long long>(e * 10 + (s[j] - '0'), 100000);
        ++j;
      }
      i = j;
      if (!exp_negative && e > 300) return std::string("number out of range");
      return std::string("malformed number: RS274 has no exponent notation (write the number out in full)");
    }
  }
  if (int_digits_dropped > 0 || n == 0 || (n == 1 && text[0] == '.')) {
    if (int_digits_dropped > 0) return std::string("number out of range");
    out = 0;  // "0", "000", "0.": all zeros
    return std::nullopt;
  }
  double v = 0;
  if (mantissa_digits <= 15 && fraction_digits <= 22) {
    v = static_cast<double>(mantissa) / kPow10[fraction_digits];
  } else {
    const auto [ptr, ec] = std::from_chars(text, text + n, v, std::chars_format::fixed);
    if (ec == std::errc::result_out_of_range) return std::string("number out of range");
    if (ec != std::errc() || !std::isfinite(v)) return std::string("malformed number");
    (void)ptr;
  }
  if (std::fabs(v) > kMaxNumberMagnitude)
    return fmt::format("number out of range (magnitude above {:g})", kMaxNumberMagnitude);
  out = (negative && v != 0.0) ? -v : v;  // "-0" reads as 0, not as a negative zero in dumps
  return std::nullopt;
}

}  // namespace softmc::program::iso
