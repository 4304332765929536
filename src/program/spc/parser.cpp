// SPC parser: one line at a time, a cursor with columns; errors abort the line, parsing goes on.
//
// line   := [N<0..999>] instruction [; comment]      (blank and comment-only lines are allowed)
// Words may be separated by blanks or not ("N000G01X10FX0"); letters are case-insensitive.
#include "program/spc/parser.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <string>
#include <vector>

#include "program/spc/address.hpp"

namespace softmc::program::spc {
namespace {

struct LineError {
  std::uint32_t col;
  std::string message;
};

// A jump whose literal line is resolved once every line is known.
struct Fixup {
  std::size_t instruction;
  int line;
  std::uint32_t line_no, col;
};

class LineParser {
 public:
  LineParser(std::string_view s) : s_(s) {}

  std::uint32_t col() const { return static_cast<std::uint32_t>(pos_ + 1); }
  void skip_ws() {
    while (pos_ < s_.size() && (s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\r')) ++pos_;
  }
  bool at_end() {
    skip_ws();
    return pos_ >= s_.size() || s_[pos_] == ';';
  }
  char peek() const { return pos_ < s_.size() ? up(s_[pos_]) : '\0'; }
  char peek_at(std::size_t k) const { return pos_ + k < s_.size() ? up(s_[pos_ + k]) : '\0'; }
  bool digit_next() const { return pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_])); }
  void advance(std::size_t n = 1) { pos_ += n; }
  // Consumes `word` (upper case) if it is next.
  bool accept(std::string_view word) {
    for (std::size_t i = 0; i < word.size(); ++i)
      if (peek_at(i) != word[i]) return false;
    pos_ += word.size();
    return true;
  }
  [[noreturn]] void fail(std::uint32_t c, std::string msg) const { throw LineError{c, std::move(msg)}; }
  [[noreturn]] void fail(std::string msg) const { fail(col(), std::move(msg)); }

  // Unsigned integer in [lo, hi]; `what` names it in messages.
  int uint(int lo, int hi, const char* what) {
    const auto c = col();
    if (!digit_next()) fail(c, fmt::format("expected {}", what));
    long v = 0;
    while (digit_next()) {
      v = v * 10 + (s_[pos_] - '0');
      if (v > 1000000) fail(c, fmt::format("{} is too large", what));
      ++pos_;
    }
    if (v < lo || v > hi) fail(c, fmt::format("{} {} out of range {}..{}", what, v, lo, hi));
    return static_cast<int>(v);
  }
  // Signed integer in [lo, hi].
  int sint(int lo, int hi, const char* what) {
    const auto c = col();
    bool neg = false;
    if (peek() == '-' || peek() == '+') {
      neg = peek() == '-';
      advance();
    }
    if (!digit_next()) fail(c, fmt::format("expected {}", what));
    long v = 0;
    while (digit_next()) {
      v = v * 10 + (s_[pos_] - '0');
      if (v > 10000000) fail(c, fmt::format("{} is too large", what));
      ++pos_;
    }
    if (neg) v = -v;
    if (v < lo || v > hi) fail(c, fmt::format("{} {} out of range {}..{}", what, v, lo, hi));
    return static_cast<int>(v);
  }
  // A position in mm with at most two decimals, returned in 0.01 mm, within ±9999.99.
  std::int32_t position() {
    const auto c = col();
    bool neg = false;
    if (peek() == '-' || peek() == '+') {
      neg = peek() == '-';
      advance();
    }
    std::int64_t v = 0;
    int digits = 0, decimals = -1;
    while (pos_ < s_.size()) {
      const char ch = s_[pos_];
      if (std::isdigit(static_cast<unsigned char>(ch))) {
        if (decimals >= 0) ++decimals;
        if (decimals > 2) fail(c, "a position has at most two decimals");
        v = v * 10 + (ch - '0');
        if (v > 100000000) fail(c, "position out of range -9999.99..9999.99");
        ++digits;
      } else if (ch == '.' && decimals < 0) {
        decimals = 0;
      } else {
        break;
      }
      ++pos_;
    }
    if (digits == 0) fail(c, "expected a position (number or @register)");
    for (int d = decimals < 0 ? 0 : decimals; d < 2; ++d) v *= 10;
    if (neg) v = -v;
    if (v < -kSpcPosMaxCenti || v > kSpcPosMaxCenti) fail(c, "position out of range -9999.99..9999.99");
    return static_cast<std::int32_t>(v);
  }
  // `<v>` of S-2: a number or @n.
  SpcPos pos_operand() {
    if (peek() == '@') {
      advance();
      return SpcPos{true, 0, static_cast<std::uint8_t>(uint(0, kSpcRegisters - 1, "position register"))};
    }
    return SpcPos{false, position(), 0};
  }
  // An SPC axis letter at the cursor (X Y Z U), or -1.
  int axis_letter() const {
    for (std::size_t i = 0; i < kSpcAxes; ++i)
      if (peek() == kSpcAxisLetters[i]) return static_cast<int>(i);
    return -1;
  }
  // `<line>` operand of a conditional jump: blanks, then the line number.
  int line_operand(std::uint32_t& c) {
    skip_ws();
    c = col();
    return uint(0, kMaxLine, "line number");
  }

 private:
  static char up(char c) { return static_cast<char>(std::toupper(static_cast<unsigned char>(c))); }
  std::string_view s_;
  std::size_t pos_ = 0;
};

class Parser {
 public:
  Parser(const std::string& file, const ParseOptions& opt) : file_(file), opt_(opt) {
    prog_.number = opt.number;
    prog_.ir.files.push_back(file);
  }

  void line(std::string_view text, std::uint32_t line_no) {
    LineParser p(text);
    try {
      if (p.at_end()) return;
      const auto ncol = p.col();
      if (!p.accept("N")) p.fail("a line starts with its number N000..N999");
      const int n = p.uint(0, kMaxLine, "line number");
      if (last_line_ >= 0 && n <= last_line_)
        p.fail(ncol, fmt::format("line number N{:03} after N{:03}: line numbers must increase strictly", n, last_line_));
      if (opt_.record_select && n > kRecordMaxLine)
        p.fail(ncol, fmt::format("line N{:03} in a Record Select program: at most N000..N031 (S-9)", n));
      last_line_ = n;
      p.skip_ws();
      const auto icol = p.col();
      if (p.at_end()) p.fail("expected an instruction after the line number");
      Op op = instruction(p, line_no);
      if (!p.at_end()) p.fail("unexpected text after the instruction");
      if (opt_.record_select && !std::holds_alternative<SpcMove>(op) && !std::holds_alternative<SpcAxisSetting>(op) &&
          !std::holds_alternative<SpcDwell>(op))
        p.fail(icol, "a Record Select program holds only motion and motion-specification instructions (S-9)");
      const auto idx = prog_.ir.instructions.size();
      prog_.ir.instructions.push_back(Instruction{SourceLoc{0, line_no, icol}, std::move(op)});
      prog_.lines.push_back(static_cast<std::uint16_t>(n));
      prog_.index_of_line[n] = static_cast<std::int16_t>(idx);
      for (auto& f : pending_) fixups_.push_back({idx, f.line, f.line_no, f.col});
      pending_.clear();
    } catch (const LineError& e) {
      pending_.clear();
      error(line_no, e.col, e.message);
    }
  }

  ParseResult finish() {
    for (const auto& f : fixups_) {
      const int target = prog_.index(f.line);
      if (target < 0) {
        error(f.line_no, f.col, fmt::format("jump to line N{:03}, which this program does not have", f.line));
        continue;
      }
      std::visit(
          [&](auto& op) {
            if constexpr (requires { op.index; }) op.index = target;
          },
          prog_.ir.instructions[f.instruction].op);
    }
    ParseResult r;
    std::stable_sort(diags_.begin(), diags_.end(),
                     [](const auto& a, const auto& b) { return a.line != b.line ? a.line < b.line : a.col < b.col; });
    r.diagnostics = std::move(diags_);
    if (!core::has_errors(r.diagnostics)) r.program = std::move(prog_);
    return r;
  }

 private:
  void error(std::uint32_t line, std::uint32_t col, std::string msg) {
    diags_.push_back(core::Diagnostic{file_, line, col, core::Severity::Error, std::move(msg)});
  }
  void jump_target(int line, std::uint32_t line_no, std::uint32_t col) { pending_.push_back({0, line, line_no, col}); }

  Op instruction(LineParser& p, std::uint32_t line_no) {
    const auto c = p.col();
    if (p.accept("#")) return hash_instruction(p, line_no);
    if (p.accept("G")) {
      const int g = p.uint(0, 99, "G code");
      switch (g) {
        case 0: return move(p, SpcProfile::Rapid);
        case 1: return move(p, SpcProfile::Trapezoid);
        case 2: return move(p, SpcProfile::SineSquared);
        case 4: p.skip_ws(); return SpcDwell{static_cast<std::uint32_t>(p.uint(0, 999999, "dwell (hundredths of a second)"))};
        case 8: return setting(p, SpcSetting::Accel, 0, 99);
        case 9: return setting(p, SpcSetting::Decel, 0, 99);
        case 25: return setting(p, SpcSetting::PassThrough, 0, 99);
        case 61: return setting(p, SpcSetting::MotionComplete, 1, 6);
        case 28: return pos_reg(p, SpcPosRegOp::Load);
        case 29: return pos_reg(p, SpcPosRegOp::Add);
        case 90:
        case 91: p.fail(c, "G90/G91 stand in a motion line (G00/G01/G02)");
        default: p.fail(c, fmt::format("unknown instruction G{:02}", g));
      }
    }
    if (p.accept("M")) {
      const int m = p.uint(0, 99, "M code");
      switch (m) {
        case 0: return SpcSync{};
        case 2: return SpcReturn{};
        case 30: return SpcEnd{};
        case 37: return setting(p, SpcSetting::Mass, 0, 99);
        case 38: return pos_reg(p, SpcPosRegOp::Capture);
        default: p.fail(c, fmt::format("unknown instruction M{:02}", m));
      }
    }
    if (p.accept("E")) {
      const int e = p.uint(0, 99, "E code");
      if (e != 5) p.fail(c, fmt::format("unknown instruction E{:02}", e));
      p.skip_ws();
      SpcJump j;
      if (p.accept("R")) {
        j.via_reg = true;
        j.reg = static_cast<std::uint8_t>(p.uint(0, kSpcRegisters - 1, "register"));
      } else {
        const auto lc = p.col();
        j.line = static_cast<std::uint16_t>(p.uint(0, kMaxLine, "line number"));
        jump_target(j.line, line_no, lc);
      }
      return j;
    }
    if (p.accept("L")) {
      SpcCall call;
      if (p.accept("R")) {
        call.via_reg = true;
        call.reg = static_cast<std::uint8_t>(p.uint(0, kSpcRegisters - 1, "register"));
      } else {
        call.program = static_cast<std::uint8_t>(p.uint(0, kPrograms - 1, "program number"));
      }
      return call;
    }
    p.fail(c, "unknown instruction");
  }

  // G00/G01/G02 [G90|G91] X<v> [FX<d>] ... (S-2).
  SpcMove move(LineParser& p, SpcProfile profile) {
    SpcMove m;
    m.profile = profile;
    const bool with_speed = profile != SpcProfile::Rapid;
    while (!p.at_end()) {
      const auto c = p.col();
      if (p.accept("G")) {
        const int g = p.uint(0, 99, "G code");
        if (g != 90 && g != 91) p.fail(c, "only G90 or G91 may stand in a motion line");
        if (m.coord != SpcCoord::Modal) p.fail(c, "G90/G91 given twice");
        if (m.axes) p.fail(c, "G90/G91 stand before the axes");
        m.coord = g == 90 ? SpcCoord::Absolute : SpcCoord::Relative;
        continue;
      }
      const int a = p.axis_letter();
      if (a < 0) {
        if (p.peek() == 'F' && !with_speed) p.fail(c, "G00 moves at the highest speed: no F word");
        p.fail(c, "expected an axis X, Y, Z or U");
      }
      if (m.axes & (1u << a)) p.fail(c, fmt::format("axis {} given twice", kSpcAxisLetters[a]));
      p.advance();
      m.axes |= static_cast<SpcAxes>(1u << a);
      m.target[a] = p.pos_operand();
      if (with_speed) {
        p.skip_ws();
        const auto fc = p.col();
        if (p.peek() != 'F' || p.peek_at(1) != kSpcAxisLetters[a])
          p.fail(fc, fmt::format("expected F{} <speed %> after the {} target", kSpcAxisLetters[a], kSpcAxisLetters[a]));
        p.advance(2);
        m.speed_pct[a] = static_cast<std::uint8_t>(p.uint(0, 99, "speed %"));
      } else if (p.peek() == 'F') {
        p.fail("G00 moves at the highest speed: no F word");
      }
    }
    if (!m.axes) p.fail("a motion line names one to four axes");
    return m;
  }

  // G08/G09/G25/G61/M37 X<n> ... (S-3).
  SpcAxisSetting setting(LineParser& p, SpcSetting kind, int lo, int hi) {
    SpcAxisSetting s;
    s.kind = kind;
    while (!p.at_end()) {
      const auto c = p.col();
      const int a = p.axis_letter();
      if (a < 0) p.fail(c, "expected an axis X, Y, Z or U");
      if (s.axes & (1u << a)) p.fail(c, fmt::format("axis {} given twice", kSpcAxisLetters[a]));
      p.advance();
      s.axes |= static_cast<SpcAxes>(1u << a);
      s.value[a] = static_cast<std::uint8_t>(p.uint(lo, hi, kind == SpcSetting::MotionComplete ? "G61 condition" : "percentage"));
    }
    if (!s.axes) p.fail("expected at least one axis");
    return s;
  }

  // G28/G29 @i X<v> ..., M38 @i X [Y Z U] (S-5).
  SpcPosReg pos_reg(LineParser& p, SpcPosRegOp op) {
    SpcPosReg r;
    r.op = op;
    p.skip_ws();
    if (!p.accept("@")) p.fail("expected the position register @i");
    r.reg = static_cast<std::uint8_t>(p.uint(0, kSpcRegisters - 1, "position register"));
    while (!p.at_end()) {
      const auto c = p.col();
      const int a = p.axis_letter();
      if (a < 0) p.fail(c, "expected an axis X, Y, Z or U");
      if (r.axes & (1u << a)) p.fail(c, fmt::format("axis {} given twice", kSpcAxisLetters[a]));
      p.advance();
      r.axes |= static_cast<SpcAxes>(1u << a);
      if (op != SpcPosRegOp::Capture) r.value[a] = p.pos_operand();
    }
    if (!r.axes) p.fail("expected at least one axis");
    return r;
  }

  SpcBit io_bit(LineParser& p, SpcBitSpace space) {
    const auto c = p.col();
    SpcBit b;
    b.space = space;
    if (space == SpcBitSpace::Flag) {
      b.bit = static_cast<std::uint8_t>(p.uint(0, kSpcFlags - 1, "flag"));
      return b;
    }
    const int module = p.uint(0, 99, "module");
    if (!p.accept(".")) p.fail("expected '.' between module and bit");
    const int bit = p.uint(0, 99, "bit");
    const bool in = space == SpcBitSpace::Input;
    if (in ? !valid_input(module, bit) : !valid_output(module, bit))
      p.fail(c, fmt::format("{}{}.{} is not an address of the SPC200 I/O (S-6)", in ? 'I' : 'Q', module, bit));
    b.module = static_cast<std::uint8_t>(module);
    b.bit = static_cast<std::uint8_t>(bit);
    return b;
  }

  Op hash_instruction(LineParser& p, std::uint32_t line_no) {
    const auto c = p.col();
    // Integer registers (S-5).
    for (auto [word, op] : {std::pair{"LR", SpcIntRegOp::Load}, {"AR", SpcIntRegOp::Add}, {"TR", SpcIntRegOp::Test}}) {
      if (!p.accept(word)) continue;
      SpcIntReg r;
      r.op = op;
      r.reg = static_cast<std::uint8_t>(p.uint(0, kSpcRegisters - 1, "register"));
      if (!p.accept("=")) p.fail("expected '=' and a value");
      r.value = p.sint(-kSpcIntMax, kSpcIntMax, "value");
      if (op == SpcIntRegOp::Test) {
        std::uint32_t lc;
        r.line = static_cast<std::uint16_t>(p.line_operand(lc));
        jump_target(r.line, line_no, lc);
      }
      return r;
    }
    // Tests (S-6): the longer words first.
    struct TestWord {
      const char* word;
      SpcBitSpace space;
      bool jump_when;
    };
    for (auto t : {TestWord{"TNI", SpcBitSpace::Input, false}, TestWord{"TNQ", SpcBitSpace::Output, false},
                   TestWord{"TNF", SpcBitSpace::Flag, false}, TestWord{"TI", SpcBitSpace::Input, true},
                   TestWord{"TQ", SpcBitSpace::Output, true}, TestWord{"TF", SpcBitSpace::Flag, true}}) {
      if (!p.accept(t.word)) continue;
      SpcBitTest bt;
      bt.bit = io_bit(p, t.space);
      bt.jump_when = t.jump_when;
      std::uint32_t lc;
      bt.line = static_cast<std::uint16_t>(p.line_operand(lc));
      jump_target(bt.line, line_no, lc);
      return bt;
    }
    struct WriteWord {
      const char* word;
      SpcBitSpace space;
      bool value;
    };
    for (auto w : {WriteWord{"SQ", SpcBitSpace::Output, true}, WriteWord{"RQ", SpcBitSpace::Output, false},
                   WriteWord{"SF", SpcBitSpace::Flag, true}, WriteWord{"RF", SpcBitSpace::Flag, false}}) {
      if (!p.accept(w.word)) continue;
      const auto ac = p.col();
      SpcBitWrite bw;
      bw.bit = io_bit(p, w.space);
      bw.value = w.value;
      if (w.space == SpcBitSpace::Output && system_output(bw.bit.module, bw.bit.bit))
        p.fail(ac, fmt::format("Q0.{} is a system output (S-8, S-9): a program must not write it", bw.bit.bit));
      return bw;
    }
    p.fail(c, "unknown instruction");
  }

  std::string file_;
  ParseOptions opt_;
  SpcProgram prog_;
  core::Diagnostics diags_;
  std::vector<Fixup> fixups_, pending_;
  int last_line_ = -1;
};

}  // namespace

ParseResult parse(std::string_view text, const std::string& file_name, const ParseOptions& opt) {
  Parser parser(file_name, opt);
  std::uint32_t line_no = 0;
  std::size_t start = 0;
  while (start <= text.size()) {
    auto end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    ++line_no;
    parser.line(text.substr(start, end - start), line_no);
    start = end + 1;
  }
  return parser.finish();
}

}  // namespace softmc::program::spc
