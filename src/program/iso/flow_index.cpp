// The control-flow index of one file: every O-word line with the lines it jumps to.
#include "program/iso/flow_index.hpp"

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
  for (std::size_t n = 0; n < lines.size(); ++n) {
    auto o = scan_o_word(lines[n]);
    if (!o) continue;
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
