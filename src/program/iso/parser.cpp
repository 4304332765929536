// ISO/RS274 program: files → lines → (O-word flow | lexer → block check → interpreter) → Program.
//
//   file ──lines──► index_flow (O-word structure, once per file)
//     run: pc ─► O-word line? ── jump (if/while/do/repeat/call/return …, conditions evaluated now)
//                   │ no
//                   ▼
//              lex_line(params) ─► check_block ─► execute(ModalState) ─► ops ─► [cutter comp] ─► Program
//                   │ error            │ error          │ error
//                   └──────────────────┴────────────────┴──► Diagnostic, next line
//
// The interpreter runs entirely here, before anything moves: loops are unrolled and subroutines
// expanded into canonical instructions. Recovery is per line: a block with an error changes no
// state and emits nothing, and reading goes on with the next line, so one pass reports every
// independent error. Loops, recursion and the total work are bounded by ParseOptions.
//
// The O-word flow, calls and M98/M99 subprograms are in program_flow.cpp; the reader's class in
// program_reader.hpp.
#include "program/iso/parser.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <unordered_set>

#include <fmt/format.h>

#include "program/iso/block.hpp"
#include "program/iso/cutter_comp.hpp"
#include "program/iso/fast_block.hpp"
#include "program/iso/flow_index.hpp"
#include "program/iso/interpreter.hpp"
#include "program/iso/lexer.hpp"
#include "program/iso/modal_state.hpp"
#include "program/iso/predefined_params.hpp"
#include "program/iso/program_reader.hpp"

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

}  // namespace

namespace detail {

// The whole file in one read (a million-line program is read in milliseconds, not by the character).
std::optional<std::string> read_text(const std::string& path, std::string& text) {
  std::error_code ec;
  const bool regular = std::filesystem::is_regular_file(path, ec) && !ec;  // a directory opens but does not read
  std::FILE* f = regular ? std::fopen(path.c_str(), "rb") : nullptr;
  if (!f) return std::string("cannot read file");
  const auto size = std::filesystem::file_size(path, ec);
  text.clear();
  if (!ec) text.resize(static_cast<std::size_t>(size));
  std::size_t n = text.empty() ? 0 : std::fread(text.data(), 1, text.size(), f);
  text.resize(n);
  // A file that grew while it was read (or whose size the system does not know): read the rest.
  char chunk[1 << 16];
  while (!std::ferror(f) && !std::feof(f)) {
    const std::size_t k = std::fread(chunk, 1, sizeof chunk, f);
    text.append(chunk, k);
    if (k == 0) break;
  }
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) return std::string("cannot read file");
  return std::nullopt;
}

ProgramReader::ProgramReader(const std::string& file, const ParseOptions& opt) : opt_(opt) {
  program_.files = {file};
  program_.start = opt.start;
  state_.position = opt.start;
  interp_.tools = opt.tools;
  interp_.mtable = opt.m_table;
  interp_.g23_tolerance_mm = opt.g23_tolerance_mm;
  frames_.emplace_back();
  const auto dir = std::filesystem::path(file).parent_path();
  main_dir_ = dir.empty() ? std::string(".") : dir.string();
}

ParseResult ProgramReader::run(std::string text) {
  for (const double v : program_.start.v)
    if (!std::isfinite(v)) add_error(0, 0, 0, "start position is not finite");
  add_file(program_.files[0], std::move(text));
  // Most lines of a CAM program make one instruction: room for them all up front, so that a
  // million-line program is not copied while its IR grows.
  program_.instructions.reserve(opt_.sink ? opt_.sink_batch + 64
                                          : std::min(total_lines_ + total_lines_ / 8 + 16, instruction_limit()));
  std::size_t f = 0, pc = 0;
  while (!done_) {
    const SourceFile& sf = *files_[f];
    if (pc >= sf.lines.size()) {
      if (frames_.size() > 1) {  // fell off a subroutine file (already reported: no endsub)
        return_from_sub(f, pc);
        continue;
      }
      break;
    }
    if (++blocks_ > block_limit()) {
      add_error(f, pc, 1, fmt::format("the program runs more than {} blocks (endless loop?): stopping here", block_limit()));
      done_ = true;
      break;
    }
    if (opt_.sink && program_.instructions.size() >= opt_.sink_batch) flush_to_sink();
    if (instructions_made() > instruction_limit()) {
      add_error(f, pc, 1, fmt::format("the program makes more than {} instructions (endless loop?): stopping here",
                                      instruction_limit()));
      done_ = true;
      break;
    }
    if (const OEntry* e = sf.flow.at(pc)) {
      o_line(*e, f, pc);
    } else {
      read_line(f, pc);
      ++pc;
      if (jump_) {  // an M98 call
        f = jump_->first;
        pc = jump_->second;
        jump_.reset();
      }
    }
  }
  finish();
  if (opt_.sink) flush_to_sink();
  ParseResult r;
  std::stable_sort(diags_.begin(), diags_.end(), [&](const core::Diagnostic& a, const core::Diagnostic& b) {
    const auto fa = file_rank(a.file), fb = file_rank(b.file);
    if (fa != fb) return fa < fb;
    if (a.line != b.line) return a.line < b.line;
    return a.col < b.col;
  });
  if (note_) diags_.push_back(*note_);
  r.diagnostics = std::move(diags_);
  if (!core::has_errors(r.diagnostics)) r.program = std::move(program_);
  return r;
}

std::size_t ProgramReader::file_rank(const std::string& name) const {
  for (std::size_t i = 0; i < program_.files.size(); ++i)
    if (program_.files[i] == name) return i;
  return program_.files.size();
}

// Streaming: the instructions so far to the sink; the list keeps its capacity for the next batch.
void ProgramReader::flush_to_sink() {
  if (program_.instructions.empty()) return;
  opt_.sink(program_);
  sunk_ += program_.instructions.size();
  program_.instructions.clear();
}

std::size_t ProgramReader::add_file(const std::string& path, std::string text) {
  auto sf = std::make_unique<SourceFile>();
  sf->path = path;
  sf->text = std::move(text);
  std::string_view t = sf->text;
  std::size_t newlines = 0;
  for (const char c : t) newlines += c == '\n';  // a loop the compiler vectorises (std::count is not)
  sf->lines.reserve(newlines + 1);
  std::size_t pos = 0;
  while (pos <= t.size()) {
    const std::size_t nl = t.find('\n', pos);
    const std::size_t end = nl == std::string_view::npos ? t.size() : nl;
    sf->lines.push_back(t.substr(pos, end - pos));
    if (nl == std::string_view::npos) break;
    pos = nl + 1;
  }
  total_lines_ += sf->lines.size();
  std::vector<IndexError> errs;
  sf->flow = index_flow(sf->lines, errs);
  files_.push_back(std::move(sf));
  const std::size_t f = files_.size() - 1;
  for (auto& e : errs) add_error(f, e.line, e.error.col, std::move(e.error.message));
  return f;
}

// ---- plain blocks ----

void ProgramReader::read_line(std::size_t f, std::size_t pc) {
  const std::string_view line = files_[f]->lines[pc];
  if (opt_.fast_path && fast_straight_block(line, state_, fast_)) {
    seen_block_ = true;
    position_params_stale_ = true;
    if (fast_.op) put(Instruction{core::SourceLoc{static_cast<std::uint16_t>(f), line_no(pc), fast_.col}, std::move(*fast_.op)});
    return;
  }
  lex(line, pc);
  if (lexed_.kind == LineKind::Percent) {
    // A '%' before any block opens the program; a later one closes it (the rest is not read) if
    // one opened it, and is an error if none did (rs274: "Bad character '%' used"); after M2/M30 it
    // is the tape's end as usual.
    if (f == 0 && frames_.size() > 1)  // rs274: "Bad character '%' used"
      return fail(f, pc, line, LineError{1, "'%' inside a subroutine or subprogram: '%' lines only open and close "
                                            "the program"});
    if (f == 0 && frames_.size() == 1) {
      if (seen_block_ && !percent_open_ && !state_.ended)
        return fail(f, pc, line, LineError{1, "'%' closes the program, but it did not open with a '%' line"});
      if (seen_block_ || percent_open_) done_ = true;
      percent_open_ = true;
    }
    return;
  }
  if (lexed_.kind == LineKind::Empty || lexed_.kind == LineKind::BlockDelete) return;
  if (state_.ended) {
    // RS274 stops reading at M2/M30; say so once, so that text left behind is not a silent surprise.
    const std::uint32_t col = lexed_.error ? lexed_.error->col : lexed_.words.empty() ? 1 : lexed_.words.front().col;
    add_diag(f, pc, col, core::Severity::Warning, "text after the program end (M2/M30) is ignored");
    done_ = true;
    return;
  }
  seen_block_ = true;
  if (lexed_.error) return fail(f, pc, line, std::move(*lexed_.error));
  // Parameters set on a line take effect after the whole line has been read (LinuxCNC).
  for (const auto& a : lexed_.assignments) {
    if (a.named) {
      if (auto err = params_.write_named(a.name, a.value)) add_error(f, pc, a.col, std::move(*err));
    } else if (auto err = params_.write(a.number, a.value)) {
      add_error(f, pc, a.col, std::move(*err));
    }
  }
  if (aborts(f, pc)) return;
  for (const Word& w : lexed_.words) {  // M98 and M70…M73 stand alone on their lines: they act on the reader
    if (w.letter != 'M') continue;
    if (w.value == 98) return call_m98(f, pc, w);
    if (w.value == 70 || w.value == 71 || w.value == 72 || w.value == 73) return modal_state_m(f, pc, w);
  }
  if (lexed_.words.empty()) {
    emit_messages(f, pc, lexed_.assignments.empty() ? 1 : lexed_.assignments.front().col);
    return;
  }
  if (auto e = check_block(lexed_.words, mtable(), block_)) return fail(f, pc, line, std::move(*e));
  out_.clear();
  // Canned cycles check their repeats and pecks against what is left of the instruction budget.
  const std::size_t made = instructions_made();
  interp_.max_ops = made < instruction_limit() ? instruction_limit() - made : 0;
  const core::Vec before = state_.position;
  const bool nurbs_before = state_.motion == Motion::Nurbs;
  if (auto e = execute(block_, state_, params_, interp_, out_)) {
    // A G5.3 that failed (a missing feed, a bad curve) leaves its block open, so that a later G5.3
    // may still close it; the program's end inside it would only echo that failure, as the end of
    // the file would echo an M2/M30 refused inside the block.
    bool ends = false;
    for (std::size_t k = 0; k < block_.m_count; ++k) ends = ends || block_.m[k].number == 2 || block_.m[k].number == 30;
    if ((block_.nurbs_end || ends) && state_.motion == Motion::Nurbs) state_.nurbs_uncertain = true;
    return fail(f, pc, line, std::move(*e));
  }
  emit_messages(f, pc, block_.col);
  deliver(core::SourceLoc{static_cast<std::uint16_t>(f), line_no(pc), block_.col}, before);
  if (!nurbs_before && state_.motion == Motion::Nurbs && block_.motion)  // where a block left open is reported
    nurbs_open_ = core::SourceLoc{static_cast<std::uint16_t>(f), line_no(pc), block_.motion->col};
  position_params_stale_ = true;
  if (state_.ended && frames_.size() > 1) done_ = true;  // M2/M30 in a subroutine ends everything
}

// (ABORT, text), LinuxCNC 2.9: the program stops there with the text (parameters substituted as
// for DEBUG) as its error. A block's comment acts before the rest of the block.
bool ProgramReader::aborts(std::size_t f, std::size_t pc) {
  if (!lexed_.abort) return false;
  std::string text = format_message(*lexed_.abort, params_);
  const auto first = text.find_first_not_of(" \t");
  text.erase(0, first == std::string::npos ? text.size() : first);
  add_error(f, pc, lexed_.abort_col, fmt::format("the program aborts here (ABORT): {}", text));
  done_ = true;
  return true;
}

// DEBUG and PRINT show the parameters as they are when the block runs: after the line's own
// assignments (LinuxCNC: "#1=5 (DEBUG, #1)" prints 5.000000). #5599 = 0 silences DEBUG.
void ProgramReader::emit_messages(std::size_t f, std::size_t pc, std::uint32_t col) {
  for (auto& m : lexed_.messages) {
    if (m.kind == MessageKind::Debug && params_.get(kDebugOutput) == 0.0) continue;
    std::string text = m.kind == MessageKind::Msg ? std::move(m.text) : format_message(m.text, params_);
    put(Instruction{core::SourceLoc{static_cast<std::uint16_t>(f), line_no(pc), col}, Message{m.kind, std::move(text)}});
  }
}

// The block's parameter writes, then its ops to the program, through cutter compensation while it is on.
void ProgramReader::deliver(const core::SourceLoc& loc, const core::Vec& before) {
  for (const auto& [n, v] : out_.param_writes) params_.set(n, v);
  if (out_.m66) params_.set_runtime_only(kM66Result);
  for (std::size_t i = 0; i <= out_.ops.size(); ++i) {
    if (out_.comp && out_.comp->at == i) switch_comp(loc, before);
    if (i < out_.ops.size()) put(Instruction{loc, std::move(out_.ops[i])});
  }
}

// G40 leaves the position the programmed point, as LinuxCNC's current position after it: #5420…
// and a G91 move count from there, while the next move starts where the tool is (its end is all the
// IR gives).
void ProgramReader::switch_comp(const core::SourceLoc& loc, const core::Vec& before) {
  const auto& c = *out_.comp;
  if (c.on) {
    if (auto msg = comp_.start(c.side, c.radius_mm, c.axis0, c.axis1, before)) add_error_loc(loc, std::move(*msg));
    return;
  }
  comp_out_.clear();
  comp_.stop(comp_out_);
  for (auto& ins : comp_out_) program_.instructions.push_back(std::move(ins));
}

void ProgramReader::put(Instruction ins) {
  if (!comp_.active()) {
    program_.instructions.push_back(std::move(ins));
    return;
  }
  comp_out_.clear();
  if (auto e = comp_.push(ins, comp_out_)) add_error_loc(e->loc, std::move(e->message));
  for (auto& i : comp_out_) program_.instructions.push_back(std::move(i));
}

// Lexes a line with the parameters up to date. Only a line with a '#' can read a parameter, so
// the position parameters (#5420…) are brought up to date only then, not after every block, and
// the predefined named ones (#<_x>, …) only before a line that also has a '<'.
void ProgramReader::lex(std::string_view line, std::size_t pc) {
  if (std::memchr(line.data(), '#', line.size())) {
    if (position_params_stale_) {
      update_position_parameters();
      position_params_stale_ = false;
      named_params_stale_ = true;
    }
    if (may_read_predefined(line)) {
      if (named_params_stale_) set_predefined_parameters(params_, state_, tool_position());
      named_params_stale_ = false;
      params_.set_predefined(Predefined::Line, static_cast<double>(line_no(pc)));
    }
  }
  lex_line(line, params_, lexed_);
}

void ProgramReader::update_position_parameters() {
  const core::Vec p = in_program_units(to_program(state_, tool_position()), state_.units);
  for (std::size_t a = 0; a < core::kMaxAxes; ++a) params_.set(kCurrentPosition + static_cast<int>(a), p[a]);
  // #5400…#5410 describe the loaded tool as its table entry has it, whatever G43/G49 is in effect
  // (LinuxCNC set_tool_parameters: tool_table[0], the spindle; zeros with no tool loaded).
  params_.set(kToolNumber, state_.current_tool);
  const Tool* t = opt_.tools && state_.current_tool > 0 ? opt_.tools->find(state_.current_tool) : nullptr;
  for (std::size_t a = 0; a < core::kMaxAxes; ++a) params_.set(kToolOffset + static_cast<int>(a), t ? t->offset[a] : 0.0);
  params_.set(kToolDiameter, t ? t->diameter_mm : 0.0);
}

void ProgramReader::fail(std::size_t f, std::size_t pc, std::string_view line, LineError e) {
  if (mentions_letter(line, 'F')) state_.feed_uncertain = true;
  if (mentions_letter(line, 'G')) state_.motion_uncertain = true;
  add_error(f, pc, e.col, std::move(e.message));
}

void ProgramReader::finish() {
  if (state_.motion == Motion::Nurbs && !state_.ended && !done_ && !state_.nurbs_uncertain)
    add_error_loc(nurbs_open_, "the program ends inside this G5.2 block: close it with G5.3");
  if (comp_.active()) {
    comp_out_.clear();
    comp_.stop(comp_out_);
    for (auto& ins : comp_out_) program_.instructions.push_back(std::move(ins));
  }
}

// ---- diagnostics ----

void ProgramReader::add_error(std::size_t f, std::size_t pc, std::uint32_t col, std::string message) {
  add_error_at(files_.empty() ? program_.files[0] : files_[f]->path, f == 0 && files_.empty() ? 0 : line_no(pc), col,
               std::move(message));
}

void ProgramReader::add_error_loc(const core::SourceLoc& loc, std::string message) {
  add_error_at(files_[loc.file]->path, loc.line, loc.col, std::move(message));
}

void ProgramReader::add_error_at(const std::string& file, std::uint32_t line, std::uint32_t col, std::string message) {
  if (!seen_.insert(fmt::format("{}:{}:{}:{}", file, line, col, message)).second) return;  // a loop repeats it
  if (errors_ == kMaxErrors) {
    note_ = make_diag(file, line, col, core::Severity::Note, fmt::format("too many errors ({}); stopping here", kMaxErrors));
    done_ = true;
    return;
  }
  ++errors_;
  diags_.push_back(make_diag(file, line, col, core::Severity::Error, std::move(message)));
}

void ProgramReader::add_diag(std::size_t f, std::size_t pc, std::uint32_t col, core::Severity sev,
                             std::string message) {
  diags_.push_back(make_diag(files_[f]->path, line_no(pc), col, sev, std::move(message)));
}

const MTable& ProgramReader::mtable() const {
  static const MTable kFixed;
  return opt_.m_table ? *opt_.m_table : kFixed;
}

}  // namespace detail

ParseResult parse(std::string_view text, const std::string& file_name, const ParseOptions& opt) {
  return detail::ProgramReader(file_name, opt).run(std::string(text));
}

ParseResult parse_file(const std::string& path, const ParseOptions& opt) {
  std::string text;
  if (auto err = detail::read_text(path, text)) {
    ParseResult r;
    r.diagnostics.push_back(make_diag(path, 0, 0, core::Severity::Error, *err));
    return r;
  }
  return detail::ProgramReader(path, opt).run(std::move(text));
}

}  // namespace softmc::program::iso
