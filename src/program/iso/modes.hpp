// The values of the RS274 modal groups this interpreter knows (one enum per group).
#pragma once

#include <cstdint>

namespace softmc::program::iso {

// Group 1. None after G80 and at program start: axis words then have no motion to drive.
enum class Motion : std::uint8_t {
  None, Rapid, Linear, ArcCw, ArcCcw,   // G80, G0, G1, G2, G3
  CubicSpline, QuadSpline, Nurbs,       // G5, G5.1, G5.2 (… G5.3)
  Drill73, Drill81, Drill82, Drill83, Bore85, Bore86, Bore89,  // canned cycles
  Tap74, Tap84, BackBore87, Bore88                                  // (cycles stay last: is_cycle)
};

// Spindle (or torch) as M3/M4/M5/M19 left it: G84, G86, G87 and G88 need it turning and restart it.
enum class SpindleDir : std::uint8_t { Stopped, Cw, Ccw };

// Group 2: the arc plane, named by (first axis, second axis); the normal is the third.
enum class Plane : std::uint8_t { XY, XZ, YZ };  // G17, G18 (Z,X), G19 (Y,Z)

// Group 6. Everything inside is mm: inch words are scaled where they are read.
enum class Units : std::uint8_t { Mm, Inch };  // G21, G20

// Group 3 (axis words, G90/G91) and group 4 (arc centre words, G90.1/G91.1).
enum class Distance : std::uint8_t { Absolute, Incremental };

// Group 5. G95 (per revolution) is refused: the machines have no spindle feedback.
enum class FeedMode : std::uint8_t { PerMinute, InverseTime };  // G94, G93

// Group 10: where canned cycles retract to.
enum class Retract : std::uint8_t { OldZ, RPlane };  // G98, G99

// Group 7.
enum class Comp : std::uint8_t { Off, Left, Right };  // G40, G41/G41.1, G42/G42.1

constexpr bool is_arc(Motion m) { return m == Motion::ArcCw || m == Motion::ArcCcw; }
constexpr bool is_cycle(Motion m) { return m >= Motion::Drill73; }
constexpr bool is_spline(Motion m) { return m == Motion::CubicSpline || m == Motion::QuadSpline || m == Motion::Nurbs; }
constexpr bool is_feed_motion(Motion m) { return m != Motion::None && m != Motion::Rapid; }

// The G code of a motion mode, times ten (G80 800, G1 10, G5.2 52, G81 810): LinuxCNC's #<_motion_mode>.
constexpr int motion_code10(Motion m) {
  switch (m) {
    case Motion::None: return 800;
    case Motion::Rapid: return 0;
    case Motion::Linear: return 10;
    case Motion::ArcCw: return 20;
    case Motion::ArcCcw: return 30;
    case Motion::CubicSpline: return 50;
    case Motion::QuadSpline: return 51;
    case Motion::Nurbs: return 52;
    case Motion::Drill73: return 730;
    case Motion::Drill81: return 810;
    case Motion::Drill82: return 820;
    case Motion::Drill83: return 830;
    case Motion::Bore85: return 850;
    case Motion::Bore86: return 860;
    case Motion::Bore89: return 890;
    case Motion::Tap74: return 740;
    case Motion::Tap84: return 840;
    case Motion::BackBore87: return 870;
    case Motion::Bore88: return 880;
  }
  return 800;
}

// G17, G18, G19 times ten (LinuxCNC's #<_plane>), and as written.
constexpr int plane_code10(Plane p) { return p == Plane::XY ? 170 : p == Plane::XZ ? 180 : 190; }
// Coordinate system n (1 … 9) as its G code ×10: G54 … G59 are 540 … 590, G59.1 … G59.3 591 … 593.
constexpr int coord_system_code10(int n) { return n <= 6 ? 530 + 10 * n : 590 + (n - 6); }
constexpr const char* plane_code(Plane p) { return p == Plane::XY ? "G17" : p == Plane::XZ ? "G18" : "G19"; }

inline constexpr double kMmPerInch = 25.4;

constexpr double mm_per_unit(Units u) { return u == Units::Inch ? kMmPerInch : 1.0; }

// Plane axes: (first, second, normal) as axis indices (X=0, Y=1, Z=2).
struct PlaneAxes {
  std::uint8_t a0, a1, n;
};
constexpr PlaneAxes axes_of(Plane p) {
  switch (p) {
    case Plane::XZ: return {2, 0, 1};
    case Plane::YZ: return {1, 2, 0};
    case Plane::XY: break;
  }
  return {0, 1, 2};
}

}  // namespace softmc::program::iso
