// ISO/RS274 program: lines → lexer → block check → interpreter → Program, with every error kept.
//
//   text ──split at '\n'──► lex_line ──words──► check_block ──Block──► execute(ModalState) ──► Ops
//                              │ error              │ error                 │ error
//                              └────────────────────┴───────────────────────┴──► Diagnostic, next line
//
// Recovery is per line: a block with an error changes no state and emits nothing, and reading goes
// on with the next line, so one pass reports every independent error.
#include "program/iso/parser.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <fmt/format.h>

#include "program/iso/block.hpp"
#include "program/iso/interpreter.hpp"
#include "program/iso/lexer.hpp"
#include "program/iso/modal_state.hpp"

namespace softmc::program::iso {
namespace {

// Enough to fix a file in one go; beyond it, a binary or wrong file only floods the terminal.
constexpr std::size_t kMaxErrors = 100;

core::Diagnostic make_diag(const std::string& file, std::uint32_t line, std::uint32_t col, core::Severity sev,
                           std::string message) {
  core::Diagnostic d;
  d.file = file;
  d.line = line;
  d.col = col;
  d.severity = sev;
  d.message = std::move(message);
  return d;
}

// Whether a (failed) line holds a word letter `c` outside comments: a rough test, enough to know
// that the failed block may have meant to set the feed (F) or the motion mode (G).
bool mentions_letter(std::string_view line, char c) {
  const char lower = static_cast<char>(c - 'A' + 'a');
  bool in_comment = false;
  for (char x : line) {
    if (in_comment) {
      in_comment = x != ')';
    } else if (x == '(') {
      in_comment = true;
    } else if (x == ';') {
      return false;
    } else if (x == c || x == lower) {
      return true;
    }
  }
  return false;
}

class ProgramReader {
 public:
  ProgramReader(const std::string& file, const ParseOptions& opt) : file_(file) {
    program_.files = {file};
    program_.start = opt.start;
    state_.position = opt.start;
  }

  ParseResult run(std::string_view text) {
    for (const double v : program_.start.v)
      if (!std::isfinite(v)) add_error(0, 0, "start position is not finite");
    std::uint32_t line_no = 0;
    std::size_t pos = 0;
    while (pos <= text.size() && !done_) {
      const std::size_t nl = text.find('\n', pos);
      const std::size_t end = nl == std::string_view::npos ? text.size() : nl;
      ++line_no;
      read_line(text.substr(pos, end - pos), line_no);
      if (nl == std::string_view::npos) break;
      pos = nl + 1;
    }
    ParseResult r;
    r.diagnostics = std::move(diags_);
    if (!core::has_errors(r.diagnostics)) r.program = std::move(program_);
    return r;
  }

 private:
  void read_line(std::string_view line, std::uint32_t line_no) {
    LexedLine lexed = lex_line(line);
    if (lexed.kind == LineKind::Percent) {
      // A '%' before any block opens the program; any later one closes it: the rest is not read.
      if (seen_block_ || percent_open_) done_ = true;
      percent_open_ = true;
      return;
    }
    if (lexed.kind == LineKind::Empty || lexed.kind == LineKind::BlockDelete) return;
    if (state_.ended) {
      // RS274 stops reading at M2/M30; say so once, so that text left behind is not a silent surprise.
      const std::uint32_t col = lexed.error ? lexed.error->col : lexed.words.front().col;
      add_diag(line_no, col, core::Severity::Warning, "text after the program end (M2/M30) is ignored");
      done_ = true;
      return;
    }
    seen_block_ = true;
    if (lexed.error) return fail(line, line_no, std::move(*lexed.error));
    Block block;
    if (auto e = check_block(lexed.words, block)) return fail(line, line_no, std::move(*e));
    ops_.clear();
    if (auto e = execute(block, state_, ops_)) return fail(line, line_no, std::move(*e));
    const core::SourceLoc loc{0, line_no, block.col};
    for (auto& op : ops_) program_.instructions.push_back(Instruction{loc, std::move(op)});
  }

  void fail(std::string_view line, std::uint32_t line_no, LineError e) {
    if (mentions_letter(line, 'F')) state_.feed_uncertain = true;
    if (mentions_letter(line, 'G')) state_.motion_uncertain = true;
    add_error(line_no, e.col, std::move(e.message));
  }

  void add_error(std::uint32_t line_no, std::uint32_t col, std::string message) {
    if (errors_ == kMaxErrors) {
      add_diag(line_no, col, core::Severity::Note, fmt::format("too many errors ({}); stopping here", kMaxErrors));
      done_ = true;
      return;
    }
    ++errors_;
    add_diag(line_no, col, core::Severity::Error, std::move(message));
  }

  void add_diag(std::uint32_t line_no, std::uint32_t col, core::Severity sev, std::string message) {
    diags_.push_back(make_diag(file_, line_no, col, sev, std::move(message)));
  }

  const std::string& file_;
  Program program_;
  ModalState state_;
  core::Diagnostics diags_;
  std::vector<Op> ops_;
  std::size_t errors_ = 0;
  bool seen_block_ = false;
  bool percent_open_ = false;
  bool done_ = false;
};

}  // namespace

ParseResult parse(std::string_view text, const std::string& file_name, const ParseOptions& opt) {
  return ProgramReader(file_name, opt).run(text);
}

ParseResult parse_file(const std::string& path, const ParseOptions& opt) {
  std::error_code ec;
  std::string text;
  bool ok = std::filesystem::is_regular_file(path, ec) && !ec;  // a directory opens but does not read
  if (ok) {
    std::ifstream in(path, std::ios::binary);
    ok = static_cast<bool>(in);
    if (ok) text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  if (!ok) {
    ParseResult r;
    r.diagnostics.push_back(make_diag(path, 0, 0, core::Severity::Error, "cannot read file"));
    return r;
  }
  return parse(text, path, opt);
}

}  // namespace softmc::program::iso
