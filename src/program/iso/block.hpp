// Block check: one block's words sorted into modal groups and values, checked on their own.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/axes.hpp"
#include "program/iso/lexer.hpp"
#include "program/iso/line_error.hpp"
#include "program/iso/m_functions.hpp"
#include "program/iso/modes.hpp"

namespace softmc::program::iso {

// A value and the column of the word that gave it (for diagnostics that point at the word).
template <class T>
struct At {
  T value{};
  std::uint32_t col = 0;
};

// One block, checked on its own; values are still in program units (G20/G21 applies later, since
// the units of a block are those in effect after its own G20/G21). G codes are kept as ten times
// their number (G92.1 = 921), one per modal group.
struct Block {
  std::uint32_t col = 0;  // first word: the location of every instruction the block makes

  std::optional<At<Motion>> motion;         // group 1: G0 G1 G2 G3 G5 G5.1 G5.2 G73 G80 G81 G82 G83 G85 G86 G89
  std::optional<std::uint32_t> nurbs_end;   // G5.3 (column)
  std::optional<At<Plane>> plane;           // group 2: G17 G18 G19
  std::optional<At<Distance>> distance;     // group 3: G90 G91
  std::optional<At<Distance>> arc_distance; // group 4: G90.1 G91.1
  std::optional<At<FeedMode>> feed_mode;    // group 5: G93 G94
  std::optional<At<Units>> units;           // group 6: G20 G21
  std::optional<At<int>> comp;              // group 7: G40 G41 G41.1 G42 G42.1
  std::optional<At<int>> tool_length;       // group 8: G43 G43.1 G49
  std::optional<At<Retract>> retract;       // group 10: G98 G99
  std::optional<At<int>> coord_system;      // group 12: G54 … G59.3 as 1 … 9
  std::optional<At<int>> path;              // group 13: G61 G61.1 G64 G23
  std::optional<At<int>> spindle_mode;      // group 14: G96 G97
  std::optional<At<int>> non_modal;         // group 0: G4 G10 G28 G28.1 G30 G30.1 G53 G92 G92.1 G92.2 G92.3
  std::optional<std::uint32_t> g53_col;     // G53 (also group 0)

  struct MCode {
    int number = 0;
    int group = 0;
    std::uint32_t col = 0;
  };
  static constexpr std::size_t kMaxM = 8;
  std::array<MCode, kMaxM> m{};  // in source order, at most one per group
  std::size_t m_count = 0;

  std::array<std::optional<At<double>>, 26> words;  // every other letter, by letter
  // LinuxCNC's polar coordinates in the G17 plane: @ radius (a length), ^ angle (degrees from +X).
  // They give X and Y in place of X and Y words.
  std::optional<At<double>> polar_radius;  // @
  std::optional<At<double>> polar_angle;   // ^

  const std::optional<At<double>>& word(char letter) const { return words[static_cast<std::size_t>(letter - 'A')]; }
  bool has(char letter) const { return word(letter).has_value(); }
  bool has_axes() const;
  std::uint32_t first_axis_col() const;  // 0 when there is none
  bool has_polar() const { return polar_radius || polar_angle; }
  std::uint32_t first_polar_col() const;  // 0 when there is none
  // Words that give an end point: axis words or polar coordinates.
  bool has_position() const { return has_axes() || has_polar(); }
  std::uint32_t first_position_col() const;  // 0 when there is none
  // The code that takes the block's axis words for itself rather than for a move (G10, G28, G30,
  // G92, G43.1; ten times its number), or 0.
  int axis_words_code() const;
  const MCode* m_code(int number) const;
};

// Sorts the words of a block and checks what the block alone can tell: repeated words, two codes
// of one modal group, unknown codes and letters, N not first, F not positive. The first problem
// found, in word order, is returned; `out` is then incomplete. Rules that need the modal state
// (feed in effect, unused words, arc geometry) belong to the interpreter.
std::optional<LineError> check_block(const std::vector<Word>& words, const MTable& mtable, Block& out);

// "G1", "G33.1", "G-2": a G number as written, from its value times ten.
std::string g_code_name(long long code10);

}  // namespace softmc::program::iso
