// Tool table: number, diameter and length of each tool, for the H (G43) and D (G41/G42) words.
//
// File format (LinuxCNC's .tbl, one tool a line, anything after ';' is a comment):
//   T1 P1 D6.0 Z25.4 ;6 mm end mill
//   T2 P2 D1.5 Z0 X0 ;torch nozzle
// T = tool number (required, 0..99999), D = diameter, Z = length offset (and X…W for other axes),
// P = pocket (kept, unused). Values in mm. Unknown letters are refused.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "core/axes.hpp"
#include "core/diagnostic.hpp"

namespace softmc::program::iso {

struct Tool {
  int number = 0;
  int pocket = 0;
  double diameter_mm = 0;
  core::Vec offset;  // length offset per axis (Z is the tool length)
};

class ToolTable {
 public:
  void set(const Tool& t) { tools_[t.number] = t; }
  const Tool* find(int number) const {
    const auto it = tools_.find(number);
    return it == tools_.end() ? nullptr : &it->second;
  }
  bool empty() const { return tools_.empty(); }

 private:
  std::map<int, Tool> tools_;
};

// Reads a tool table; every bad line becomes a diagnostic (file:line:col) and is skipped.
ToolTable parse_tool_table(std::string_view text, const std::string& file_name, core::Diagnostics& diags);
std::optional<ToolTable> load_tool_table(const std::string& path, core::Diagnostics& diags);

}  // namespace softmc::program::iso
