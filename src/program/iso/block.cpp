// Block check: one block's words sorted into modal groups and values, checked on their own.
#include "program/iso/block.hpp"

#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

namespace softmc::program::iso {
namespace {

// RS274 modal groups, named as in the "two ... codes in one block" messages. At most one code of
// each group may appear in a block (LinuxCNC's rule; group 0 holds the non-modal codes).
enum class Group : std::uint8_t {
  NonModal, Motion, Plane, Distance, ArcDistance, FeedMode, Units, CutterComp, ToolLength, CoordSystem,
  Stop, Spindle, Count
};

const char* group_name(Group g) {
  switch (g) {
    case Group::NonModal: return "non-modal";
    case Group::Motion: return "motion";
    case Group::Plane: return "plane selection";
    case Group::Distance: return "distance mode";
    case Group::ArcDistance: return "arc distance mode";
    case Group::FeedMode: return "feed rate mode";
    case Group::Units: return "units";
    case Group::CutterComp: return "cutter compensation";
    case Group::ToolLength: return "tool length offset";
    case Group::CoordSystem: return "coordinate system";
    case Group::Stop: return "program stop";
    case Group::Spindle: return "spindle";
    case Group::Count: break;
  }
  return "?";
}

// The code already seen in each group of this block, by name, for the conflict message.
using GroupSeen = std::array<std::optional<std::string>, static_cast<std::size_t>(Group::Count)>;

std::optional<LineError> claim(GroupSeen& seen, Group g, std::string name, std::uint32_t col) {
  auto& slot = seen[static_cast<std::size_t>(g)];
  if (slot) return LineError{col, fmt::format("two {} codes in one block: {} and {}", group_name(g), *slot, name)};
  slot = std::move(name);
  return std::nullopt;
}

std::optional<LineError> apply_g(const Word& w, Block& b, GroupSeen& seen) {
  const double tenths = w.value * 10.0;
  const long long code10 = std::llround(tenths);
  if (std::fabs(tenths - static_cast<double>(code10)) > 1e-6)
    return LineError{w.col, fmt::format("malformed G code G{}: at most one decimal place", w.value)};
  const std::string name = g_code_name(code10);
  Group group = Group::NonModal;
  switch (code10) {
    case 0: group = Group::Motion; b.motion = At<Motion>{Motion::Rapid, w.col}; break;
    case 10: group = Group::Motion; b.motion = At<Motion>{Motion::Linear, w.col}; break;
    case 20: group = Group::Motion; b.motion = At<Motion>{Motion::ArcCw, w.col}; break;
    case 30: group = Group::Motion; b.motion = At<Motion>{Motion::ArcCcw, w.col}; break;
    case 800: group = Group::Motion; b.motion = At<Motion>{Motion::None, w.col}; break;
    case 40: group = Group::NonModal; b.dwell_col = w.col; break;
    case 170: group = Group::Plane; b.plane = At<Plane>{Plane::XY, w.col}; break;
    case 180: return LineError{w.col, "G18 (XZ plane) is not supported yet: only G17 (XY plane)"};
    case 190: return LineError{w.col, "G19 (YZ plane) is not supported yet: only G17 (XY plane)"};
    case 200: group = Group::Units; b.units = At<Units>{Units::Inch, w.col}; break;
    case 210: group = Group::Units; b.units = At<Units>{Units::Mm, w.col}; break;
    case 900: group = Group::Distance; b.distance = At<Distance>{Distance::Absolute, w.col}; break;
    case 910: group = Group::Distance; b.distance = At<Distance>{Distance::Incremental, w.col}; break;
    case 901: group = Group::ArcDistance; b.arc_distance = At<Distance>{Distance::Absolute, w.col}; break;
    case 911: group = Group::ArcDistance; b.arc_distance = At<Distance>{Distance::Incremental, w.col}; break;
    case 930: return LineError{w.col, "G93 (inverse time feed) is not supported yet: only G94 (units per minute)"};
    // The codes below select the only state this interpreter has; CAM preambles program them, so
    // they are accepted (and still take their group's place in the block).
    case 940: group = Group::FeedMode; break;      // feed in units per minute
    case 400: group = Group::CutterComp; break;    // cutter compensation off
    case 490: group = Group::ToolLength; break;    // tool length offset off
    case 540: group = Group::CoordSystem; break;   // coordinate system 1, whose offsets are zero
    default: return LineError{w.col, fmt::format("unsupported G code {}", name)};
  }
  return claim(seen, group, name, w.col);
}

std::optional<LineError> apply_m(const Word& w, Block& b, GroupSeen& seen) {
  const long long n = std::llround(w.value);
  if (std::fabs(w.value - static_cast<double>(n)) > 1e-9 || n < 0)
    return LineError{w.col, fmt::format("malformed M code M{}: M codes are whole numbers", w.value)};
  const std::string name = fmt::format("M{}", n);
  switch (n) {
    case 2:
    case 30:
      b.m_stop = At<int>{static_cast<int>(n), w.col};
      return claim(seen, Group::Stop, name, w.col);
    case 3:
    case 4:
    case 5:
      b.m_spindle = At<int>{static_cast<int>(n), w.col};
      return claim(seen, Group::Spindle, name, w.col);
    default:
      return LineError{w.col, fmt::format("unsupported M code {}", name)};
  }
}

// Letters that RS274 (LinuxCNC dialect) knows but this interpreter does not use yet.
std::optional<LineError> refuse_letter(const Word& w) {
  switch (w.letter) {
    case 'A':
    case 'B':
    case 'C': return LineError{w.col, fmt::format("rotary axis words ({}) are not supported yet", w.letter)};
    case 'K': return LineError{w.col, "K words are not supported: arcs lie in the XY plane (G17), whose centre is given by I and J"};
    case 'R': return LineError{w.col, "R-format arcs are not supported yet: give the arc centre with I and J"};
    case 'D':
    case 'H':
    case 'L':
    case 'O':
    case 'Q':
    case 'S':
    case 'T': return LineError{w.col, fmt::format("{} words are not supported yet", w.letter)};
    default: return LineError{w.col, fmt::format("unknown word letter {}", w.letter)};
  }
}

}  // namespace

bool Block::has_axes() const {
  for (const auto& a : axes)
    if (a) return true;
  return false;
}

std::uint32_t Block::first_axis_col() const {
  std::uint32_t col = 0;
  for (const auto& a : axes)
    if (a && (col == 0 || a->col < col)) col = a->col;
  return col;
}

std::string g_code_name(long long code10) {
  const char* sign = code10 < 0 ? "-" : "";
  const long long m = std::llabs(code10);
  if (m % 10 == 0) return fmt::format("G{}{}", sign, m / 10);
  return fmt::format("G{}{}.{}", sign, m / 10, m % 10);
}

std::optional<LineError> check_block(const std::vector<Word>& words, Block& out) {
  out = Block{};
  if (words.empty()) return std::nullopt;
  out.col = words.front().col;
  GroupSeen seen;
  std::array<bool, 26> letter_seen{};
  for (std::size_t k = 0; k < words.size(); ++k) {
    const Word& w = words[k];
    if (w.letter == 'G') {
      if (auto e = apply_g(w, out, seen)) return e;
      continue;
    }
    if (w.letter == 'M') {
      if (auto e = apply_m(w, out, seen)) return e;
      continue;
    }
    if (w.letter < 'A' || w.letter > 'Z') return LineError{w.col, "unknown word"};  // the lexer never makes one
    bool& seen_before = letter_seen[static_cast<std::size_t>(w.letter - 'A')];
    if (seen_before) return LineError{w.col, fmt::format("two {} words in one block", w.letter)};
    seen_before = true;
    switch (w.letter) {
      case 'N':
        // RS274: the line number comes first; its value is a label only.
        if (k != 0) return LineError{w.col, "line number (N word) must be the first word of the block"};
        if (w.value < 0 || w.value != std::floor(w.value))
          return LineError{w.col, "line number (N word) must be a whole number, 0 or more"};
        break;
      case 'F':
        if (!(w.value > 0)) return LineError{w.col, "feed rate must be greater than zero"};
        out.f = At<double>{w.value, w.col};
        break;
      case 'P': out.p = At<double>{w.value, w.col}; break;
      case 'I': out.i = At<double>{w.value, w.col}; break;
      case 'J': out.j = At<double>{w.value, w.col}; break;
      case 'X':
      case 'Y':
      case 'Z':
      case 'U':
      case 'V':
      case 'W': out.axes[*core::axis_from_letter(w.letter)] = At<double>{w.value, w.col}; break;
      default: return refuse_letter(w);
    }
  }
  return std::nullopt;
}

}  // namespace softmc::program::iso
