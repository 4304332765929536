// The control-flow index of one file: every O-word line with the lines it jumps to, built before
// the program runs so that structure errors are reported in one pass and jumps cost nothing.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "program/iso/lexer.hpp"
#include "program/iso/line_error.hpp"

namespace softmc::program::iso {

inline constexpr std::size_t kNoLine = static_cast<std::size_t>(-1);

struct OEntry {
  OWord o;                    // header only (name, keyword, col)
  std::size_t line = 0;       // 0-based line index
  std::size_t next = kNoLine; // if/elseif/else: the next branch line (elseif, else or endif)
  std::size_t end = kNoLine;  // sub: endsub; if/elseif/else: endif; while/do/repeat: closing line;
                              // endwhile/endrepeat/do-end while: the opening line;
                              // break/continue: the opening line of their loop
  bool do_end = false;        // a "while" that closes a "do"
  bool valid = false;         // structure complete: jumps may be taken
};

struct FlowIndex {
  std::vector<std::uint32_t> entry_of;  // per line: index into entries + 1, 0 = not an O-word line
  std::vector<OEntry> entries;
  std::unordered_map<std::string, std::size_t> subs;  // name → entry index of its "sub"
  // Fanuc-style subprograms (O1000 … M99, called by M98 P1000): number → entry index of its O line.
  std::unordered_map<std::string, std::size_t> programs;
  std::unordered_set<std::string> rejected_programs;  // numbers whose definition had a structure error

  const OEntry* at(std::size_t line) const {
    return line < entry_of.size() && entry_of[line] ? &entries[entry_of[line] - 1] : nullptr;
  }
};

struct IndexError {
  std::size_t line = 0;  // 0-based
  LineError error;
};

// Builds the index of `lines`; structure errors (unmatched or misnamed keywords) go to `errors`.
// A bare O-number line after the file's first block, followed by an M99 line before the next bare
// O-number line, is a Fanuc-style subprogram: an OKeyword::Program entry on the O line whose end is
// the M99 line, and an OKeyword::ProgramEnd entry there (end: the O line). A bare O-number line
// without such an M99 (the program number CAM posts put first) is no entry, as before.
FlowIndex index_flow(const std::vector<std::string_view>& lines, std::vector<IndexError>& errors);

}  // namespace softmc::program::iso
