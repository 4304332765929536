// Lexer: one line of RS274/NGC text into words (values evaluated), parameter assignments, an O-word
// and operator messages, each with the column it came from.
#include "program/iso/lexer.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "program/iso/expression.hpp"

namespace softmc::program::iso {
namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_letter(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
char to_upper(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c; }
char to_lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

void skip_spaces(std::string_view s, std::size_t& i) {
  while (i < s.size() && is_space(s[i])) ++i;
}

// Names a stray character so that binary garbage gives a readable message.
std::string unexpected(char c) {
  if (is_digit(c) || c == '.' || c == '+' || c == '-') return "number without a word letter in front of it";
  switch (c) {
    case ']': return "']' without an opening '['";
    case '[': return "expression without a word letter in front of it";
    case ')': return "')' without an opening '('";
    case '%': return "'%' must be alone on its line";
    case '/': return "'/' (block delete) must be the first character of the line";
    case '=': return "'=' without a parameter in front of it";
    default: break;
  }
  const auto u = static_cast<unsigned char>(c);
  if (u >= 0x21 && u < 0x7f) return fmt::format("unexpected character '{}'", c);
  return fmt::format("unexpected byte 0x{:02X}", u);
}

// A word's value: a literal number (errors at the letter, as the foundation reported them) or a
// parameter, expression or function (errors where they arise).
std::optional<LineError> word_value(std::string_view s, std::size_t& i, char letter, std::uint32_t col,
                                    const Parameters& params, double& out) {
  std::size_t j = i;
  skip_spaces(s, j);
  bool computed = j < s.size() && (s[j] == '[' || s[j] == '#');
  if (j < s.size() && (s[j] == '+' || s[j] == '-')) {
    std::size_t k = j + 1;
    skip_spaces(s, k);
    computed = k < s.size() && (s[k] == '[' || s[k] == '#' || is_letter(s[k]));
  }
  if (j < s.size() && is_letter(s[j])) {  // a function only when its '[' follows: "X Y2" is a missing number
    std::size_t k = j;
    while (k < s.size() && is_letter(s[k])) ++k;
    skip_spaces(s, k);
    computed = k < s.size() && s[k] == '[';
  }
  if (computed) {
    ValueReader r(s, params);
    return r.value(i, out);
  }
  if (auto err = read_number(s, i, letter, out)) return LineError{col, std::move(*err)};
  return std::nullopt;
}

OKeyword keyword_of(std::string_view w, bool& ok) {
  ok = true;
  static constexpr std::pair<std::string_view, OKeyword> kWords[] = {
      {"sub", OKeyword::Sub},       {"endsub", OKeyword::EndSub},     {"call", OKeyword::Call},
      {"return", OKeyword::Return}, {"if", OKeyword::If},             {"elseif", OKeyword::ElseIf},
      {"else", OKeyword::Else},     {"endif", OKeyword::EndIf},       {"while", OKeyword::While},
      {"endwhile", OKeyword::EndWhile}, {"do", OKeyword::Do},         {"repeat", OKeyword::Repeat},
      {"endrepeat", OKeyword::EndRepeat}, {"break", OKeyword::Break}, {"continue", OKeyword::Continue}};
  for (const auto& [name, k] : kWords)
    if (name == w) return k;
  ok = false;
  return OKeyword::Sub;
}

// A bare O-word at s[i] (the 'O'): "O0001" or "o<name>" with nothing after it but spaces and
// comments. LinuxCNC 2.9 reads it as a (Fanuc-style) program number and does nothing with it in the
// program; CAM posts put one on the first line. Returns the index after it, or npos.
std::size_t bare_o_word(std::string_view s, std::size_t i) {
  ++i;
  skip_spaces(s, i);
  if (i < s.size() && s[i] == '<') {
    const std::size_t close = s.find('>', i);
    if (close == std::string_view::npos) return std::string_view::npos;
    i = close + 1;
  } else {
    const std::size_t digits = i;
    while (i < s.size() && (is_digit(s[i]) || is_space(s[i]))) ++i;
    if (i == digits) return std::string_view::npos;
  }
  std::size_t j = i;
  skip_spaces(s, j);
  return (j >= s.size() || s[j] == '(' || s[j] == ';') ? i : std::string_view::npos;
}

// O-word header at s[i] (the 'O'): name and keyword. Leaves i after the keyword.
std::optional<LineError> o_header(std::string_view s, std::size_t& i, OWord& o) {
  o.col = col_of(i);
  o.name.clear();
  o.args.clear();
  ++i;
  skip_spaces(s, i);
  if (i < s.size() && s[i] == '<') {
    o.name += '<';
    for (++i; i < s.size() && s[i] != '>'; ++i)
      if (!is_space(s[i])) o.name += to_lower(s[i]);
    if (i >= s.size()) return LineError{o.col, "O-word name has no closing '>'"};
    ++i;
    o.name += '>';
    if (o.name == "<>") return LineError{o.col, "empty O-word name"};
  } else {
    bool any = false;
    while (i < s.size() && (is_digit(s[i]) || is_space(s[i]))) {
      if (is_digit(s[i])) {
        any = true;
        if (!(o.name.empty() && s[i] == '0')) o.name += s[i];  // O0100 is O100
      }
      ++i;
    }
    if (o.name.empty() && any) o.name.push_back('0');
    if (o.name.empty()) return LineError{o.col, "O word needs a number or a <name>"};
  }
  skip_spaces(s, i);
  std::string kw;
  while (i < s.size() && is_letter(s[i]) && kw.size() < 12) kw += to_lower(s[i++]);
  if (kw.empty()) return LineError{o.col, "O word without a keyword (sub, call, if, while, …)"};
  bool ok = false;
  o.keyword = keyword_of(kw, ok);
  if (!ok) return LineError{o.col, fmt::format("unknown O-word keyword '{}'", kw)};
  return std::nullopt;
}

// Comment text at s[open+1 .. close): an active comment becomes a message. As LinuxCNC's
// convert_comment: spaces may come before the keyword, but the comma follows it directly ("(MSG ,
// x)" is a plain comment). DEBUG and PRINT texts keep their #n and #<name> as written: they are
// substituted when the block runs, after the line's assignments (format_message). A block has one
// comment in LinuxCNC, the last ( ) one of its line: an earlier one is not acted on.
void comment(std::string_view body, std::uint32_t col, LexedLine& out) {
  out.messages.clear();
  out.abort.reset();
  std::size_t i = 0;
  skip_spaces(body, i);
  std::string head;
  std::size_t j = i;
  while (j < body.size() && is_letter(body[j]) && head.size() < 8) head += to_lower(body[j++]);
  if (j >= body.size() || body[j] != ',') return;
  MessageKind kind;
  if (head == "msg") kind = MessageKind::Msg;
  else if (head == "debug") kind = MessageKind::Debug;
  else if (head == "print") kind = MessageKind::Print;
  else if (head == "abort") {
    out.abort = std::string(body.substr(j + 1));
    out.abort_col = col;
    return;
  } else return;
  out.messages.push_back(LineMessage{kind, std::string(body.substr(j + 1))});
}

}  // namespace

const char* to_string(OKeyword k) {
  switch (k) {
    case OKeyword::Sub: return "sub";
    case OKeyword::EndSub: return "endsub";
    case OKeyword::Call: return "call";
    case OKeyword::Return: return "return";
    case OKeyword::If: return "if";
    case OKeyword::ElseIf: return "elseif";
    case OKeyword::Else: return "else";
    case OKeyword::EndIf: return "endif";
    case OKeyword::While: return "while";
    case OKeyword::EndWhile: return "endwhile";
    case OKeyword::Do: return "do";
    case OKeyword::Repeat: return "repeat";
    case OKeyword::EndRepeat: return "endrepeat";
    case OKeyword::Break: return "break";
    case OKeyword::Continue: return "continue";
    case OKeyword::Program: return "(subprogram)";
    case OKeyword::ProgramEnd: return "M99";
  }
  return "?";
}

void lex_line(std::string_view s, const Parameters& params, LexedLine& out) {
  out.kind = LineKind::Empty;
  out.words.clear();
  out.assignments.clear();
  out.o.reset();
  out.messages.clear();
  out.abort.reset();
  out.error.reset();
  std::size_t i = 0;
  skip_spaces(s, i);
  if (i < s.size() && s[i] == '%') {
    out.kind = LineKind::Percent;  // text after a tape delimiter is ignored, as on tape readers
    return;
  }
  if (i < s.size() && s[i] == '/') {
    out.kind = LineKind::BlockDelete;
    return;
  }
  auto fail = [&](LineError e) { out.error = std::move(e); };
  while (!out.error) {
    skip_spaces(s, i);
    if (i >= s.size()) break;
    const char c = s[i];
    if (c == ';') break;  // comment to end of line
    if (c == '(') {
      const std::size_t open = i;
      for (++i; i < s.size() && s[i] != ')'; ++i) {
        if (s[i] == '(') {
          fail(LineError{col_of(i), "nested comment: '(' inside a comment"});
          break;
        }
      }
      if (out.error) break;
      if (i >= s.size()) {
        fail(LineError{col_of(open), "comment has no closing ')'"});
        break;
      }
      comment(s.substr(open + 1, i - open - 1), col_of(open), out);
      ++i;
      continue;
    }
    if (c == '#') {  // #ref = value
      const std::size_t at = i;
      ValueReader r(s, params);
      Assignment a;
      ParamRef ref;
      if (auto e = r.param_ref(i, ref)) {
        fail(std::move(*e));
        break;
      }
      skip_spaces(s, i);
      if (i >= s.size() || s[i] != '=') {
        fail(LineError{col_of(at), "parameter without '=': a parameter is set with #n = value"});
        break;
      }
      ++i;
      if (auto e = r.value(i, a.value)) {
        fail(std::move(*e));
        break;
      }
      a.named = ref.named;
      a.number = ref.number;
      a.name = std::move(ref.name);
      a.col = col_of(at);
      out.assignments.push_back(std::move(a));
      continue;
    }
    if (c == 'o' || c == 'O') {
      const bool only_n = out.words.empty() || (out.words.size() == 1 && out.words[0].letter == 'N');
      if (!only_n || !out.assignments.empty()) {
        fail(LineError{col_of(i), "O word must be the first word of its line (after an optional N)"});
        break;
      }
      if (const std::size_t after = bare_o_word(s, i); after != std::string_view::npos) {
        i = after;  // a program number: nothing to do
        continue;
      }
      OWord o;
      if (auto e = o_header(s, i, o)) {
        fail(std::move(*e));
        break;
      }
      // Arguments: any number of [expr] for call, at most one value for the others.
      while (true) {
        skip_spaces(s, i);
        if (i >= s.size() || s[i] == ';') break;
        if (s[i] == '(') {
          const std::size_t close = s.find(')', i);
          if (close == std::string_view::npos) {
            fail(LineError{col_of(i), "comment has no closing ')'"});
            break;
          }
          comment(s.substr(i + 1, close - i - 1), col_of(i), out);
          i = close + 1;
          continue;
        }
        if (s[i] != '[') {
          fail(LineError{col_of(i), fmt::format("unexpected text after O-word '{}': arguments go in [ ]", to_string(o.keyword))});
          break;
        }
        if (o.args.size() >= kLocalParameters) {
          fail(LineError{col_of(i), fmt::format("more than {} arguments", kLocalParameters)});
          break;
        }
        ValueReader r(s, params);
        double v = 0;
        if (auto e = r.value(i, v)) {
          fail(std::move(*e));
          break;
        }
        o.args.push_back(v);
      }
      if (out.error) break;
      out.o = std::move(o);
      break;
    }
    // '@' and '^' are LinuxCNC's polar coordinate words (radius, angle in degrees): words like letters.
    if (is_letter(c) || c == '@' || c == '^') {
      Word w;
      w.letter = to_upper(c);
      w.col = col_of(i);
      ++i;
      if (auto e = word_value(s, i, w.letter, w.col, params, w.value)) {
        fail(std::move(*e));
        break;
      }
      out.words.push_back(w);
      continue;
    }
    fail(LineError{col_of(i), unexpected(c)});
  }
  const bool has_content = !out.words.empty() || !out.assignments.empty() || out.o || !out.messages.empty() || out.abort;
  out.kind = (has_content || out.error) ? LineKind::Block : LineKind::Empty;
}

std::string format_message(std::string_view text, const Parameters& params) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t k = 0; k < text.size();) {
    if (text[k] != '#' || k + 1 >= text.size()) {
      out += text[k++];
      continue;
    }
    double v = 0;
    bool found = false;
    std::size_t end = k + 1;
    if (is_digit(text[end])) {
      long long n = 0;
      for (; end < text.size() && is_digit(text[end]); ++end) n = n < 1000000000 ? n * 10 + (text[end] - '0') : n;
      found = !params.read(n, v);
    } else if (text[end] == '<') {
      const std::size_t close = text.find('>', end);
      if (close == std::string_view::npos) {
        out += text[k++];
        continue;
      }
      std::string name;
      for (std::size_t c = end + 1; c < close; ++c)
        if (!is_space(text[c])) name += to_lower(text[c]);
      end = close + 1;
      found = !name.empty() && !params.read_named(name, v);
    } else {
      out += text[k++];
      continue;
    }
    if (std::fabs(v) < 0.0001) v = 0.0;  // LinuxCNC prints a value under 0.0001 as 0.000000 (not -0.000000)
    out += found ? fmt::format("{:.6f}", v) : std::string("######");
    k = end;
  }
  return out;
}

LexedLine lex_line(std::string_view line) {
  static const Parameters kZero;
  LexedLine out;
  lex_line(line, kZero, out);
  return out;
}

namespace {
// Where a line's O word starts (after spaces and an optional N word), or npos.
std::size_t o_word_at(std::string_view s) {
  std::size_t i = 0;
  skip_spaces(s, i);
  if (i < s.size() && (s[i] == 'n' || s[i] == 'N')) {
    ++i;
    while (i < s.size() && (is_digit(s[i]) || is_space(s[i]) || s[i] == '.')) ++i;
  }
  return i < s.size() && (s[i] == 'o' || s[i] == 'O') ? i : std::string_view::npos;
}
}  // namespace

std::optional<OWord> scan_o_word(std::string_view s) {
  std::size_t i = o_word_at(s);
  if (i == std::string_view::npos) return std::nullopt;
  OWord o;
  if (o_header(s, i, o)) return std::nullopt;  // the error is reported when the line runs
  return o;
}

std::optional<ProgramNumber> scan_program_number(std::string_view s) {
  const std::size_t at = o_word_at(s);
  if (at == std::string_view::npos || bare_o_word(s, at) == std::string_view::npos) return std::nullopt;
  ProgramNumber p;
  p.col = col_of(at);
  bool any = false;
  for (std::size_t k = at + 1; k < s.size() && (is_digit(s[k]) || is_space(s[k])); ++k) {
    if (!is_digit(s[k])) continue;
    any = true;
    if (!(p.name.empty() && s[k] == '0')) p.name += s[k];  // O0100 is O100, as o_header names it
  }
  if (!any) return std::nullopt;  // o<name>: not a program number
  if (p.name.empty()) p.name = "0";
  return p;
}

std::uint32_t scan_m99(std::string_view s) {
  if (s.find_first_of("Mm") == std::string_view::npos) return 0;  // most lines of a program: at once
  std::size_t first = 0;
  skip_spaces(s, first);
  if (first < s.size() && s[first] == '/') return 0;  // a block-delete line never ends a subprogram
  for (std::size_t i = first; i < s.size(); ++i) {
    const char c = s[i];
    if (c == ';') return 0;
    if (c == '(') {
      const std::size_t close = s.find(')', i);
      if (close == std::string_view::npos) return 0;
      i = close;
      continue;
    }
    if (c == '<') {  // #<name>
      const std::size_t close = s.find('>', i);
      if (close == std::string_view::npos) return 0;
      i = close;
      continue;
    }
    if (c != 'm' && c != 'M') continue;
    if (i > 0 && is_letter(s[i - 1])) continue;  // a function name such as "mod" or "sum"
    std::size_t k = i + 1;
    skip_spaces(s, k);
    long long v = 0;
    std::size_t digits = 0;
    while (k < s.size() && (is_digit(s[k]) || is_space(s[k]))) {
      if (is_digit(s[k])) {
        v = std::min(v * 10 + (s[k] - '0'), 1000LL);
        ++digits;
      }
      ++k;
    }
    if (digits > 0 && v == 99 && (k >= s.size() || s[k] != '.')) return col_of(i);
  }
  return 0;
}

}  // namespace softmc::program::iso
