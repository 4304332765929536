// The values of the RS274 modal groups this interpreter knows (one enum per group).
#pragma once

#include <cstdint>

namespace softmc::program::iso {

// Group 1. None after G80 and at program start: axis words then have no motion to drive.
enum class Motion : std::uint8_t { None, Rapid, Linear, ArcCw, ArcCcw };  // G80, G0, G1, G2, G3

// Group 2. Only XY exists for now; the others are refused with a clear message by the block check.
enum class Plane : std::uint8_t { XY };  // G17

// Group 6. Everything inside is mm: inch words are scaled where they are read.
enum class Units : std::uint8_t { Mm, Inch };  // G21, G20

// Group 3 (axis words, G90/G91) and group 4 (arc centre words, G90.1/G91.1).
enum class Distance : std::uint8_t { Absolute, Incremental };

constexpr bool is_arc(Motion m) { return m == Motion::ArcCw || m == Motion::ArcCcw; }
constexpr bool is_feed_motion(Motion m) { return m == Motion::Linear || is_arc(m); }

inline constexpr double kMmPerInch = 25.4;

constexpr double mm_per_unit(Units u) { return u == Units::Inch ? kMmPerInch : 1.0; }

}  // namespace softmc::program::iso
