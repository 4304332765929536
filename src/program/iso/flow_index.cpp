// The control-flow index of one file: every O-word line with the lines it jumps to.
#include "program/iso/flow_index.hpp"

#include <optional>

#include <fmt/format.h>

namespace softmc::program::iso {
namespace {

bool is_loop(OKeyword k) { return k == OKeyword::While || k == OKeyword::Do || k == OKeyword::Repeat; }

std::string label(const OWord& o) { return fmt::format("o{} {}", o.name, to_string(o.keyword)); }

}  // namespace

FlowIndex index_flow(const std::vector<std::string_view>& lines, std::vector<IndexError>& errors) {
  FlowIndex idx;
  idx.entry_of.assign(lines.size(), 0);
  struct Open {
    std::size_t entry;
    std::size_t last_branch;           // if: the latest if/elseif/else entry
    std::vector<std::size_t> jumps;    // break/continue entries inside this loop
    std::vector<std::size_t> branches; // if: every branch entry
    bool has_else = false;
  };
  std::vector<Open> stack;
  auto err = [&](std::size_t line, std::uint32_t col, std::string msg) {
    errors.push_back(IndexError{line, LineError{col, std::move(msg)}});
  };
  // Fanuc-style subprograms: the bare O-number line waiting for its M99, and the structures open there.
  struct Pending {
    ProgramNumber number;
    std::size_t line = 0, depth = 0;
    std::string inside;  // the innermost structure open at the O line ("o1 if (line 3)"), if any
  };
  std::optional<Pending> pending;
  bool block_seen = false;  // a bare O-number before any block is the program's own number
  const auto close_program = [&](std::size_t n, std::uint32_t m99_col) {
    const Pending p = *pending;
    pending.reset();
    idx.rejected_programs.insert(p.number.name);  // until it is accepted below
    const std::string what = fmt::format("subprogram O{} (line {})", p.number.name, p.line + 1);
    if (stack.size() > p.depth) {
      const auto& t = idx.entries[stack.back().entry];
      return err(n, m99_col, fmt::format("M99 ends {} while {} (line {}) inside it is still open", what, label(t.o),
                                         t.line + 1));
    }
    if (!p.inside.empty())
      return err(p.line, p.number.col, fmt::format("{} starts inside {}: subprograms stand on their own, outside "
                                                   "every O-word structure", what, p.inside));
    if (idx.programs.count(p.number.name)) return err(p.line, p.number.col, fmt::format("{} is defined twice", what));
    const std::size_t e = idx.entries.size();
    OEntry start{OWord{p.number.name, OKeyword::Program, p.number.col, {}}, p.line, kNoLine, n, false, true};
    OEntry end{OWord{p.number.name, OKeyword::ProgramEnd, m99_col, {}}, n, kNoLine, p.line, false, true};
    idx.entries.push_back(std::move(start));
    idx.entries.push_back(std::move(end));
    idx.entry_of[p.line] = static_cast<std::uint32_t>(e + 1);
    idx.entry_of[n] = static_cast<std::uint32_t>(e + 2);
    idx.programs.emplace(p.number.name, e);
    idx.rejected_programs.erase(p.number.name);
  };
  for (std::size_t n = 0; n < lines.size(); ++n) {
    auto o = scan_o_word(lines[n]);
    if (!o) {
      if (auto number = scan_program_number(lines[n])) {
        if (block_seen) {
          pending = Pending{std::move(*number), n, stack.size(), {}};
          if (!stack.empty()) {
            const auto& t = idx.entries[stack.back().entry];
            pending->inside = fmt::format("{} (line {})", label(t.o), t.line + 1);
          }
        }
        block_seen = true;
      } else if (pending) {
        if (const std::uint32_t col = scan_m99(lines[n])) close_program(n, col);
      }
      if (!block_seen) {
        const auto first = lines[n].find_first_not_of(" \t\r");
        block_seen = first != std::string_view::npos && lines[n][first] != '(' && lines[n][first] != ';' &&
                     lines[n][first] != '%';
      }
      continue;
    }
    block_seen = true;
    idx.entries.push_back(OEntry{std::move(*o), n});
    const std::size_t e = idx.entries.size() - 1;
    idx.entry_of[n] = static_cast<std::uint32_t>(e + 1);
    OEntry& cur = idx.entries[e];
    const OKeyword k = cur.o.keyword;
    auto top_matches = [&](OKeyword open_kw) {
      return !stack.empty() && idx.entries[stack.back().entry].o.keyword == open_kw &&
             idx.entries[stack.back().entry].o.name == cur.o.name;
    };
    auto mismatch = [&](const char* wants) {
      if (stack.empty()) return err(n, cur.o.col, fmt::format("{} without a matching {}", label(cur.o), wants));
      const auto& t = idx.entries[stack.back().entry];
      err(n, cur.o.col, fmt::format("{} does not match the open {} (line {})", label(cur.o), label(t.o), t.line + 1));
    };
    switch (k) {
      case OKeyword::Sub:
        for (const auto& s : stack)
          if (idx.entries[s.entry].o.keyword == OKeyword::Sub) {
            err(n, cur.o.col, fmt::format("{} inside another subroutine: subroutines cannot be nested", label(cur.o)));
            break;
          }
        if (idx.subs.count(cur.o.name)) err(n, cur.o.col, fmt::format("subroutine o{} is defined twice", cur.o.name));
        else idx.subs.emplace(cur.o.name, e);
        stack.push_back(Open{e, e});
        break;
      case OKeyword::If:
      case OKeyword::Do:
      case OKeyword::Repeat:
        stack.push_back(Open{e, e});
        if (k == OKeyword::If) stack.back().branches.push_back(e);
        break;
      case OKeyword::While:
        if (top_matches(OKeyword::Do)) {  // closes a do … while
          auto& open = stack.back();
          cur.do_end = true;
          cur.end = idx.entries[open.entry].line;
          cur.valid = true;
          idx.entries[open.entry].end = n;
          idx.entries[open.entry].valid = true;
          for (auto j : open.jumps) {
            idx.entries[j].end = idx.entries[open.entry].line;
            idx.entries[j].valid = true;
          }
          stack.pop_back();
        } else {
          stack.push_back(Open{e, e});
        }
        break;
      case OKeyword::ElseIf:
      case OKeyword::Else:
        if (!top_matches(OKeyword::If)) {
          mismatch("if");
          break;
        }
        if (stack.back().has_else) {
          err(n, cur.o.col, fmt::format("{} after the else of o{}", label(cur.o), cur.o.name));
          break;
        }
        idx.entries[stack.back().last_branch].next = n;
        stack.back().last_branch = e;
        stack.back().branches.push_back(e);
        stack.back().has_else = k == OKeyword::Else;
        break;
      case OKeyword::EndSub:
      case OKeyword::EndIf:
      case OKeyword::EndWhile:
      case OKeyword::EndRepeat: {
        const OKeyword opener = k == OKeyword::EndSub ? OKeyword::Sub
                                : k == OKeyword::EndIf ? OKeyword::If
                                : k == OKeyword::EndWhile ? OKeyword::While
                                                          : OKeyword::Repeat;
        if (!top_matches(opener)) {
          mismatch(to_string(opener));
          break;
        }
        auto& open = stack.back();
        OEntry& first = idx.entries[open.entry];
        cur.end = first.line;
        cur.valid = true;
        first.end = n;
        first.valid = true;
        if (k == OKeyword::EndIf) {
          idx.entries[open.last_branch].next = n;
          for (auto b : open.branches) {
            idx.entries[b].end = n;
            idx.entries[b].valid = true;
          }
        }
        for (auto j : open.jumps) {
          idx.entries[j].end = first.line;
          idx.entries[j].valid = true;
        }
        stack.pop_back();
        break;
      }
      case OKeyword::Break:
      case OKeyword::Continue: {
        bool found = false;
        for (auto it = stack.rbegin(); it != stack.rend(); ++it) {
          const auto& oe = idx.entries[it->entry];
          if (oe.o.keyword == OKeyword::Sub) break;
          if (is_loop(oe.o.keyword) && oe.o.name == cur.o.name) {
            it->jumps.push_back(e);
            found = true;
            break;
          }
        }
        if (!found) err(n, cur.o.col, fmt::format("{} outside a loop named o{}", label(cur.o), cur.o.name));
        break;
      }
      case OKeyword::Return: {
        // Any O-number inside a subroutine's definition returns from it (LinuxCNC 2.9: `o1010 return`
        // inside sub o1000's `o1010 if` returns from o1000); outside every definition it is an error.
        bool in_sub = false;
        for (const auto& s : stack)
          if (idx.entries[s.entry].o.keyword == OKeyword::Sub) in_sub = true;
        if (!in_sub) err(n, cur.o.col, fmt::format("{} outside a subroutine definition", label(cur.o)));
        cur.valid = in_sub;
        break;
      }
      case OKeyword::Call: cur.valid = true; break;
      case OKeyword::Program:
      case OKeyword::ProgramEnd: break;  // never written as keywords (scan_program_number, scan_m99)
    }
  }
  for (const auto& open : stack) {
    const auto& oe = idx.entries[open.entry];
    const char* closer = oe.o.keyword == OKeyword::Sub ? "endsub"
                         : oe.o.keyword == OKeyword::If ? "endif"
                         : oe.o.keyword == OKeyword::While ? "endwhile"
                         : oe.o.keyword == OKeyword::Do ? "while"
                                                        : "endrepeat";
    err(oe.line, oe.o.col, fmt::format("{} has no o{} {}", label(oe.o), oe.o.name, closer));
  }
  return idx;
}

}  // namespace softmc::program::iso
