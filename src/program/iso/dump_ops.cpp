// Canonical dump text of the ISO payloads of the IR (splines, modes, tool, I/O, messages).
#include <fmt/format.h>

#include "program/ir/program.hpp"

namespace softmc::program {
namespace {

// Every axis of a control point, so that splines in any plane print alike.
std::string point(const core::Vec& v) {
  std::string s;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    if (i >= 3 && v[i] == 0.0) continue;
    if (!s.empty()) s += ' ';
    s += fmt::format("{}{:.6f}", core::letter(i), v[i]);
  }
  return s;
}

}  // namespace

std::string iso_text(const Bezier& op) {
  if (op.degree == 2)
    return fmt::format("bezier2 {} via {} P{}{} F{:.6f}", point(op.end), point(op.ctrl1), core::letter(op.axis0),
                       core::letter(op.axis1), op.feed_mm_s);
  return fmt::format("bezier3 {} via {} / {} P{}{} F{:.6f}", point(op.end), point(op.ctrl1), point(op.ctrl2),
                     core::letter(op.axis0), core::letter(op.axis1), op.feed_mm_s);
}

std::string iso_text(const Nurbs& op) {
  std::string s = fmt::format("nurbs order {} F{:.6f}", op.order, op.feed_mm_s);
  for (std::size_t i = 0; i < op.ctrl.size(); ++i)
    s += fmt::format(" [{} w{:.6f}]", point(op.ctrl[i]), i < op.weights.size() ? op.weights[i] : 1.0);
  return s;
}

std::string iso_text(const PathMode& op) {
  switch (op.kind) {
    case PathKind::ExactPath: return "path exact";
    case PathKind::ExactStop: return "path stop";
    case PathKind::Blend: break;
  }
  return fmt::format("path blend P{:.6f} Q{:.6f}{}", op.tolerance_mm, op.naive_tolerance_mm,
                     op.continuous ? " continuous" : "");
}

std::string iso_text(const SpindleSpeed& op) {
  if (op.css) return fmt::format("spindle css {:.6f} m/min max {:.6f}", op.surface_m_min, op.max_rpm);
  return fmt::format("spindle {:.6f} rpm", op.rpm);
}

std::string iso_text(const ToolSelect& op) { return fmt::format("tool select {}", op.tool); }
std::string iso_text(const ToolChange& op) { return fmt::format("tool change {}", op.tool); }
std::string iso_text(const Pause& op) { return op.optional ? "pause optional" : "pause"; }

std::string iso_text(const OffsetsChanged& op) {
  return fmt::format("offsets cs{} work {} axis {} tool {} R{:.6f}", op.coord_system, point(op.work), point(op.axis),
                     point(op.tool), op.rotation_deg);
}

std::string iso_text(const DigitalOutput& op) {
  return fmt::format("dout {} {}{}", op.index, op.on ? "on" : "off", op.synced ? " synced" : "");
}

std::string iso_text(const AnalogOutput& op) {
  return fmt::format("aout {} {:.6f}{}", op.index, op.value, op.synced ? " synced" : "");
}

std::string iso_text(const WaitInput& op) {
  return fmt::format("wait {} {} mode {} timeout {:.6f}", op.digital ? "din" : "ain", op.index, op.mode, op.timeout_s);
}

std::string iso_text(const Message& op) {
  const char* kind = op.kind == MessageKind::Msg ? "msg" : op.kind == MessageKind::Debug ? "debug" : "print";
  return fmt::format("{} \"{}\"", kind, op.text);
}

}  // namespace softmc::program
