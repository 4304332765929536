// LinuxCNC's predefined named parameters from the interpreter's state.
#include "program/iso/predefined_params.hpp"

#include "program/iso/exec.hpp"

namespace softmc::program::iso {

bool may_read_predefined(std::string_view line) {
  for (std::size_t i = line.find('<'); i != std::string_view::npos; i = line.find('<', i + 1)) {
    std::size_t k = i + 1;
    while (k < line.size() && (line[k] == ' ' || line[k] == '\t')) ++k;
    if (k < line.size() && line[k] == '_') return true;
  }
  return false;
}

core::Vec in_program_units(core::Vec v, Units u) {
  const double k = mm_per_unit(u);
  for (std::size_t a = 0; a < core::kMaxAxes; ++a)
    if (detail::is_linear_axis(a)) v[a] /= k;
  return v;
}

void set_predefined_parameters(Parameters& params, const ModalState& st, const core::Vec& tool) {
  const auto set = [&](Predefined p, double v) { params.set_predefined(p, v); };
  const auto flag = [&](Predefined p, bool on) { params.set_predefined(p, on ? 1.0 : 0.0); };
  const core::Vec mach = in_program_units(tool, st.units);
  for (std::size_t a = 0; a < core::kMaxAxes; ++a)
    set(static_cast<Predefined>(static_cast<std::size_t>(Predefined::AbsX) + a), mach[a]);
  set(Predefined::MotionMode, motion_code10(st.motion));
  set(Predefined::Plane, plane_code10(st.plane));
  set(Predefined::Ccomp, st.comp == Comp::Left ? 410 : st.comp == Comp::Right ? 420 : 400);
  flag(Predefined::Metric, st.units == Units::Mm);
  flag(Predefined::Imperial, st.units == Units::Inch);
  flag(Predefined::Absolute, st.distance == Distance::Absolute);
  flag(Predefined::Incremental, st.distance == Distance::Incremental);
  flag(Predefined::InverseTime, st.feed_mode == FeedMode::InverseTime);
  flag(Predefined::UnitsPerMinute, st.feed_mode == FeedMode::PerMinute);
  flag(Predefined::UnitsPerRev, false);  // G95 is refused
  set(Predefined::CoordSystem, coord_system_code10(st.coord_system));
  bool offset = false;  // LinuxCNC: a tool length offset other than zero is in effect (G43 with a zero one: 0)
  for (const double t : st.tool.v) offset = offset || t != 0;
  flag(Predefined::ToolOffset, offset);
  flag(Predefined::RetractRPlane, st.retract == Retract::RPlane);
  flag(Predefined::RetractOldZ, st.retract == Retract::OldZ);
  flag(Predefined::SpindleRpmMode, !st.css);
  flag(Predefined::SpindleCssMode, st.css);
  flag(Predefined::IjkAbsoluteMode, st.arc_distance == Distance::Absolute);
  flag(Predefined::LatheDiameterMode, false);
  flag(Predefined::LatheRadiusMode, true);
  flag(Predefined::SpindleOn, st.spindle != SpindleDir::Stopped);
  flag(Predefined::SpindleCw, st.spindle == SpindleDir::Cw);
  flag(Predefined::Mist, st.mist);
  flag(Predefined::Flood, st.flood);
  flag(Predefined::SpeedOverride, st.feed_override);  // M48/M49 switch both
  flag(Predefined::FeedOverride, st.feed_override);
  set(Predefined::Feed, st.feed_word);
  set(Predefined::Rpm, st.spindle_speed);
  set(Predefined::CurrentTool, st.current_tool);
  set(Predefined::SelectedTool, st.selected_tool);
  set(Predefined::RemapLevel, 0);
  flag(Predefined::Task, true);  // the interpretation is what runs, not a preview
}

}  // namespace softmc::program::iso
