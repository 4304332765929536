// Canonical text dump of a Program: stable formatting so golden files compare byte for byte.
#include <fmt/format.h>

#include "program/ir/program.hpp"

namespace softmc::program {
namespace {

// Axes that differ from zero or were ever non-zero are printed; here: all axes in the mask of used axes.
std::string fmt_vec(const Vec& v, AxisMask used) {
  std::string s;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    if (!(used & core::axis_bit(i))) continue;
    if (!s.empty()) s += ' ';
    s += fmt::format("{}{:.6f}", core::letter(i), v[i]);
  }
  return s;
}

AxisMask used_axes(const Program& p) {
  AxisMask m = 0b111;  // X Y Z always
  auto note = [&](const Vec& v) {
    for (std::size_t i = 3; i < core::kMaxAxes; ++i)
      if (v[i] != 0.0) m |= core::axis_bit(i);
  };
  note(p.start);
  for (const auto& ins : p.instructions) {
    if (auto* r = std::get_if<Rapid>(&ins.op)) note(r->end);
    if (auto* l = std::get_if<Linear>(&ins.op)) note(l->end);
    if (auto* a = std::get_if<Arc>(&ins.op)) note(a->end);
    if (auto* b = op_if<Bezier>(ins.op)) note(b->end);
  }
  return m;
}

}  // namespace

std::string dump(const Program& p) {
  const AxisMask used = used_axes(p);
  std::string out = fmt::format("start {}\n", fmt_vec(p.start, used));
  for (const auto& ins : p.instructions) {
    out += fmt::format("{:>5}:{:<3} ", ins.loc.line, ins.loc.col);
    std::visit(
        [&](const auto& alt) {
          const auto& op = program::unboxed(alt);  // a Boxed payload as itself
          using T = std::decay_t<decltype(op)>;
          if constexpr (std::is_same_v<T, Rapid>) {
            out += fmt::format("rapid {}", fmt_vec(op.end, used));
          } else if constexpr (std::is_same_v<T, Linear>) {
            out += fmt::format("feed {} F{:.6f}", fmt_vec(op.end, used), op.feed_mm_s);
          } else if constexpr (std::is_same_v<T, Arc>) {
            out += fmt::format("arc {} C{}{:.6f},{}{:.6f} N{} turns {} F{:.6f}", fmt_vec(op.end, used),
                               core::letter(op.axis0), op.center0, core::letter(op.axis1), op.center1,
                               core::letter(op.normal), op.turns, op.feed_mm_s);
          } else if constexpr (std::is_same_v<T, Dwell>) {
            out += fmt::format("dwell {:.6f}", op.seconds);
          } else if constexpr (std::is_same_v<T, ToolSwitch>) {
            out += op.on ? "tool on" : "tool off";
          } else if constexpr (std::is_same_v<T, MFunction>) {
            out += fmt::format("m {}", op.number);
          } else if constexpr (std::is_same_v<T, ProgramEnd>) {
            out += op.rewind ? "end rewind" : "end";
          } else if constexpr (requires { iso_text(op); }) {  // ISO payloads (program/iso/dump_ops.cpp)
            out += iso_text(op);
          } else if constexpr (requires { spc_text(op); }) {  // SPC payloads (program/spc/dump_ops.cpp)
            out += spc_text(op);
          }
        },
        ins.op);
    out += '\n';
  }
  return out;
}

}  // namespace softmc::program
