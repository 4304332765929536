// Register names and values from outside, checked as a whole, then written in one SQLite transaction.
#include "io/register_access.hpp"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <memory>

namespace softmc::io {

namespace {

using control::spc::RegResult;
using control::spc::Registers;

char upper(char c) { return static_cast<char>(std::toupper(static_cast<unsigned char>(c))); }

int axis_of(char c) {
  for (std::size_t i = 0; i < program::kSpcAxes; ++i)
    if (program::kSpcAxisLetters[i] == upper(c)) return static_cast<int>(i);
  return -1;
}

// Leading decimal digits of `s` as an index; consumes them. -1 when there are none.
int take_index(std::string_view& s) {
  int n = 0;
  std::size_t i = 0;
  while (i < s.size() && i < 4 && std::isdigit(static_cast<unsigned char>(s[i]))) n = n * 10 + (s[i++] - '0');
  if (i == 0) return -1;
  s.remove_prefix(i);
  return n;
}

std::optional<std::int64_t> parse_integer(std::string_view s, std::string& error) {
  std::int64_t v = 0;
  const char* b = s.data();
  if (!s.empty() && s[0] == '+') ++b;
  const auto [p, ec] = std::from_chars(b, s.data() + s.size(), v);
  if (s.empty() || ec != std::errc{} || p != s.data() + s.size()) {
    error = fmt::format("'{}' is not an integer", s);
    return std::nullopt;
  }
  if (v < -program::kSpcIntMax || v > program::kSpcIntMax) {
    error = fmt::format("{} is outside -{}..{} (S-5)", s, program::kSpcIntMax, program::kSpcIntMax);
    return std::nullopt;
  }
  return v;
}

}  // namespace

std::string RegisterRef::name() const {
  switch (kind) {
    case RegisterKind::Position: return fmt::format("@{}{}", index, program::kSpcAxisLetters[static_cast<std::size_t>(axis)]);
    case RegisterKind::Integer: return fmt::format("R{}", index);
    case RegisterKind::Flag: return fmt::format("F{}", index);
  }
  return "?";
}

std::string RegisterValue::text() const {
  if (ref.kind == RegisterKind::Position) {
    const std::int64_t a = value < 0 ? -value : value;
    return fmt::format("{}={}{}.{:02}", ref.name(), value < 0 ? "-" : "", a / 100, a % 100);
  }
  return fmt::format("{}={}", ref.name(), value);
}

std::optional<std::int64_t> parse_position_centi(std::string_view s, std::string& error) {
  std::string_view t = s;
  bool neg = false;
  if (!t.empty() && (t[0] == '+' || t[0] == '-')) {
    neg = t[0] == '-';
    t.remove_prefix(1);
  }
  std::int64_t whole = 0, frac = 0;
  std::size_t i = 0, int_digits = 0, frac_digits = 0;
  for (; i < t.size() && std::isdigit(static_cast<unsigned char>(t[i])); ++i, ++int_digits)
    if (int_digits < 9) whole = whole * 10 + (t[i] - '0');
  if (i < t.size() && t[i] == '.') {
    for (++i; i < t.size() && std::isdigit(static_cast<unsigned char>(t[i])); ++i, ++frac_digits)
      if (frac_digits < 2) frac = frac * 10 + (t[i] - '0');
  }
  if (i != t.size() || int_digits + frac_digits == 0) {
    error = fmt::format("'{}' is not a number", s);
    return std::nullopt;
  }
  if (frac_digits > 2) {
    error = fmt::format("{} has more than two decimals (S-5: positions in 0.01 mm)", s);
    return std::nullopt;
  }
  if (frac_digits == 1) frac *= 10;
  const std::int64_t v = (int_digits > 8 ? std::int64_t{1} << 40 : whole * 100 + frac) * (neg ? -1 : 1);
  if (v < -program::kSpcPosMaxCenti || v > program::kSpcPosMaxCenti) {
    error = fmt::format("{} is outside -9999.99..9999.99 (S-5)", s);
    return std::nullopt;
  }
  return v;
}

RegisterArgs parse_register_args(const std::vector<std::string>& words, bool assignments) {
  RegisterArgs out;
  for (std::size_t w = 0; w < words.size(); ++w) {
    const std::string& word = words[w];
    std::string spelled = word;  // the argument as the user wrote it, for messages
    std::string_view s = word;
    auto fail = [&](const std::string& msg) { out.errors.push_back(fmt::format("'{}': {}", spelled, msg)); };
    if (s.empty()) {
      fail("an empty argument");
      continue;
    }
    RegisterRef ref;
    const char head = upper(s[0]);
    s.remove_prefix(1);
    const int index = take_index(s);
    if (head == '@') {
      ref.kind = RegisterKind::Position;
      if (s.empty() && w + 1 < words.size()) {  // `@3 X=12.5`: the axis is the next word
        s = words[++w];
        spelled += " " + words[w];
      }
      if (s.empty() || axis_of(s[0]) < 0) {
        fail("a position register names its axis: @n X, Y, Z or U (S-5)");
        continue;
      }
      ref.axis = axis_of(s[0]);
      s.remove_prefix(1);
    } else if (head == 'R') {
      ref.kind = RegisterKind::Integer;
    } else if (head == 'F') {
      ref.kind = RegisterKind::Flag;
    } else {
      fail("a register is @n X (position), Rn (integer) or Fn (flag)");
      continue;
    }
    const int max = ref.kind == RegisterKind::Flag ? program::kSpcFlags : program::kSpcRegisters;
    if (index < 0 || index >= max) {
      fail(fmt::format("the register number is 0..{}", max - 1));
      continue;
    }
    ref.index = index;
    if (!assignments) {
      if (!s.empty()) fail("expected a register name only (get)");
      else out.refs.push_back(ref);
      continue;
    }
    if (s.empty() || s[0] != '=') {
      fail("expected NAME=VALUE (set)");
      continue;
    }
    s.remove_prefix(1);
    std::string err;
    std::optional<std::int64_t> v;
    if (ref.kind == RegisterKind::Position) v = parse_position_centi(s, err);
    else if (ref.kind == RegisterKind::Integer) v = parse_integer(s, err);
    else if (s == "0" || s == "1") v = s[0] - '0';
    else err = "a flag is 0 or 1";
    if (!v) {
      fail(err);
      continue;
    }
    bool twice = false;
    for (const auto& x : out.writes) twice = twice || x.ref == ref;
    if (twice) {
      fail(fmt::format("{} is written twice", ref.name()));
      continue;
    }
    out.writes.push_back({ref, *v});
  }
  return out;
}

RegisterAccess::RegisterAccess(const std::string& path) : store_(path) {}

std::vector<RegisterValue> RegisterAccess::get(const std::vector<RegisterRef>& refs, std::vector<std::string>& errors) {
  auto regs = std::make_unique<Registers>();
  store_.restore(*regs);
  std::vector<RegisterValue> out;
  for (const auto& r : refs) {
    switch (r.kind) {
      case RegisterKind::Position: out.push_back({r, regs->position_centi(r.axis, r.index)}); break;
      case RegisterKind::Integer: out.push_back({r, regs->integer(r.index)}); break;
      case RegisterKind::Flag: errors.push_back(fmt::format("'{}': {}", r.name(), kFlagsNotRetentive)); break;
    }
  }
  return out;
}

std::vector<RegisterValue> RegisterAccess::nonzero() {
  auto regs = std::make_unique<Registers>();
  store_.restore(*regs);
  std::vector<RegisterValue> out;
  for (int a = 0; a < static_cast<int>(program::kSpcAxes); ++a)
    for (int i = 0; i < program::kSpcRegisters; ++i)
      if (const auto v = regs->position_centi(a, i)) out.push_back({{RegisterKind::Position, a, i}, v});
  for (int i = 0; i < program::kSpcRegisters; ++i)
    if (const auto v = regs->integer(i)) out.push_back({{RegisterKind::Integer, 0, i}, v});
  return out;
}

std::vector<std::string> RegisterAccess::set(const std::vector<RegisterValue>& writes) {
  // Validate the whole thing on a scratch copy, then act: flush() writes exactly the dirty registers,
  // all in one transaction.
  auto regs = std::make_unique<Registers>();
  std::vector<std::string> errors;
  for (const auto& w : writes) {
    RegResult r = RegResult::Ok;
    switch (w.ref.kind) {
      case RegisterKind::Position: r = regs->set_position_centi(w.ref.axis, w.ref.index, w.value); break;
      case RegisterKind::Integer: r = regs->set_integer(w.ref.index, w.value); break;
      case RegisterKind::Flag: errors.push_back(fmt::format("'{}': {}", w.text(), kFlagsNotRetentive)); continue;
    }
    if (r != RegResult::Ok) errors.push_back(fmt::format("'{}': {}", w.text(), control::spc::to_string(r)));
  }
  if (!errors.empty()) return errors;
  store_.flush(*regs);
  return errors;
}

}  // namespace softmc::io
