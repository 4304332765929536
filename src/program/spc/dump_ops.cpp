// Canonical dump text of the SPC payloads: close to the source syntax, fixed formatting.
#include <fmt/format.h>

#include "program/ir/spc_ops.hpp"

namespace softmc::program {
namespace {

std::string pos_text(const SpcPos& p) {
  if (p.is_reg) return fmt::format("@{}", p.reg);
  const std::int32_t a = p.centi < 0 ? -p.centi : p.centi;
  return fmt::format("{}{}.{:02}", p.centi < 0 ? "-" : "", a / 100, a % 100);
}

std::string bit_text(const SpcBit& b) {
  switch (b.space) {
    case SpcBitSpace::Input: return fmt::format("I{}.{}", b.module, b.bit);
    case SpcBitSpace::Output: return fmt::format("Q{}.{}", b.module, b.bit);
    case SpcBitSpace::Flag: return fmt::format("F{}", b.bit);
  }
  return "?";
}

std::string target_text(std::uint16_t line, std::int32_t index) { return fmt::format("N{:03} (#{})", line, index); }

}  // namespace

std::string spc_text(const SpcMove& op) {
  static constexpr const char* kProfile[] = {"G00", "G01", "G02"};
  static constexpr const char* kCoord[] = {"", " G90", " G91"};
  std::string s = fmt::format("spc move {}{}", kProfile[static_cast<int>(op.profile)], kCoord[static_cast<int>(op.coord)]);
  for (std::size_t a = 0; a < kSpcAxes; ++a) {
    if (!(op.axes & (1u << a))) continue;
    s += fmt::format(" {}{}", kSpcAxisLetters[a], pos_text(op.target[a]));
    if (op.profile != SpcProfile::Rapid) s += fmt::format(" F{}{}", kSpcAxisLetters[a], op.speed_pct[a]);
  }
  return s;
}

std::string spc_text(const SpcAxisSetting& op) {
  static constexpr const char* kKind[] = {"G08 accel", "G09 decel", "G25 pass", "G61 complete", "M37 mass"};
  std::string s = fmt::format("spc {}", kKind[static_cast<int>(op.kind)]);
  for (std::size_t a = 0; a < kSpcAxes; ++a)
    if (op.axes & (1u << a)) s += fmt::format(" {}{}", kSpcAxisLetters[a], op.value[a]);
  return s;
}

std::string spc_text(const SpcDwell& op) { return fmt::format("spc dwell {}cs", op.hundredths); }
std::string spc_text(const SpcJump& op) {
  return op.via_reg ? fmt::format("spc jump R{}", op.reg) : fmt::format("spc jump {}", target_text(op.line, op.index));
}
std::string spc_text(const SpcCall& op) {
  return op.via_reg ? fmt::format("spc call R{}", op.reg) : fmt::format("spc call P{}", op.program);
}
std::string spc_text(const SpcReturn&) { return "spc return"; }
std::string spc_text(const SpcEnd&) { return "spc end"; }
std::string spc_text(const SpcSync&) { return "spc sync"; }

std::string spc_text(const SpcPosReg& op) {
  static constexpr const char* kOp[] = {"G28 load", "G29 add", "M38 capture"};
  std::string s = fmt::format("spc {} @{}", kOp[static_cast<int>(op.op)], op.reg);
  for (std::size_t a = 0; a < kSpcAxes; ++a) {
    if (!(op.axes & (1u << a))) continue;
    s += fmt::format(" {}", kSpcAxisLetters[a]);
    if (op.op != SpcPosRegOp::Capture) s += pos_text(op.value[a]);
  }
  return s;
}

std::string spc_text(const SpcIntReg& op) {
  switch (op.op) {
    case SpcIntRegOp::Load: return fmt::format("spc R{} = {}", op.reg, op.value);
    case SpcIntRegOp::Add: return fmt::format("spc R{} += {}", op.reg, op.value);
    case SpcIntRegOp::Test: return fmt::format("spc if R{} == {} jump {}", op.reg, op.value, target_text(op.line, op.index));
  }
  return "?";
}

std::string spc_text(const SpcBitTest& op) {
  return fmt::format("spc if {} == {} jump {}", bit_text(op.bit), op.jump_when ? 1 : 0, target_text(op.line, op.index));
}
std::string spc_text(const SpcBitWrite& op) { return fmt::format("spc {} = {}", bit_text(op.bit), op.value ? 1 : 0); }

}  // namespace softmc::program
