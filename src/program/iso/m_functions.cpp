// M functions of plc_interface.md P-10: groups, last value per group, change bits and decoded bits.
#include "program/iso/m_functions.hpp"

namespace softmc::program::iso {
namespace {

// P-10: 1 = M00 M01 M02 M30; 2 = M03 M04 M05 M19; 3 = M41..M44 M40; 5 = M07 M08 M09 M17;
// 6 = M50..M53; 7 = M10 M11; 8 = M48 M49; 9 = M06 M60.
int fixed_group(int n) {
  switch (n) {
    case 0: case 1: case 2: case 30: return 1;
    case 3: case 4: case 5: case 19: return 2;
    case 40: case 41: case 42: case 43: case 44: return 3;
    case 7: case 8: case 9: case 17: return 5;
    case 50: case 51: case 52: case 53: return 6;
    case 10: case 11: return 7;
    case 48: case 49: return 8;
    case 6: case 60: return 9;
    default: return 0;
  }
}

}  // namespace

MTable::MTable() {
  for (int n = 0; n <= kMaxMNumber; ++n) {
    auto& c = table_[static_cast<std::size_t>(n)];
    c.number = n;
    const int g = fixed_group(n);
    c.group = g ? g : kMOtherGroup;
    // Stops, tool change and program end break the continuous path at the end of their block.
    c.breaks_path_at_end = g == 1 || g == 9;
    c.changes_position = n == 6 || n == 60;
  }
  other_.group = kMOtherGroup;
}

bool MTable::is_fixed(int number) { return fixed_group(number) != 0; }

bool MTable::configure(const MConfig& c) {
  if (c.number < 0 || c.number > kMaxMNumber || c.group < 1 || c.group > kMGroups) return false;
  const int g = fixed_group(c.number);
  if (g && c.group != g) return false;
  // Free groups for user functions: 4 and 10..13 (and 14, the default).
  if (!g && !(c.group == 4 || c.group >= 10)) return false;
  table_[static_cast<std::size_t>(c.number)] = c;
  return true;
}

const MConfig& MTable::get(int number) const {
  if (number < 0 || number > kMaxMNumber) return other_;
  return table_[static_cast<std::size_t>(number)];
}

void MGroupState::begin_block() {
  changed.fill(false);
  m10 = m11 = m6 = m60 = m0 = m1 = m2 = m30 = false;
}

void MGroupState::apply(int n, const MTable& table) {
  const int g = table.get(n).group;
  value[static_cast<std::size_t>(g)] = n;
  changed[static_cast<std::size_t>(g)] = true;
  switch (n) {
    case 3: m3 = true; m4 = false; m19 = false; break;
    case 4: m4 = true; m3 = false; m19 = false; break;
    case 19: m19 = true; m3 = false; m4 = false; break;
    case 5: m3 = m4 = m19 = false; break;
    case 40: gear = 0; break;
    case 41: case 42: case 43: case 44: gear = n - 40; break;
    case 7: coolant1 = true; coolant2 = false; break;
    case 8: coolant1 = false; coolant2 = true; break;
    case 9: coolant1 = coolant2 = false; break;
    case 17: coolant1 = coolant2 = true; break;
    case 50: m50_1 = true; m50_2 = false; break;
    case 51: m50_1 = false; m50_2 = true; break;
    case 52: m50_1 = m50_2 = true; break;
    case 53: m50_1 = m50_2 = false; break;
    case 48: feed_override_enabled = true; break;
    case 49: feed_override_enabled = false; break;
    case 10: m10 = true; break;
    case 11: m11 = true; break;
    case 6: m6 = true; break;
    case 60: m60 = true; break;
    case 0: m0 = true; break;
    case 1: m1 = true; break;
    case 2: m2 = true; break;
    case 30: m30 = true; break;
    default: break;
  }
}

}  // namespace softmc::program::iso
