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
#include "program/iso/modes.hpp"

namespace softmc::program::iso {

// A value and the column of the word that gave it (for diagnostics that point at the word).
template <class T>
struct At {
  T value{};
  std::uint32_t col = 0;
};

// One block, checked on its own; values are still in program units (G20/G21 applies later, since
// the units of a block are those in effect after its own G20/G21).
struct Block {
  std::uint32_t col = 0;  // first word: the location of every instruction the block makes

  // G codes, one per modal group.
  std::optional<At<Motion>> motion;           // group 1: G0 G1 G2 G3 G80
  std::optional<At<Plane>> plane;             // group 2: G17
  std::optional<At<Distance>> distance;       // group 3: G90 G91
  std::optional<At<Distance>> arc_distance;   // group 4: G90.1 G91.1
  std::optional<At<Units>> units;             // group 6: G20 G21
  std::optional<std::uint32_t> dwell_col;     // group 0: G4

  // M codes, one per modal group.
  std::optional<At<int>> m_spindle;  // group 7: M3 M4 M5
  std::optional<At<int>> m_stop;     // group 4: M2 M30

  // Value words.
  std::array<std::optional<At<double>>, core::kMaxAxes> axes;  // linear axes only: X Y Z U V W
  std::optional<At<double>> i, j, f, p;

  bool has_axes() const;
  std::uint32_t first_axis_col() const;  // 0 when there is none
};

// Sorts the words of a block and checks what the block alone can tell: repeated words, two codes
// of one modal group, unknown codes and letters, N not first, F not positive. The first problem
// found, in word order, is returned; `out` is then incomplete. Rules that need the modal state
// (feed in effect, unused I/J/P, arc geometry) belong to the interpreter.
std::optional<LineError> check_block(const std::vector<Word>& words, Block& out);

// "G1", "G33.1", "G-2": a G number as written, from its value times ten.
std::string g_code_name(long long code10);

}  // namespace softmc::program::iso
