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

struct SourceFile {
  std::string path;
  std::string text;
  std::vector<std::string_view> lines;
  FlowIndex flow;
};

struct LoopCount {
  std::size_t file = 0, line = 0;
  std::size_t count = 0;
  long long repeat_left = 0;
};

struct CallFrame {
  std::size_t file = 0, return_line = 0;
  std::vector<LoopCount> loops;
  // An M98 call of a Fanuc-style subprogram: its named locals are its own, #1…#30 the caller's
  // (LinuxCNC); its O line, and the passes left including the present one (M98 L).
  bool m98 = false;
  std::size_t program_line = 0;
  long long passes_left = 0;
};

class ProgramReader {
 public:
  ProgramReader(const std::string& file, const ParseOptions& opt) : opt_(opt) {
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

  ParseResult run(std::string text) {
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

 private:
  std::size_t file_rank(const std::string& name) const {
    for (std::size_t i = 0; i < program_.files.size(); ++i)
      if (program_.files[i] == name) return i;
    return program_.files.size();
  }

  // The work limits (ParseOptions): one pass over every line read, plus what loops and calls add.
  std::size_t block_limit() const { return total_lines_ + opt_.max_blocks; }
  std::size_t instruction_limit() const { return 2 * total_lines_ + opt_.max_instructions; }
  std::size_t instructions_made() const { return sunk_ + program_.instructions.size(); }

  // Streaming: the instructions so far to the sink; the list keeps its capacity for the next batch.
  void flush_to_sink() {
    if (program_.instructions.empty()) return;
    opt_.sink(program_);
    sunk_ += program_.instructions.size();
    program_.instructions.clear();
  }

  std::size_t add_file(const std::string& path, std::string text) {
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

  void read_line(std::size_t f, std::size_t pc) {
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
    for (const Word& w : lexed_.words)
      if (w.letter == 'M' && w.value == 98) return call_m98(f, pc, w);
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
    for (const auto& [n, v] : out_.param_writes) params_.set(n, v);
    if (out_.m66) params_.set_runtime_only(kM66Result);
    deliver(core::SourceLoc{static_cast<std::uint16_t>(f), line_no(pc), block_.col}, before);
    if (!nurbs_before && state_.motion == Motion::Nurbs && block_.motion)  // where a block left open is reported
      nurbs_open_ = core::SourceLoc{static_cast<std::uint16_t>(f), line_no(pc), block_.motion->col};
    position_params_stale_ = true;
    if (state_.ended && frames_.size() > 1) done_ = true;  // M2/M30 in a subroutine ends everything
  }

  // (ABORT, text), LinuxCNC 2.9: the program stops there with the text (parameters substituted as
  // for DEBUG) as its error. A block's comment acts before the rest of the block.
  bool aborts(std::size_t f, std::size_t pc) {
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
  void emit_messages(std::size_t f, std::size_t pc, std::uint32_t col) {
    for (auto& m : lexed_.messages) {
      if (m.kind == MessageKind::Debug && params_.get(kDebugOutput) == 0.0) continue;
      std::string text = m.kind == MessageKind::Msg ? std::move(m.text) : format_message(m.text, params_);
      put(Instruction{core::SourceLoc{static_cast<std::uint16_t>(f), line_no(pc), col}, Message{m.kind, std::move(text)}});
    }
  }

  // The block's ops to the program, through cutter compensation while it is on.
  void deliver(const core::SourceLoc& loc, const core::Vec& before) {
    for (std::size_t i = 0; i <= out_.ops.size(); ++i) {
      if (out_.comp && out_.comp->at == i) switch_comp(loc, before, i == out_.ops.size());
      if (i < out_.ops.size()) put(Instruction{loc, std::move(out_.ops[i])});
    }
  }

  void switch_comp(const core::SourceLoc& loc, const core::Vec& before, bool last) {
    const auto& c = *out_.comp;
    if (c.on) {
      if (auto msg = comp_.start(c.side, c.radius_mm, c.axis0, c.axis1, before)) add_error_loc(loc, std::move(*msg));
      return;
    }
    comp_out_.clear();
    comp_.stop(comp_out_);
    for (auto& ins : comp_out_) program_.instructions.push_back(std::move(ins));
    if (last) state_.position = comp_.tool_position();  // the next move starts where the tool is
  }

  void put(Instruction ins) {
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
  void lex(std::string_view line, std::size_t pc) {
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

  // Where the tool is: under cutter compensation the compensated end of the last move (the
  // programmed end moved by the tool radius along its normal there), as LinuxCNC's #5420… give it.
  const core::Vec& tool_position() const { return comp_.active() ? comp_.tool_position() : state_.position; }

  void update_position_parameters() {
    const core::Vec p = in_program_units(to_program(state_, tool_position()), state_.units);
    for (std::size_t a = 0; a < core::kMaxAxes; ++a) params_.set(kCurrentPosition + static_cast<int>(a), p[a]);
    // #5400…#5410 describe the loaded tool as its table entry has it, whatever G43/G49 is in effect
    // (LinuxCNC set_tool_parameters: tool_table[0], the spindle; zeros with no tool loaded).
    params_.set(kToolNumber, state_.current_tool);
    const Tool* t = opt_.tools && state_.current_tool > 0 ? opt_.tools->find(state_.current_tool) : nullptr;
    for (std::size_t a = 0; a < core::kMaxAxes; ++a) params_.set(kToolOffset + static_cast<int>(a), t ? t->offset[a] : 0.0);
    params_.set(kToolDiameter, t ? t->diameter_mm : 0.0);
  }

  void fail(std::size_t f, std::size_t pc, std::string_view line, LineError e) {
    if (mentions_letter(line, 'F')) state_.feed_uncertain = true;
    if (mentions_letter(line, 'G')) state_.motion_uncertain = true;
    add_error(f, pc, e.col, std::move(e.message));
  }

  // ---- O-words ----

  // Evaluates the O-word line (its [values]); false (reported) when it has an error.
  bool eval_o(std::size_t f, std::size_t pc, OWord& out) {
    lex(files_[f]->lines[pc], pc);
    if (lexed_.error) {
      add_error(f, pc, lexed_.error->col, std::move(lexed_.error->message));
      return false;
    }
    if (!lexed_.o) return false;
    if (aborts(f, pc)) return false;
    emit_messages(f, pc, lexed_.o->col);
    out = std::move(*lexed_.o);
    return true;
  }

  bool condition(std::size_t f, std::size_t pc, bool& value) {
    OWord o;
    if (!eval_o(f, pc, o)) return false;
    if (o.args.size() != 1) {
      add_error(f, pc, o.col, fmt::format("o{} {} needs one condition in [ ]", o.name, to_string(o.keyword)));
      return false;
    }
    value = o.args[0] != 0.0;
    return true;
  }

  LoopCount* loop(std::size_t f, std::size_t line) {
    for (auto& l : frames_.back().loops)
      if (l.file == f && l.line == line) return &l;
    return nullptr;
  }
  void drop_loop(std::size_t f, std::size_t line) {
    auto& v = frames_.back().loops;
    v.erase(std::remove_if(v.begin(), v.end(), [&](const LoopCount& l) { return l.file == f && l.line == line; }), v.end());
  }
  // Counts one more pass of the loop opened at `line`; false (reported, program stopped) past the limit.
  bool count_pass(std::size_t f, std::size_t line, const OEntry& e) {
    LoopCount* l = loop(f, line);
    if (!l) {
      frames_.back().loops.push_back(LoopCount{f, line, 0, 0});
      l = &frames_.back().loops.back();
    }
    if (++l->count > opt_.max_loop_iterations) {
      add_error(f, line, e.o.col, fmt::format("loop o{} ran more than {} times: endless loop? (stopping here)", e.o.name,
                                              opt_.max_loop_iterations));
      done_ = true;
      return false;
    }
    return true;
  }

  void o_line(const OEntry& e, std::size_t& f, std::size_t& pc) {
    if (state_.ended) {
      // Subroutines and subprograms may follow M2 (they are never run there).
      if ((e.o.keyword == OKeyword::Sub || e.o.keyword == OKeyword::Program) && e.valid) {
        pc = e.end + 1;
        return;
      }
      add_diag(f, pc, e.o.col, core::Severity::Warning, "text after the program end (M2/M30) is ignored");
      done_ = true;
      return;
    }
    const bool back = back_edge_;
    back_edge_ = false;
    if (!e.valid && e.o.keyword != OKeyword::Call) {  // structure error, already reported
      ++pc;
      return;
    }
    seen_block_ = true;
    switch (e.o.keyword) {
      case OKeyword::Sub: pc = e.end + 1; return;  // a definition: skipped until called
      case OKeyword::Program:
        // Met by the main program before its end: LinuxCNC runs these lines as main-program text (an
        // O0001 … M99 main program, a subprogram put before M30); skipping them would move
        // differently without a word.
        add_error(f, pc, e.o.col, fmt::format("subprogram O{} (lines {}–{}) stands before the program's end: softmc "
                                              "would skip it and LinuxCNC would run it here; put subprograms after "
                                              "M2/M30 (and end a main program with M2/M30, not M99)",
                                              e.o.name, pc + 1, e.end + 1));
        pc = e.end + 1;
        return;
      case OKeyword::ProgramEnd: m99(e, f, pc); return;
      case OKeyword::EndSub:
      case OKeyword::Return: {
        // #<_value> is what this return gives, 0 without an expression (LinuxCNC 2.9: retval.ngc's
        // bare `return` leaves 0, not the previous call's value); #<_value_returned> says which.
        OWord o;
        if (eval_o(f, pc, o)) {
          params_.write_named("_value", o.args.empty() ? 0.0 : o.args[0]);
          params_.write_named("_value_returned", o.args.empty() ? 0.0 : 1.0);
        }
        if (frames_.size() <= 1) {
          add_error(f, pc, e.o.col, fmt::format("o{} {} reached outside a call", e.o.name, to_string(e.o.keyword)));
          ++pc;
          return;
        }
        return_from_sub(f, pc);
        return;
      }
      case OKeyword::Call: call(e, f, pc); return;
      case OKeyword::If: {
        bool v = false;
        condition(f, pc, v);
        if (v) {
          ++pc;
          return;
        }
        for (std::size_t b = e.next; b != kNoLine;) {
          const OEntry* be = files_[f]->flow.at(b);
          if (!be) break;
          if (be->o.keyword == OKeyword::ElseIf) {
            bool bv = false;
            condition(f, b, bv);
            if (bv) {
              pc = b + 1;
              return;
            }
            b = be->next;
            continue;
          }
          pc = b + 1;  // else or endif
          return;
        }
        pc = e.end + 1;
        return;
      }
      case OKeyword::ElseIf:
      case OKeyword::Else: pc = e.end + 1; return;  // the branch before it ran: leave the if
      case OKeyword::EndIf:
      case OKeyword::Do:
        if (e.o.keyword == OKeyword::Do && !back) drop_loop(f, pc);
        ++pc;
        return;
      case OKeyword::While: {
        if (e.do_end) {
          bool v = false;
          condition(f, pc, v);
          if (v && count_pass(f, e.end, e)) {
            pc = e.end + 1;
            back_edge_ = true;
          } else {
            drop_loop(f, e.end);
            ++pc;
          }
          return;
        }
        if (!back) drop_loop(f, pc);
        bool v = false;
        condition(f, pc, v);
        if (v && count_pass(f, pc, e)) {
          ++pc;
        } else {
          drop_loop(f, pc);
          pc = e.end + 1;
        }
        return;
      }
      case OKeyword::EndWhile:
        pc = e.end;
        back_edge_ = true;
        return;
      case OKeyword::Repeat: {
        OWord o;
        double n = 0;
        if (eval_o(f, pc, o)) {
          if (o.args.size() != 1) add_error(f, pc, o.col, fmt::format("o{} repeat needs the count in [ ]", o.name));
          else n = o.args[0];
        }
        // LinuxCNC: repeat_count = round_to_int(value), i.e. nearbyint (2.5 runs twice, 2.6 three
        // times), and a count of 0 or less runs the body no time.
        n = std::max(0.0, std::nearbyint(n));
        if (n > static_cast<double>(opt_.max_loop_iterations)) {
          add_error(f, pc, e.o.col, fmt::format("repeat count {:g} is above the loop limit {}", n, opt_.max_loop_iterations));
          done_ = true;
          return;
        }
        drop_loop(f, pc);
        if (n == 0) {
          pc = e.end + 1;
          return;
        }
        frames_.back().loops.push_back(LoopCount{f, pc, 0, static_cast<long long>(n)});
        ++pc;
        return;
      }
      case OKeyword::EndRepeat: {
        LoopCount* l = loop(f, e.end);
        if (l && --l->repeat_left > 0) {
          pc = e.end + 1;
        } else {
          drop_loop(f, e.end);
          ++pc;
        }
        return;
      }
      case OKeyword::Break: {
        const OEntry* open = files_[f]->flow.at(e.end);
        drop_loop(f, e.end);
        pc = open ? open->end + 1 : pc + 1;
        return;
      }
      case OKeyword::Continue: {
        const OEntry* open = files_[f]->flow.at(e.end);
        if (!open) {
          ++pc;
          return;
        }
        if (open->o.keyword == OKeyword::While) {
          pc = e.end;
          back_edge_ = true;
        } else {
          pc = open->end;  // do: its closing while; repeat: its endrepeat
        }
        return;
      }
    }
  }

  // Finds a subroutine: the current file, the main file, files loaded so far, then <name>.ngc on
  // the subroutine path and in the main file's directory.
  bool find_sub(const std::string& name, std::size_t f, std::size_t& sub_file, std::size_t& sub_line, std::string& why) {
    auto look = [&](std::size_t i) {
      const auto it = files_[i]->flow.subs.find(name);
      if (it == files_[i]->flow.subs.end()) return false;
      sub_file = i;
      sub_line = files_[i]->flow.entries[it->second].line;
      return true;
    };
    if (look(f) || look(0)) return true;
    for (std::size_t i = 1; i < files_.size(); ++i)
      if (look(i)) return true;
    std::string base = name;
    if (base.size() >= 2 && base.front() == '<') base = base.substr(1, base.size() - 2);
    // A call in a loop to a missing subroutine would search the disk on every pass.
    const auto not_found = [&] {
      return fmt::format("subroutine o{} is not defined in the program, and no {}.ngc on the subroutine path", name, base);
    };
    if (missing_subs_.count(name)) {
      why = not_found();
      return false;
    }
    std::vector<std::string> dirs = opt_.subroutine_path;
    dirs.push_back(main_dir_);
    for (const auto& d : dirs) {
      const std::string path = (std::filesystem::path(d) / (base + ".ngc")).string();
      std::string text;
      if (read_text(path, text)) continue;
      if (files_.size() >= 1000) {
        why = "too many subroutine files";
        return false;
      }
      program_.files.push_back(path);
      const std::size_t nf = add_file(path, std::move(text));
      if (look(nf)) return true;
      why = fmt::format("{} does not define o{} sub", path, name);
      return false;
    }
    missing_subs_.insert(name);
    why = not_found();
    return false;
  }

  void call(const OEntry& e, std::size_t& f, std::size_t& pc) {
    OWord o;
    if (!eval_o(f, pc, o)) {
      ++pc;
      return;
    }
    std::size_t sf = 0, sl = 0;
    std::string why;
    if (!find_sub(o.name, f, sf, sl, why)) {
      add_error(f, pc, e.o.col, why);
      ++pc;
      return;
    }
    if (!enter_call(f, pc, e.o.col, "subroutine", CallFrame{f, pc + 1, {}})) return;
    params_.write_named("_value_returned", 0);
    params_.push_frame(o.args.data(), o.args.size());
    f = sf;
    pc = sl + 1;
  }

  // A call's frame, within the call depth (ParseOptions::max_call_depth); past it the program stops
  // with an error (endless recursion) and false.
  bool enter_call(std::size_t f, std::size_t pc, std::uint32_t col, const char* what, CallFrame frame) {
    if (frames_.size() > opt_.max_call_depth) {
      add_error(f, pc, col, fmt::format("{} calls nested more than {} deep (endless recursion?)", what, opt_.max_call_depth));
      done_ = true;
      return false;
    }
    frames_.push_back(std::move(frame));
    return true;
  }

  void return_from_sub(std::size_t& f, std::size_t& pc) {
    f = frames_.back().file;
    pc = frames_.back().return_line;
    frames_.pop_back();
    params_.pop_frame();
  }

  // ---- Fanuc-style subprograms: M98 P<n> [L<k>] calls O<n> … M99 ----

  // The subprogram M98 P names, in this file or the main one: P itself, else (P above 9999, no L)
  // Fanuc's packed form P<passes><4-digit number>. Rejected: none found, but P names a definition
  // whose structure error is reported already.
  enum class Found : std::uint8_t { Yes, Rejected, No };
  Found find_program(std::size_t f, long long p, bool has_l, long long& passes, std::size_t& pf, std::size_t& line) {
    bool rejected = false;
    const auto look = [&](long long number) {
      const std::string name = std::to_string(number);
      for (const std::size_t i : {f, std::size_t{0}}) {
        const FlowIndex& flow = files_[i]->flow;
        const auto it = flow.programs.find(name);
        if (it == flow.programs.end()) {
          rejected = rejected || (number == p && flow.rejected_programs.count(name));
          continue;
        }
        pf = i;
        line = flow.entries[it->second].line;
        return true;
      }
      return false;
    };
    if (look(p)) return Found::Yes;
    if (!has_l && p > 9999 && look(p % 10000)) {
      passes = p / 10000;
      return Found::Yes;
    }
    return rejected ? Found::Rejected : Found::No;
  }

  void call_m98(std::size_t f, std::size_t pc, const Word& m) {
    const std::string_view line = files_[f]->lines[pc];
    std::optional<Word> p, l;
    for (const Word& w : lexed_.words) {
      if (w.letter == 'N' || &w == &m) continue;
      if (w.letter == 'P' && !p) {
        p = w;
      } else if (w.letter == 'L' && !l) {
        l = w;
      } else {
        return fail(f, pc, line, LineError{w.col, fmt::format("M98 stands alone on its line, with P (the subprogram) "
                                                              "and L (how many times): {} is not allowed here",
                                                              w.letter == 'P' || w.letter == 'L'
                                                                  ? fmt::format("a second {}", w.letter)
                                                                  : fmt::format("{}{:g}", w.letter, w.value))});
      }
    }
    const auto whole = [](const Word& w) { return w.value >= 0 && w.value == std::floor(w.value); };
    if (!p) return fail(f, pc, line, LineError{m.col, "M98 needs P: the number of the subprogram O<n> … M99 to call"});
    if (!whole(*p)) return fail(f, pc, line, LineError{p->col, fmt::format("M98 P{:g}: P is a subprogram number (a "
                                                                            "whole number, 0 or more)", p->value)});
    if (l && !whole(*l)) return fail(f, pc, line, LineError{l->col, fmt::format("M98 L{:g}: L is how many times to run "
                                                                                 "it (a whole number, 0 or more)", l->value)});
    long long passes = l ? static_cast<long long>(l->value) : 1;
    std::size_t pf = 0, def = 0;
    const Found found = find_program(f, static_cast<long long>(p->value), l.has_value(), passes, pf, def);
    if (found == Found::Rejected) return;  // its definition's error is reported already
    if (found == Found::No) {
      return fail(f, pc, line, LineError{p->col, fmt::format("M98 P{0}: subprogram O{0} is not in the program (a line "
                                                             "O{0} after the main program's first block, then its "
                                                             "blocks, then M99)", static_cast<long long>(p->value))});
    }
    if (passes > static_cast<long long>(opt_.max_loop_iterations))
      return fail(f, pc, line, LineError{(l ? *l : *p).col, fmt::format("M98 runs the subprogram {} times, above the loop "
                                                                         "limit {}", passes, opt_.max_loop_iterations)});
    emit_messages(f, pc, m.col);
    if (passes == 0) return;
    CallFrame frame{f, pc + 1, {}};
    frame.m98 = true;
    frame.program_line = def;
    frame.passes_left = passes;
    if (!enter_call(f, pc, m.col, "subprogram", std::move(frame))) return;
    params_.push_frame(nullptr, 0, true);  // named locals of its own, the caller's #1…#30
    jump_ = {pf, def + 1};
  }

  // M99 closing a subprogram: the next pass (M98 L), or back after the M98. The line holds M99
  // alone (with N and comments); M99 P<seq> (return to a sequence number) is not supported.
  void m99(const OEntry& e, std::size_t& f, std::size_t& pc) {
    const std::string_view line = files_[f]->lines[pc];
    lex(line, pc);
    if (lexed_.error) {
      fail(f, pc, line, std::move(*lexed_.error));
      ++pc;
      return;
    }
    if (aborts(f, pc)) return;
    if (!lexed_.assignments.empty()) {
      fail(f, pc, line, LineError{lexed_.assignments.front().col, "M99 stands alone on its line (with N): set "
                                                                    "parameters on a line of their own"});
      ++pc;
      return;
    }
    for (const Word& w : lexed_.words) {
      if (w.letter == 'N' || (w.letter == 'M' && w.value == 99)) continue;
      fail(f, pc, line, LineError{w.col, w.letter == 'P' ? std::string("M99 P (return to a sequence number) is not "
                                                                         "supported: M99 returns after the M98")
                                                          : fmt::format("M99 stands alone on its line (with N): {}{:g} "
                                                                        "is not allowed here", w.letter, w.value)});
      ++pc;
      return;
    }
    emit_messages(f, pc, e.o.col);
    if (frames_.size() <= 1 || !frames_.back().m98) {
      add_error(f, pc, e.o.col, fmt::format("M99 of subprogram O{} reached outside an M98 call", e.o.name));
      ++pc;
      return;
    }
    CallFrame& top = frames_.back();
    if (--top.passes_left > 0) {
      top.loops.clear();
      pc = top.program_line + 1;
      return;
    }
    return_from_sub(f, pc);
  }

  void finish() {
    if (state_.motion == Motion::Nurbs && !state_.ended && !done_ && !state_.nurbs_uncertain)
      add_error_loc(nurbs_open_, "the program ends inside this G5.2 block: close it with G5.3");
    if (comp_.active()) {
      comp_out_.clear();
      comp_.stop(comp_out_);
      for (auto& ins : comp_out_) program_.instructions.push_back(std::move(ins));
    }
  }

  // ---- diagnostics ----

  static std::uint32_t line_no(std::size_t pc) { return static_cast<std::uint32_t>(std::min<std::size_t>(pc + 1, 0xFFFFFFFFu)); }

  void add_error(std::size_t f, std::size_t pc, std::uint32_t col, std::string message) {
    add_error_at(files_.empty() ? program_.files[0] : files_[f]->path, f == 0 && files_.empty() ? 0 : line_no(pc), col,
                 std::move(message));
  }
  void add_error_loc(const core::SourceLoc& loc, std::string message) {
    add_error_at(files_[loc.file]->path, loc.line, loc.col, std::move(message));
  }
  void add_error_at(const std::string& file, std::uint32_t line, std::uint32_t col, std::string message) {
    if (!seen_.insert(fmt::format("{}:{}:{}:{}", file, line, col, message)).second) return;  // a loop repeats it
    if (errors_ == kMaxErrors) {
      note_ = make_diag(file, line, col, core::Severity::Note, fmt::format("too many errors ({}); stopping here", kMaxErrors));
      done_ = true;
      return;
    }
    ++errors_;
    diags_.push_back(make_diag(file, line, col, core::Severity::Error, std::move(message)));
  }
  void add_diag(std::size_t f, std::size_t pc, std::uint32_t col, core::Severity sev, std::string message) {
    diags_.push_back(make_diag(files_[f]->path, line_no(pc), col, sev, std::move(message)));
  }

  const MTable& mtable() const {
    static const MTable kFixed;
    return opt_.m_table ? *opt_.m_table : kFixed;
  }

  const ParseOptions& opt_;
  InterpOptions interp_;
  Program program_;
  ModalState state_;
  core::SourceLoc nurbs_open_;  // the G5.2 word of the open NURBS block
  Parameters params_;
  CutterComp comp_;
  std::vector<Instruction> comp_out_;
  std::vector<std::unique_ptr<SourceFile>> files_;
  std::vector<CallFrame> frames_;
  std::optional<std::pair<std::size_t, std::size_t>> jump_;  // where a line's M98 goes next (file, line)
  std::string main_dir_;
  LexedLine lexed_;
  FastBlock fast_;
  Block block_;
  BlockOutput out_;
  core::Diagnostics diags_;
  std::optional<core::Diagnostic> note_;
  std::unordered_set<std::string> seen_;
  std::unordered_set<std::string> missing_subs_;  // searched for and not found: not searched again
  std::size_t errors_ = 0;
  std::size_t blocks_ = 0;
  std::size_t total_lines_ = 0;  // of every file read
  std::size_t sunk_ = 0;         // instructions handed to ParseOptions::sink
  bool position_params_stale_ = true;
  bool named_params_stale_ = true;  // the predefined named parameters, likewise
  bool seen_block_ = false;
  bool percent_open_ = false;
  bool back_edge_ = false;
  bool done_ = false;
};

}  // namespace

ParseResult parse(std::string_view text, const std::string& file_name, const ParseOptions& opt) {
  return ProgramReader(file_name, opt).run(std::string(text));
}

ParseResult parse_file(const std::string& path, const ParseOptions& opt) {
  std::string text;
  if (auto err = read_text(path, text)) {
    ParseResult r;
    r.diagnostics.push_back(make_diag(path, 0, 0, core::Severity::Error, *err));
    return r;
  }
  return ProgramReader(path, opt).run(std::move(text));
}

}  // namespace softmc::program::iso
