// Tool table: number, diameter and length of each tool, for the H (G43) and D (G41/G42) words.
#include "program/iso/tool_table.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <fmt/format.h>

#include "program/iso/lexer.hpp"

namespace softmc::program::iso {

ToolTable parse_tool_table(std::string_view text, const std::string& file_name, core::Diagnostics& diags) {
  ToolTable table;
  std::uint32_t line_no = 0;
  auto add = [&](std::uint32_t col, std::string msg) {
    core::Diagnostic d;
    d.file = file_name;
    d.line = line_no;
    d.col = col;
    d.message = std::move(msg);
    diags.push_back(std::move(d));
  };
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t nl = text.find('\n', pos);
    std::string_view line = text.substr(pos, (nl == std::string_view::npos ? text.size() : nl) - pos);
    pos = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
    ++line_no;
    const LexedLine l = lex_line(line);  // the same words as G-code; ';' starts the comment
    if (l.error) {
      add(l.error->col, l.error->message);
      continue;
    }
    if (l.words.empty()) continue;
    Tool t;
    bool has_t = false, bad = false;
    for (const auto& w : l.words) {
      if (w.letter == 'T') {
        if (w.value < 0 || w.value != std::floor(w.value) || w.value > 99999) {
          add(w.col, "tool number must be a whole number 0 … 99999");
          bad = true;
          break;
        }
        t.number = static_cast<int>(w.value);
        has_t = true;
      } else if (w.letter == 'P') {
        t.pocket = static_cast<int>(w.value);
      } else if (w.letter == 'D') {
        if (w.value < 0) {
          add(w.col, "tool diameter must be 0 or more");
          bad = true;
          break;
        }
        t.diameter_mm = w.value;
      } else if (auto a = core::axis_from_letter(w.letter)) {
        t.offset[*a] = w.value;
      } else if (w.letter == 'I' || w.letter == 'J' || w.letter == 'Q') {
        // lathe front/back angles and orientation: accepted and ignored
      } else {
        add(w.col, fmt::format("unknown tool table word {}", w.letter));
        bad = true;
        break;
      }
    }
    if (bad) continue;
    if (!has_t) {
      add(l.words.front().col, "tool table line without a T word");
      continue;
    }
    table.set(t);
  }
  return table;
}

std::optional<ToolTable> load_tool_table(const std::string& path, core::Diagnostics& diags) {
  std::error_code ec;
  std::string text;
  bool ok = std::filesystem::is_regular_file(path, ec) && !ec;
  if (ok) {
    std::ifstream in(path, std::ios::binary);
    ok = static_cast<bool>(in);
    if (ok) text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  if (!ok) {
    core::Diagnostic d;
    d.file = path;
    d.message = "cannot read tool table";
    diags.push_back(std::move(d));
    return std::nullopt;
  }
  return parse_tool_table(text, path, diags);
}

}  // namespace softmc::program::iso
