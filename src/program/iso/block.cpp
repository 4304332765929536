// Block check: one block's words sorted into modal groups and values, checked on their own.
#include "program/iso/block.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

namespace softmc::program::iso {
namespace {

// RS274 modal groups, named as in the "two ... codes in one block" messages. At most one code of
// each group may appear in a block (LinuxCNC's rule; group 0 holds the non-modal codes).
enum class Group : std::uint8_t {
  NonModal, Motion, Plane, Distance, ArcDistance, FeedMode, Units, CutterComp, ToolLength, Retract, CoordSystem,
  PathControl, SpindleMode, Count
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
    case Group::Retract: return "canned cycle return";
    case Group::CoordSystem: return "coordinate system";
    case Group::PathControl: return "path control";
    case Group::SpindleMode: return "spindle speed mode";
    case Group::Count: break;
  }
  return "?";
}

// The code already seen in each group of this block (ten times its number), for the message.
using GroupSeen = std::array<long long, static_cast<std::size_t>(Group::Count)>;

std::optional<LineError> claim(GroupSeen& seen, Group g, long long code10, std::uint32_t col) {
  auto& slot = seen[static_cast<std::size_t>(g)];
  if (slot >= 0)
    return LineError{col, fmt::format("two {} codes in one block: {} and {}", group_name(g), g_code_name(slot),
                                      g_code_name(code10))};
  slot = code10;
  return std::nullopt;
}

std::optional<LineError> refuse_g(long long code10, std::uint32_t col) {
  switch (code10) {
    case 330:
    case 331:
    case 760:
      return LineError{col, fmt::format("{} (spindle-synchronised motion) is not supported: the machine has no spindle "
                                        "feedback", g_code_name(code10))};
    case 950:
      return LineError{col, "G95 (feed per revolution) is not supported: the machine has no spindle feedback"};
    case 382: case 383: case 384: case 385:
      return LineError{col, fmt::format("{} (probing) is not supported: the machine has no probe input", g_code_name(code10))};
    case 70:
    case 80: return LineError{col, fmt::format("{} (lathe diameter/radius mode) is not supported", g_code_name(code10))};
    case 171: case 181: case 191:
      return LineError{col, fmt::format("{} (UVW planes) is not supported: use G17, G18 or G19", g_code_name(code10))};
    case 432: return LineError{col, "G43.2 (additional tool offset) is not supported"};
    case 520: return LineError{col, "G52 (local offset) is not supported: use G92"};
    default: break;
  }
  return LineError{col, fmt::format("unsupported G code {}", g_code_name(code10))};
}

std::optional<LineError> apply_g(const Word& w, Block& b, GroupSeen& seen) {
  const double tenths = w.value * 10.0;
  const long long code10 = std::llround(tenths);
  if (std::fabs(tenths - static_cast<double>(code10)) > 1e-6)
    return LineError{w.col, fmt::format("malformed G code G{}: at most one decimal place", w.value)};
  Group group = Group::NonModal;
  const auto motion_before = b.motion;
  auto motion = [&](Motion m) {
    group = Group::Motion;
    b.motion = At<Motion>{m, w.col};
  };
  switch (code10) {
    case 0: motion(Motion::Rapid); break;
    case 10: motion(Motion::Linear); break;
    case 20: motion(Motion::ArcCw); break;
    case 30: motion(Motion::ArcCcw); break;
    case 50: motion(Motion::CubicSpline); break;
    case 51: motion(Motion::QuadSpline); break;
    case 52: motion(Motion::Nurbs); break;
    case 53: group = Group::Motion; b.nurbs_end = w.col; break;
    case 730: motion(Motion::Drill73); break;
    case 800: motion(Motion::None); break;
    case 810: motion(Motion::Drill81); break;
    case 820: motion(Motion::Drill82); break;
    case 830: motion(Motion::Drill83); break;
    case 850: motion(Motion::Bore85); break;
    case 860: motion(Motion::Bore86); break;
    case 890: motion(Motion::Bore89); break;
    case 740: motion(Motion::Tap74); break;
    case 840: motion(Motion::Tap84); break;
    case 870: motion(Motion::BackBore87); break;
    case 880: motion(Motion::Bore88); break;
    case 40: case 100: case 280: case 281: case 300: case 301: case 920: case 921: case 922: case 923:
      b.non_modal = At<int>{static_cast<int>(code10), w.col};
      break;
    case 530: b.g53_col = w.col; break;
    case 170: group = Group::Plane; b.plane = At<Plane>{Plane::XY, w.col}; break;
    case 180: group = Group::Plane; b.plane = At<Plane>{Plane::XZ, w.col}; break;
    case 190: group = Group::Plane; b.plane = At<Plane>{Plane::YZ, w.col}; break;
    case 200: group = Group::Units; b.units = At<Units>{Units::Inch, w.col}; break;
    case 210: group = Group::Units; b.units = At<Units>{Units::Mm, w.col}; break;
    case 900: group = Group::Distance; b.distance = At<Distance>{Distance::Absolute, w.col}; break;
    case 910: group = Group::Distance; b.distance = At<Distance>{Distance::Incremental, w.col}; break;
    case 901: group = Group::ArcDistance; b.arc_distance = At<Distance>{Distance::Absolute, w.col}; break;
    case 911: group = Group::ArcDistance; b.arc_distance = At<Distance>{Distance::Incremental, w.col}; break;
    case 930: group = Group::FeedMode; b.feed_mode = At<FeedMode>{FeedMode::InverseTime, w.col}; break;
    case 940: group = Group::FeedMode; b.feed_mode = At<FeedMode>{FeedMode::PerMinute, w.col}; break;
    case 400: case 410: case 411: case 420: case 421:
      group = Group::CutterComp;
      b.comp = At<int>{static_cast<int>(code10), w.col};
      break;
    case 430: case 431: case 490:
      group = Group::ToolLength;
      b.tool_length = At<int>{static_cast<int>(code10), w.col};
      break;
    case 980: group = Group::Retract; b.retract = At<Retract>{Retract::OldZ, w.col}; break;
    case 990: group = Group::Retract; b.retract = At<Retract>{Retract::RPlane, w.col}; break;
    case 540: case 550: case 560: case 570: case 580: case 590: case 591: case 592: case 593: {
      group = Group::CoordSystem;
      const int n = code10 <= 590 ? static_cast<int>((code10 - 540) / 10 + 1) : static_cast<int>(code10 - 591 + 7);
      b.coord_system = At<int>{n, w.col};
      break;
    }
    case 610: case 611: case 640: case 230:
      group = Group::PathControl;
      b.path = At<int>{static_cast<int>(code10), w.col};
      break;
    case 960: case 970:
      group = Group::SpindleMode;
      b.spindle_mode = At<int>{static_cast<int>(code10), w.col};
      break;
    default: return refuse_g(code10, w.col);
  }
  if (group == Group::Motion) {
    // LinuxCNC read_g: "This allows G80 on the same line as one other g_code with the same mode. If
    // this happens, the G80 is simply ignored" (CAM safety lines such as G0 G17 G40 G49 G80 G90); a
    // second G80 is ignored the same way.
    auto& slot = seen[static_cast<std::size_t>(Group::Motion)];
    if (code10 == 800 && slot >= 0) {
      b.motion = motion_before;
      return std::nullopt;
    }
    if (slot == 800 && code10 != 800) {
      slot = -1;
      if (code10 == 53) b.motion.reset();  // G5.3 names no motion of its own
    }
  }
  return claim(seen, group, code10, w.col);
}

// M codes: the P-10 groups decide conflicts; group 14 ("everything else") does not conflict,
// except M62…M68 among themselves (one I/O operation per block, as LinuxCNC). M7 with M8 is
// allowed (both coolants, LinuxCNC), as the P-10 value M17 says.
std::optional<LineError> apply_m(const Word& w, const MTable& mt, Block& b) {
  const long long n = std::llround(w.value);
  if (std::fabs(w.value - static_cast<double>(n)) > 1e-9 || n < 0)
    return LineError{w.col, fmt::format("malformed M code M{}: M codes are whole numbers", w.value)};
  if (n > kMaxMNumber) return LineError{w.col, fmt::format("unknown M code M{} (M0 … M{})", n, kMaxMNumber)};
  switch (n) {
    case 70: case 71: case 72: case 73:  // the parser runs them before the block is checked (modal_state_m)
      return LineError{w.col, fmt::format("M{} (save/restore modal state) stands alone on its line", n)};
    case 98:  // the parser runs it before the block is checked (call_m98)
      return LineError{w.col, "M98 stands alone on its line, with P and L"};
    case 99:
      return LineError{w.col, "M99 outside a subprogram: M99 ends a subprogram (a line O<n> after the main program's "
                              "first block, its blocks, then M99) that M98 P<n> calls; an M99 that repeats the main "
                              "program for ever is not supported"};
    default: break;
  }
  const int num = static_cast<int>(n);
  const int group = mt.get(num).group;
  const bool io = num >= 62 && num <= 68;
  for (std::size_t k = 0; k < b.m_count; ++k) {
    const auto& o = b.m[k];
    const bool o_io = o.number >= 62 && o.number <= 68;
    const bool coolant_pair = (o.number == 7 && num == 8) || (o.number == 8 && num == 7);
    if (((group == o.group && group != kMOtherGroup) || (io && o_io)) && !coolant_pair)
      return LineError{w.col, fmt::format("two M codes of group {} in one block: M{} and M{}", io ? 14 : group, o.number, num)};
  }
  if (b.m_count == Block::kMaxM) return LineError{w.col, "too many M codes in one block"};
  b.m[b.m_count++] = Block::MCode{num, group, w.col};
  return std::nullopt;
}

}  // namespace

bool Block::has_axes() const {
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (has(core::letter(i))) return true;
  return false;
}

std::uint32_t Block::first_axis_col() const {
  std::uint32_t col = 0;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    const auto& a = word(core::letter(i));
    if (a && (col == 0 || a->col < col)) col = a->col;
  }
  return col;
}

int Block::axis_words_code() const {
  if (tool_length && tool_length->value == 431) return 431;
  if (non_modal) switch (non_modal->value) {
      case 100: case 280: case 300: case 920: return non_modal->value;
      default: break;
    }
  return 0;
}

std::uint32_t Block::first_polar_col() const {
  if (polar_radius && polar_angle) return std::min(polar_radius->col, polar_angle->col);
  return polar_radius ? polar_radius->col : polar_angle ? polar_angle->col : 0;
}

std::uint32_t Block::first_position_col() const {
  const std::uint32_t a = first_axis_col(), p = first_polar_col();
  if (a == 0 || p == 0) return a + p;
  return std::min(a, p);
}

const Block::MCode* Block::m_code(int number) const {
  for (std::size_t k = 0; k < m_count; ++k)
    if (m[k].number == number) return &m[k];
  return nullptr;
}

std::string g_code_name(long long code10) {
  const char* sign = code10 < 0 ? "-" : "";
  const long long m = std::llabs(code10);
  if (m % 10 == 0) return fmt::format("G{}{}", sign, m / 10);
  return fmt::format("G{}{}.{}", sign, m / 10, m % 10);
}

std::optional<LineError> check_block(const std::vector<Word>& words, const MTable& mtable, Block& out) {
  out = Block{};
  if (words.empty()) return std::nullopt;
  out.col = words.front().col;
  GroupSeen seen;
  seen.fill(-1);
  std::uint32_t g53_or_nonmodal = 0;
  for (std::size_t k = 0; k < words.size(); ++k) {
    const Word& w = words[k];
    if (w.letter == 'G') {
      const auto before = out.non_modal;
      const bool had53 = out.g53_col.has_value();
      if (auto e = apply_g(w, out, seen)) return e;
      // G53 and the other group-0 codes share group 0.
      const bool now_nm = (out.non_modal && !before) || (out.g53_col && !had53);
      if (now_nm) {
        if (g53_or_nonmodal)
          return LineError{w.col, fmt::format("two non-modal codes in one block: {} and {}", g_code_name(g53_or_nonmodal),
                                              g_code_name(std::llround(w.value * 10)))};
        g53_or_nonmodal = static_cast<std::uint32_t>(std::llround(w.value * 10));
        if (g53_or_nonmodal == 0) g53_or_nonmodal = 1;  // never happens (G0 is group 1); keeps 0 = none
      }
      continue;
    }
    if (w.letter == 'M') {
      if (auto e = apply_m(w, mtable, out)) return e;
      continue;
    }
    if (w.letter == '@' || w.letter == '^') {
      // LinuxCNC 2.9 silently keeps the last of two @ (or ^) words; like any other word, softmc refuses it.
      auto& polar = w.letter == '@' ? out.polar_radius : out.polar_angle;
      if (polar) return LineError{w.col, fmt::format("two {} words in one block", w.letter)};
      polar = At<double>{w.value, w.col};
      continue;
    }
    if (w.letter < 'A' || w.letter > 'Z') return LineError{w.col, "unknown word"};  // the lexer never makes one
    auto& slot = out.words[static_cast<std::size_t>(w.letter - 'A')];
    if (slot) return LineError{w.col, fmt::format("two {} words in one block", w.letter)};
    switch (w.letter) {
      case 'N':
        // RS274: the line number comes first; its value is a label only.
        if (k != 0) return LineError{w.col, "line number (N word) must be the first word of the block"};
        // LinuxCNC's read_n_number accepts and ignores a fraction (N20.5).
        if (w.value < 0) return LineError{w.col, "line number (N word) must be 0 or more"};
        break;
      case 'F':
        // F0 is a feed rate like any other until a feed move needs it (LinuxCNC: "Cannot do g1 with
        // zero feed rate" at the move); a negative one is refused where it stands.
        if (w.value < 0) return LineError{w.col, "feed rate (F) must be 0 or more"};
        break;
      case 'S':
        if (w.value < 0) return LineError{w.col, "spindle speed (S) must be 0 or more"};
        break;
      case 'T':
        if (w.value < 0 || w.value != std::floor(w.value)) return LineError{w.col, "tool number (T) must be a whole number, 0 or more"};
        break;
      case 'D': case 'E': case 'H': case 'I': case 'J': case 'K': case 'L': case 'P': case 'Q': case 'R':
      case 'X': case 'Y': case 'Z': case 'A': case 'B': case 'C': case 'U': case 'V': case 'W':
        break;
      default: return LineError{w.col, fmt::format("unknown word letter {}", w.letter)};
    }
    slot = At<double>{w.value, w.col};
  }
  return std::nullopt;
}

}  // namespace softmc::program::iso
