// M72/M73's restore of modal state as the blocks LinuxCNC's saved modes amount to.
#include "program/iso/modal_restore.hpp"

#include <fmt/format.h>

namespace softmc::program::iso {
namespace {

bool same_path(const ModalState& a, const ModalState& b) {
  return a.path_programmed == b.path_programmed && a.path == b.path;
}

}  // namespace

ModalRestore modal_restore_blocks(const ModalState& saved, const ModalState& now, std::uint32_t col) {
  ModalRestore r;
  const auto word = [col](char letter, double value) { return Word{letter, value, col}; };
  if (saved.comp != Comp::Off && (now.comp != saved.comp || now.comp_radius_mm != saved.comp_radius_mm)) {
    r.error = fmt::format("cannot restore cutter compensation {} (radius {:g} mm): program G41/G42 again after the "
                          "restore (LinuxCNC would turn it on with the current tool's radius)",
                          saved.comp == Comp::Left ? "left (G41)" : "right (G42)", saved.comp_radius_mm);
    return r;
  }
  if (!saved.path_programmed && now.path_programmed) {
    r.error = "cannot restore the machine's default path mode: no G61/G61.1/G64 was in effect when the state was "
              "saved; program one before M70/M73";
    return r;
  }
  if (saved.units != now.units) r.blocks.push_back({word('G', saved.units == Units::Inch ? 20 : 21)});
  if (now.comp != Comp::Off && saved.comp == Comp::Off) r.blocks.push_back({word('G', 40)});
  // M9 first where a coolant the saved state had off is on (M9 and M7/M8 are one group).
  const bool coolant_off = (now.mist && !saved.mist) || (now.flood && !saved.flood);
  if (coolant_off) r.blocks.push_back({word('M', 9)});
  std::vector<Word> rest;
  if (saved.plane != now.plane) rest.push_back(word('G', plane_code10(saved.plane) / 10.0));
  if (saved.distance != now.distance) rest.push_back(word('G', saved.distance == Distance::Absolute ? 90 : 91));
  if (saved.arc_distance != now.arc_distance)
    rest.push_back(word('G', saved.arc_distance == Distance::Absolute ? 90.1 : 91.1));
  if (saved.feed_mode != now.feed_mode) rest.push_back(word('G', saved.feed_mode == FeedMode::InverseTime ? 93 : 94));
  if (saved.coord_system != now.coord_system) rest.push_back(word('G', coord_system_code10(saved.coord_system) / 10.0));
  if (saved.retract != now.retract) rest.push_back(word('G', saved.retract == Retract::OldZ ? 98 : 99));
  if (saved.css != now.css || saved.spindle_speed != now.spindle_speed ||
      (saved.css && saved.css_max_rpm != now.css_max_rpm)) {
    rest.push_back(word('G', saved.css ? 96 : 97));
    rest.push_back(word('S', saved.spindle_speed));
    if (saved.css && saved.css_max_rpm > 0) rest.push_back(word('D', saved.css_max_rpm));
  }
  if (saved.spindle != now.spindle)
    rest.push_back(word('M', saved.spindle == SpindleDir::Cw ? 3 : saved.spindle == SpindleDir::Ccw ? 4 : 5));
  if (saved.mist && (coolant_off || !now.mist)) rest.push_back(word('M', 7));
  if (saved.flood && (coolant_off || !now.flood)) rest.push_back(word('M', 8));
  if (saved.feed_override != now.feed_override) rest.push_back(word('M', saved.feed_override ? 48 : 49));
  // G43 and G49 are programmed again where the code differs (G43: the tool now loaded, as rs274
  // does); a G43.1 offset is set to the bit by restore_exact_modes.
  if (saved.tool_length_code != now.tool_length_code && saved.tool_length_code != 431)
    rest.push_back(word('G', saved.tool_length_code / 10.0));
  if (!rest.empty()) r.blocks.push_back(std::move(rest));
  return r;
}

std::optional<std::string> restore_exact_modes(const ModalState& saved, ModalState& st, std::vector<Op>& ops) {
  const bool tool_changes = saved.tool_length_code == 431 && (st.tool_length_code != 431 || !(saved.tool == st.tool));
  if (tool_changes && st.comp != Comp::Off)
    return "cannot restore the tool length offset with cutter radius compensation on (G40 first)";
  if (!same_path(saved, st) && saved.path_programmed) {
    st.path = saved.path;
    st.path_programmed = true;
    ops.emplace_back(saved.path);
  }
  if (tool_changes) {
    st.tool = saved.tool;
    st.tool_length_code = 431;
    ops.emplace_back(offsets_of(st));
  }
  st.feed_mm_s = saved.feed_mm_s;
  st.feed_word = saved.feed_word;
  st.feed_in_block = false;
  return std::nullopt;
}

}  // namespace softmc::program::iso
