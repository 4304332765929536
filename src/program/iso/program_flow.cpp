// The ISO program reader's control flow: O-word branches, loops, subroutine calls and returns, M98/M99 subprograms.
//
// Every O-word line was indexed with the lines it jumps to (flow_index.hpp) before the program runs;
// here the reader follows those jumps as it meets them, evaluating conditions and counts then.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "program/iso/flow_index.hpp"
#include "program/iso/lexer.hpp"
#include "program/iso/modal_restore.hpp"
#include "program/iso/program_reader.hpp"

namespace softmc::program::iso::detail {

// ---- O-words ----

// Evaluates the O-word line (its [values]); false (reported) when it has an error.
bool ProgramReader::eval_o(std::size_t f, std::size_t pc, OWord& out) {
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

bool ProgramReader::condition(std::size_t f, std::size_t pc, bool& value) {
  OWord o;
  if (!eval_o(f, pc, o)) return false;
  if (o.args.size() != 1) {
    add_error(f, pc, o.col, fmt::format("o{} {} needs one condition in [ ]", o.name, to_string(o.keyword)));
    return false;
  }
  value = o.args[0] != 0.0;
  return true;
}

LoopCount* ProgramReader::loop(std::size_t f, std::size_t line) {
  for (auto& l : frames_.back().loops)
    if (l.file == f && l.line == line) return &l;
  return nullptr;
}

void ProgramReader::drop_loop(std::size_t f, std::size_t line) {
  auto& v = frames_.back().loops;
  v.erase(std::remove_if(v.begin(), v.end(), [&](const LoopCount& l) { return l.file == f && l.line == line; }), v.end());
}

// Counts one more pass of the loop opened at `line`; false (reported, program stopped) past the limit.
bool ProgramReader::count_pass(std::size_t f, std::size_t line, const OEntry& e) {
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

void ProgramReader::o_line(const OEntry& e, std::size_t& f, std::size_t& pc) {
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
      return_from_sub(f, pc, e.o.col);
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
bool ProgramReader::find_sub(const std::string& name, std::size_t f, std::size_t& sub_file, std::size_t& sub_line,
                             std::string& why) {
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

void ProgramReader::call(const OEntry& e, std::size_t& f, std::size_t& pc) {
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
bool ProgramReader::enter_call(std::size_t f, std::size_t pc, std::uint32_t col, const char* what, CallFrame frame) {
  if (frames_.size() > opt_.max_call_depth) {
    add_error(f, pc, col, fmt::format("{} calls nested more than {} deep (endless recursion?)", what, opt_.max_call_depth));
    done_ = true;
    return false;
  }
  frames_.push_back(std::move(frame));
  return true;
}

void ProgramReader::return_from_sub(std::size_t& f, std::size_t& pc, std::uint32_t col) {
  // Not where a subroutine file ended without its endsub: that is reported already.
  if (pc < files_[f]->lines.size()) autorestore(f, pc, col);
  f = frames_.back().file;
  pc = frames_.back().return_line;
  frames_.pop_back();
  params_.pop_frame();
}

// ---- Fanuc-style subprograms: M98 P<n> [L<k>] calls O<n> … M99 ----

// The subprogram M98 P names, in this file or the main one: P itself, else (P above 9999, no L)
// Fanuc's packed form P<passes><4-digit number>. Rejected: none found, but P names a definition
// whose structure error is reported already.
ProgramReader::Found ProgramReader::find_program(std::size_t f, long long p, bool has_l, long long& passes,
                                                 std::size_t& pf, std::size_t& line) {
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

void ProgramReader::call_m98(std::size_t f, std::size_t pc, const Word& m) {
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
void ProgramReader::m99(const OEntry& e, std::size_t& f, std::size_t& pc) {
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
    // Each pass is a call of its own (LinuxCNC): M73's modes come back at its M99, and what M70/M73
    // saved is gone for the next pass.
    autorestore(f, pc, e.o.col);
    top.forget_modes();
    top.loops.clear();
    pc = top.program_line + 1;
    return;
  }
  return_from_sub(f, pc, e.o.col);
}

// ---- modal state: M70 save, M71 invalidate, M72 restore, M73 save and restore on return ----

// LinuxCNC 2.9's M70…M73. Each call level keeps its own saved state (the main program one), so an
// M72 restores only what M70/M73 saved at its own level. The line holds the M code alone (with N and
// comments): LinuxCNC runs it at step 10 of a block's order, between the spindle and the coolant, an
// order a restore in the middle of a block would make hard to read.
void ProgramReader::modal_state_m(std::size_t f, std::size_t pc, const Word& m) {
  const std::string_view line = files_[f]->lines[pc];
  const int n = static_cast<int>(m.value);
  for (const Word& w : lexed_.words) {
    if (w.letter == 'N' || &w == &m) continue;
    return fail(f, pc, line, LineError{w.col, fmt::format("M{} stands alone on its line (with N): {}{:g} is not allowed "
                                                          "here", n, w.letter, w.value)});
  }
  if (state_.motion == Motion::Nurbs)
    return fail(f, pc, line, LineError{m.col, fmt::format("M{} inside a G5.2 block: close it with G5.3 first", n)});
  emit_messages(f, pc, m.col);
  CallFrame& level = frames_.back();
  switch (n) {
    case 70:
    case 73:
      level.saved_modes = state_;
      // M73 in the main program saves only: its end (M2/M30) restores nothing (LinuxCNC).
      level.autorestore = level.autorestore || (n == 73 && frames_.size() > 1);
      return;
    case 71:
      level.forget_modes();
      return;
    default:
      if (!level.saved_modes) {
        add_error(f, pc, m.col, "M72 with no modal state saved at this call level: M70 or M73 first (a subroutine's "
                                "saved state is its own, the main program's its own)");
        return;
      }
      restore_modes(*level.saved_modes, f, pc, m.col, "M72");
  }
}

void ProgramReader::autorestore(std::size_t f, std::size_t pc, std::uint32_t col) {
  const CallFrame& level = frames_.back();
  if (level.autorestore && level.saved_modes)
    restore_modes(*level.saved_modes, f, pc, col, "the return restores the modes M73 saved");
}

// Brings the saved modes back (modal_restore.hpp) as the restore's blocks would, run on a copy of the
// state first: an error (`what`: which restore it was) leaves the state and the program unchanged.
bool ProgramReader::restore_modes(const ModalState& saved, std::size_t f, std::size_t pc, std::uint32_t col,
                                  std::string_view what) {
  const ModalRestore r = modal_restore_blocks(saved, state_, col);
  if (r.error) {
    add_error(f, pc, col, fmt::format("{}: {}", what, *r.error));
    return false;
  }
  ModalState st = state_;
  std::vector<BlockOutput> outs(r.blocks.size());
  for (std::size_t i = 0; i < r.blocks.size(); ++i) {
    Block b;
    std::optional<LineError> e = check_block(r.blocks[i], mtable(), b);
    if (!e) e = execute(b, st, params_, interp_, outs[i]);
    if (e) {
      add_error(f, pc, col, fmt::format("{}: {}", what, e->message));
      return false;
    }
  }
  std::vector<Op> exact;
  if (auto e = restore_exact_modes(saved, st, exact)) {
    add_error(f, pc, col, fmt::format("{}: {}", what, *e));
    return false;
  }
  const core::Vec before = state_.position;
  state_ = std::move(st);
  const core::SourceLoc loc{static_cast<std::uint16_t>(f), line_no(pc), col};
  for (auto& o : outs) {
    out_ = std::move(o);
    deliver(loc, before);
  }
  for (auto& op : exact) put(Instruction{loc, std::move(op)});
  position_params_stale_ = true;
  return true;
}

}  // namespace softmc::program::iso::detail
