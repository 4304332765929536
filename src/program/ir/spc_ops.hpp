// SPC dialect payloads of the Program IR (spc200.md S-2..S-7): point-to-point moves, modal axis
// settings, flow control, registers and I/O bits. Positions are fixed point in 0.01 mm (the
// language's two decimals), so register arithmetic is exact.
#pragma once

#include <array>
#include <cstdint>

namespace softmc::program {

// SPC axes X, Y, Z, U (S-1); bit i of an SpcAxes mask is SPC axis i.
inline constexpr std::size_t kSpcAxes = 4;
inline constexpr std::array<char, kSpcAxes> kSpcAxisLetters{'X', 'Y', 'Z', 'U'};
using SpcAxes = std::uint8_t;

inline constexpr std::int32_t kSpcPosMaxCenti = 999999;  // ±9999.99 mm (S-5)
inline constexpr int kSpcRegisters = 100;                // @0..@99 and R0..R99
inline constexpr int kSpcFlags = 64;                     // F0..F63
inline constexpr std::int32_t kSpcIntMax = 32767;        // R: -32767..32767

// A position operand: a number in 0.01 mm or position register @reg of the same axis.
struct SpcPos {
  bool is_reg = false;
  std::int32_t centi = 0;
  std::uint8_t reg = 0;
  friend bool operator==(const SpcPos&, const SpcPos&) = default;
};

enum class SpcProfile : std::uint8_t { Rapid /*G00*/, Trapezoid /*G01*/, SineSquared /*G02*/ };
enum class SpcCoord : std::uint8_t { Modal, Absolute /*G90*/, Relative /*G91*/ };

// G00/G01/G02: every named axis starts in the same cycle with its own speed (S-2).
struct SpcMove {
  SpcAxes axes = 0;
  SpcProfile profile = SpcProfile::Rapid;
  SpcCoord coord = SpcCoord::Modal;
  std::array<SpcPos, kSpcAxes> target{};
  std::array<std::uint8_t, kSpcAxes> speed_pct{};  // FX..FU, 0..99, 0 = 100 %
};

// Modal per-axis settings (S-3), one value per named axis.
enum class SpcSetting : std::uint8_t { Accel /*G08*/, Decel /*G09*/, PassThrough /*G25*/, MotionComplete /*G61*/, Mass /*M37*/ };
struct SpcAxisSetting {
  SpcSetting kind = SpcSetting::Accel;
  SpcAxes axes = 0;
  std::array<std::uint8_t, kSpcAxes> value{};
};

// G04: dwell in hundredths of a second.
struct SpcDwell {
  std::uint32_t hundredths = 0;
};

// E05 n / E05 Rn. `index` is the resolved instruction index when the line is literal (-1 otherwise).
struct SpcJump {
  bool via_reg = false;
  std::uint16_t line = 0;
  std::uint8_t reg = 0;
  std::int32_t index = -1;
};

// Ln / LRn.
struct SpcCall {
  bool via_reg = false;
  std::uint8_t program = 0;
  std::uint8_t reg = 0;
};

struct SpcReturn {};  // M02
struct SpcEnd {};     // M30
struct SpcSync {};    // M00 (S-7)

// G28 @i (load), G29 @i (add), M38 @i (capture the current position) per named axis (S-5).
enum class SpcPosRegOp : std::uint8_t { Load, Add, Capture };
struct SpcPosReg {
  SpcPosRegOp op = SpcPosRegOp::Load;
  std::uint8_t reg = 0;
  SpcAxes axes = 0;
  std::array<SpcPos, kSpcAxes> value{};  // unused for Capture
};

// #LRn=v, #ARn=v, #TRn=v line (S-5).
enum class SpcIntRegOp : std::uint8_t { Load, Add, Test };
struct SpcIntReg {
  SpcIntRegOp op = SpcIntRegOp::Load;
  std::uint8_t reg = 0;
  std::int32_t value = 0;
  std::uint16_t line = 0;   // Test only
  std::int32_t index = -1;  // Test only: resolved jump target
};

// A bit: input In.m, output Qn.m or flag Fn (module unused).
enum class SpcBitSpace : std::uint8_t { Input, Output, Flag };
struct SpcBit {
  SpcBitSpace space = SpcBitSpace::Input;
  std::uint8_t module = 0;
  std::uint8_t bit = 0;
};

// #TI/#TQ/#TF (jump when 1) and #TNI/#TNQ/#TNF (jump when 0) (S-6).
struct SpcBitTest {
  SpcBit bit;
  bool jump_when = true;
  std::uint16_t line = 0;
  std::int32_t index = -1;
};

// #SQ/#SF (value 1) and #RQ/#RF (value 0).
struct SpcBitWrite {
  SpcBit bit;
  bool value = true;
};

}  // namespace softmc::program

#include <string>

namespace softmc::program {

// Canonical dump text of each SPC payload (used by dump(); defined in program/spc/dump_ops.cpp).
std::string spc_text(const SpcMove& op);
std::string spc_text(const SpcAxisSetting& op);
std::string spc_text(const SpcDwell& op);
std::string spc_text(const SpcJump& op);
std::string spc_text(const SpcCall& op);
std::string spc_text(const SpcReturn& op);
std::string spc_text(const SpcEnd& op);
std::string spc_text(const SpcSync& op);
std::string spc_text(const SpcPosReg& op);
std::string spc_text(const SpcIntReg& op);
std::string spc_text(const SpcBitTest& op);
std::string spc_text(const SpcBitWrite& op);

}  // namespace softmc::program
