// The interpreter's machine settings made into ParseOptions: tool table, subroutine folders, user M functions.
#include "program/iso/interp_config.hpp"

#include <fmt/format.h>

namespace softmc::program::iso {

core::Diagnostics InterpSetup::load(const InterpConfig& cfg) {
  core::Diagnostics d;
  auto error = [&](std::string message) { d.push_back({cfg.source, 0, 0, core::Severity::Error, std::move(message)}); };
  tools_ = ToolTable{};
  has_tools_ = false;
  if (!cfg.tool_table.empty()) {
    if (auto t = load_tool_table(cfg.tool_table, d)) {
      tools_ = std::move(*t);
      has_tools_ = true;
    }
  }
  m_table_ = MTable{};
  for (const MConfig& m : cfg.m_functions) {
    const std::string key = fmt::format("gcode.m.{}", m.number);
    if (m.number < 0 || m.number > kMaxMNumber) {
      error(fmt::format("{}: M functions are numbered 0 … {}", key, kMaxMNumber));
      continue;
    }
    MConfig c = m;
    // Group 0: keep the function's own group (a fixed P-10 function's, else "everything else").
    if (c.group == 0) c.group = m_table_.get(m.number).group;
    if (!MTable::is_fixed(m.number) && !(c.group == 4 || (c.group >= 10 && c.group <= kMGroups))) {
      error(fmt::format("{}.group: user M functions go in the free groups 4, 10, 11, 12, 13 or 14 (got {})", key, c.group));
      continue;
    }
    if (MTable::is_fixed(m.number) && c.group != m_table_.get(m.number).group) {
      error(fmt::format("{}.group: M{} is a fixed P-10 function of group {} and cannot leave it (got {}); only its "
                        "flags may change", key, m.number, m_table_.get(m.number).group, c.group));
      continue;
    }
    if (!m_table_.configure(c)) error(fmt::format("{}: cannot be configured (group {})", key, c.group));
  }
  subroutine_path_ = cfg.subroutine_path;
  g23_tolerance_mm_ = cfg.g23_tolerance_mm;
  return d;
}

ParseOptions InterpSetup::options() const {
  ParseOptions o;
  o.subroutine_path = subroutine_path_;
  o.tools = tools();
  o.m_table = &m_table_;
  o.g23_tolerance_mm = g23_tolerance_mm_;
  return o;
}

}  // namespace softmc::program::iso
