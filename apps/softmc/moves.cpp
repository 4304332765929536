// `softmc moves` writer: IR instructions → JSON Lines, fast enough to stream million-line programs.
#include "moves.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <type_traits>

namespace softmc::app {
namespace {

using Buf = fmt::memory_buffer;
using program::Instruction;
using program::Program;

// Shortest round-trip decimal; -0 prints as 0 so that dumps do not differ by the sign of zero.
void num(Buf& b, double v) {
  if (v == 0) v = 0;
  fmt::format_to(std::back_inserter(b), "{}", v);
}

void axes_obj(Buf& b, const char* key, const core::Vec& v, core::AxisMask axes) {
  fmt::format_to(std::back_inserter(b), ",\"{}\":{{", key);
  bool first = true;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    if (!(axes & core::axis_bit(i))) continue;
    if (!first) b.push_back(',');
    first = false;
    b.push_back('"');
    b.push_back(core::letter(i));
    b.append(std::string_view("\":"));
    num(b, v[i]);
  }
  b.push_back('}');
}

void key_num(Buf& b, const char* key, double v) {
  fmt::format_to(std::back_inserter(b), ",\"{}\":", key);
  num(b, v);
}

void key_int(Buf& b, const char* key, long long v) { fmt::format_to(std::back_inserter(b), ",\"{}\":{}", key, v); }

void key_bool(Buf& b, const char* key, bool v) {
  fmt::format_to(std::back_inserter(b), ",\"{}\":{}", key, v ? "true" : "false");
}

void key_str(Buf& b, const char* key, std::string_view s) {
  fmt::format_to(std::back_inserter(b), ",\"{}\":{}", key, nlohmann::json(std::string(s)).dump());
}

void type(Buf& b, std::string_view t) {
  b.append(std::string_view(",\"type\":\""));
  b.append(t);
  b.push_back('"');
}

void plane_key(Buf& b, std::uint8_t a0, std::uint8_t a1) {
  const char p[3] = {core::letter(a0), core::letter(a1), 0};
  key_str(b, "plane", p);
}

void write_one(Buf& b, const Program& prog, const Instruction& ins, core::AxisMask axes) {
  fmt::format_to(std::back_inserter(b), "{{\"line\":{},\"col\":{}", ins.loc.line, ins.loc.col);
  if (ins.loc.file != 0 && ins.loc.file < prog.files.size()) key_str(b, "file", prog.files[ins.loc.file]);
  std::visit(
      [&](const auto& op) {
        using T = std::decay_t<decltype(op)>;
        using namespace program;
        if constexpr (std::is_same_v<T, Rapid>) {
          type(b, "rapid");
          axes_obj(b, "end", op.end, axes);
        } else if constexpr (std::is_same_v<T, Linear>) {
          type(b, "feed");
          axes_obj(b, "end", op.end, axes);
          key_num(b, "feed_mm_s", op.feed_mm_s);
        } else if constexpr (std::is_same_v<T, Arc>) {
          type(b, "arc");
          axes_obj(b, "end", op.end, axes);
          fmt::format_to(std::back_inserter(b), ",\"center\":{{\"{}\":", core::letter(op.axis0));
          num(b, op.center0);
          fmt::format_to(std::back_inserter(b), ",\"{}\":", core::letter(op.axis1));
          num(b, op.center1);
          b.push_back('}');
          plane_key(b, op.axis0, op.axis1);
          key_str(b, "normal", std::string_view(&core::kAxisLetters[op.normal], 1));
          key_int(b, "turns", op.turns < 0 ? -static_cast<long long>(op.turns) : op.turns);
          key_str(b, "direction", op.turns < 0 ? "cw" : "ccw");
          key_num(b, "feed_mm_s", op.feed_mm_s);
        } else if constexpr (std::is_same_v<T, Bezier>) {
          type(b, "spline");
          axes_obj(b, "end", op.end, axes);
          key_int(b, "degree", op.degree);
          axes_obj(b, "control1", op.ctrl1, axes);
          if (op.degree == 3) axes_obj(b, "control2", op.ctrl2, axes);
          plane_key(b, op.axis0, op.axis1);
          key_num(b, "feed_mm_s", op.feed_mm_s);
        } else if constexpr (std::is_same_v<T, Nurbs>) {
          type(b, "nurbs");
          axes_obj(b, "end", op.ctrl.empty() ? core::Vec{} : op.ctrl.back(), axes);
          key_int(b, "order", op.order);
          b.append(std::string_view(",\"controls\":["));
          for (std::size_t i = 0; i < op.ctrl.size(); ++i) {
            if (i) b.push_back(',');
            Buf one;
            axes_obj(one, "p", op.ctrl[i], axes);
            b.append(std::string_view(one.data() + 5, one.size() - 5));  // drop `,"p":`
          }
          b.append(std::string_view("],\"weights\":["));
          for (std::size_t i = 0; i < op.weights.size(); ++i) {
            if (i) b.push_back(',');
            num(b, op.weights[i]);
          }
          b.push_back(']');
          key_num(b, "feed_mm_s", op.feed_mm_s);
        } else if constexpr (std::is_same_v<T, Dwell>) {
          type(b, "dwell");
          key_num(b, "seconds", op.seconds);
        } else if constexpr (std::is_same_v<T, ToolSwitch>) {
          type(b, "spindle");
          key_bool(b, "on", op.on);
        } else if constexpr (std::is_same_v<T, SpindleSpeed>) {
          type(b, "spindle_speed");
          key_num(b, "rpm", op.rpm);
          key_bool(b, "css", op.css);
          key_num(b, "surface_m_min", op.surface_m_min);
          key_num(b, "max_rpm", op.max_rpm);
        } else if constexpr (std::is_same_v<T, MFunction>) {
          type(b, "m");
          key_int(b, "number", op.number);
          key_int(b, "group", op.group);
        } else if constexpr (std::is_same_v<T, ToolSelect>) {
          type(b, "tool_select");
          key_int(b, "tool", op.tool);
        } else if constexpr (std::is_same_v<T, ToolChange>) {
          type(b, "tool_change");
          key_int(b, "tool", op.tool);
        } else if constexpr (std::is_same_v<T, Pause>) {
          type(b, "pause");
          key_bool(b, "optional", op.optional);
        } else if constexpr (std::is_same_v<T, PathMode>) {
          type(b, "path_mode");
          key_str(b, "mode", op.kind == PathKind::ExactPath   ? "exact_path"
                             : op.kind == PathKind::ExactStop ? "exact_stop"
                                                              : "blend");
          key_num(b, "tolerance_mm", op.tolerance_mm);
          key_num(b, "naive_tolerance_mm", op.naive_tolerance_mm);
          key_bool(b, "continuous", op.continuous);
        } else if constexpr (std::is_same_v<T, OffsetsChanged>) {
          type(b, "offsets");
          key_int(b, "coord_system", op.coord_system);
          axes_obj(b, "work", op.work, axes);
          axes_obj(b, "axis", op.axis, axes);
          axes_obj(b, "tool", op.tool, axes);
          key_num(b, "rotation_deg", op.rotation_deg);
        } else if constexpr (std::is_same_v<T, DigitalOutput>) {
          type(b, "digital_output");
          key_int(b, "index", op.index);
          key_bool(b, "on", op.on);
          key_bool(b, "synced", op.synced);
        } else if constexpr (std::is_same_v<T, WaitInput>) {
          type(b, "wait_input");
          key_int(b, "index", op.index);
          key_bool(b, "digital", op.digital);
          key_int(b, "mode", op.mode);
          key_num(b, "timeout_s", op.timeout_s);
        } else if constexpr (std::is_same_v<T, Message>) {
          type(b, "message");
          key_str(b, "kind", op.kind == MessageKind::Msg ? "msg" : op.kind == MessageKind::Debug ? "debug" : "print");
          key_str(b, "text", op.text);
        } else if constexpr (std::is_same_v<T, ProgramEnd>) {
          type(b, "end");
          key_bool(b, "rewind", op.rewind);
        } else if constexpr (requires { spc_text(op); }) {  // SPC payloads: their canonical text
          type(b, "spc");
          key_str(b, "text", spc_text(op));
        } else {
          type(b, "other");
          key_int(b, "op", static_cast<long long>(ins.op.index()));
        }
      },
      ins.op);
  b.append(std::string_view("}\n"));
}

}  // namespace

void write_moves(std::FILE* out, const Program& prog, core::AxisMask axes) {
  constexpr std::size_t kFlush = 64 * 1024;
  Buf b;
  for (const auto& ins : prog.instructions) {
    write_one(b, prog, ins, axes);
    if (b.size() >= kFlush) {
      std::fwrite(b.data(), 1, b.size(), out);
      b.clear();
    }
  }
  std::fwrite(b.data(), 1, b.size(), out);
}

std::string moves_jsonl(const Program& prog, core::AxisMask axes) {
  Buf b;
  for (const auto& ins : prog.instructions) write_one(b, prog, ins, axes);
  return fmt::to_string(b);
}

}  // namespace softmc::app
