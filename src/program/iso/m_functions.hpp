// M functions of plc_interface.md P-10: groups, last value per group, change bits and decoded bits.
//
// The interpreter uses the group table to refuse two M functions of one group in a block (naming
// both) and records the group in each MFunction of the IR; the PLC side keeps an MGroupState and
// applies every block's M functions to it to publish values, change bits and decoded bits.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace softmc::program::iso {

inline constexpr int kMGroups = 14;        // groups 1..14
inline constexpr int kMOtherGroup = 14;    // "everything else"
inline constexpr int kMaxMNumber = 199;    // M0..M199 (P-10 configures 0..100; LinuxCNC's user M100..M199)

// Configuration of one M function (P-10): group and path/position flags.
struct MConfig {
  int number = 0;
  int group = kMOtherGroup;
  bool breaks_path_at_start = false;
  bool breaks_path_at_end = false;
  bool changes_position = false;
};

// The fixed P-10 table plus user entries (free groups 4 and 10..13, or flags of fixed ones).
class MTable {
 public:
  MTable();  // the fixed functions only
  // Adds or overrides an entry. Fixed functions cannot leave their group: false then.
  bool configure(const MConfig& c);
  const MConfig& get(int number) const;  // numbers outside 0..kMaxMNumber: group 14, no flags
  static bool is_fixed(int number);

 private:
  std::array<MConfig, kMaxMNumber + 1> table_{};
  MConfig other_{};
};

// Decoded static bits (P-10) and per-group values, as the PLC sees them.
struct MGroupState {
  std::array<int, kMGroups + 1> value{};        // last M number per group (index 1..14), -1 = none yet
  std::array<bool, kMGroups + 1> changed{};     // set for the block that programmed the group
  bool m3 = false, m4 = false, m19 = false;     // spindle (M5 clears all three)
  int gear = 0;                                 // 1..4 from M41..M44, 0 = automatic (M40) or none
  bool coolant1 = false, coolant2 = false;      // M7 → 10, M8 → 01, M9 → 00, M17 → 11
  bool m50_1 = false, m50_2 = false;            // M50 → 10, M51 → 01, M52 → 11, M53 → 00
  bool feed_override_enabled = true;            // M48 on / M49 off
  // Dynamic (one block) bits.
  bool m10 = false, m11 = false, m6 = false, m60 = false, m0 = false, m1 = false, m2 = false, m30 = false;

  MGroupState() { value.fill(-1); }
  // Starts a new block: change bits and dynamic bits fall.
  void begin_block();
  // Applies one M function of the block (its group from `table`).
  void apply(int number, const MTable& table);
};

}  // namespace softmc::program::iso
