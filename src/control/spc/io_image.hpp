// The SPC200 I/O image (S-6): input and output bits of the four I/O modules and two CP buses, plus the
// named system signals of the first module (S-8 Start/Stop, S-9 Record Select).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace softmc::control::spc {

// Module numbers as the SPC200 addresses them: In.m / Qn.m with n = module, m = bit.
//   0: first I/O module   I0.0..I0.9  / Q0.0..Q0.7
//   1: first CP bus       I1.0..I1.15 / Q1.0..Q1.15
//   2: second I/O module  I2.0..I2.9  / Q2.0..Q2.7
//   3: second CP bus      I3.0..I3.15 / Q3.0..Q3.15
//   4: third I/O module   I4.0..I4.9  / Q4.0..Q4.7
//   5: fourth I/O module  I5.0..I5.9  / Q5.0..Q5.7
inline constexpr int kIoModules = 6;
inline constexpr std::array<int, kIoModules> kInputBits{10, 16, 10, 16, 10, 10};
inline constexpr std::array<int, kIoModules> kOutputBits{8, 16, 8, 16, 8, 8};

constexpr bool valid_input(int module, int bit) {
  return module >= 0 && module < kIoModules && bit >= 0 && bit < kInputBits[static_cast<std::size_t>(module)];
}
constexpr bool valid_output(int module, int bit) {
  return module >= 0 && module < kIoModules && bit >= 0 && bit < kOutputBits[static_cast<std::size_t>(module)];
}

// One address In.m or Qn.m.
struct IoAddress {
  bool output = false;
  std::uint8_t module = 0;
  std::uint8_t bit = 0;
  friend constexpr bool operator==(const IoAddress&, const IoAddress&) = default;
};
constexpr bool valid(IoAddress a) { return a.output ? valid_output(a.module, a.bit) : valid_input(a.module, a.bit); }

// System signals of the first module. Several addresses carry two names, one per operating mode
// (I0.5 is SYNC_IB in Start/Stop and CLK_B in Record Select).
namespace sig {
inline constexpr IoAddress kSyncIB{false, 0, 5};  // S-8
inline constexpr IoAddress kSyncIA{false, 0, 6};  // S-8
inline constexpr IoAddress kClkB{false, 0, 5};    // S-9
inline constexpr IoAddress kClkA{false, 0, 6};    // S-9
inline constexpr IoAddress kStop{false, 0, 7};    // 0 = stop (normally-closed)
inline constexpr IoAddress kStart{false, 0, 8};   // S-8 START/RESET
inline constexpr IoAddress kReset{false, 0, 8};   // S-9 RESET
inline constexpr IoAddress kEnable{false, 0, 9};
inline constexpr IoAddress kMcB{true, 0, 3};      // S-8
inline constexpr IoAddress kMcA{true, 0, 4};      // S-8
inline constexpr IoAddress kRcB{true, 0, 3};      // S-9
inline constexpr IoAddress kRcA{true, 0, 4};      // S-9
inline constexpr IoAddress kSyncOB{true, 0, 5};   // S-8
inline constexpr IoAddress kSyncOA{true, 0, 6};   // S-8
inline constexpr IoAddress kAckB{true, 0, 5};     // S-9
inline constexpr IoAddress kAckA{true, 0, 6};     // S-9
inline constexpr IoAddress kReady{true, 0, 7};
}  // namespace sig

// Outputs Q0.3..Q0.7 belong to the system in both modes; a program must not write them (S-6).
constexpr bool is_system_output(int module, int bit) { return module == 0 && bit >= 3 && bit <= 7; }

// Plain bit image: one 16-bit word per module and direction. Copyable, no allocation; every accessor
// is rt-safe. Out-of-range addresses read 0 and ignore writes (programs are checked at load time, so
// this is a last line of defence, not the validation).
struct IoImage {
  static constexpr int kModules = kIoModules;
  std::array<std::uint16_t, kModules> inputs{};
  std::array<std::uint16_t, kModules> outputs{};

  bool get_input(int module, int bit) const {
    return valid_input(module, bit) && ((inputs[idx(module)] >> bit) & 1u) != 0;
  }
  bool get_output(int module, int bit) const {
    return valid_output(module, bit) && ((outputs[idx(module)] >> bit) & 1u) != 0;
  }
  void set_input(int module, int bit, bool v) {
    if (valid_input(module, bit)) put(inputs[idx(module)], bit, v);
  }
  void set_output(int module, int bit, bool v) {
    if (valid_output(module, bit)) put(outputs[idx(module)], bit, v);
  }

  bool get(IoAddress a) const { return a.output ? get_output(a.module, a.bit) : get_input(a.module, a.bit); }
  void set(IoAddress a, bool v) {
    if (a.output)
      set_output(a.module, a.bit, v);
    else
      set_input(a.module, a.bit, v);
  }

  // S-9: line number = B0 + 2·B1 + 4·B2 + 8·B3 + 16·B4 from I0.0..I0.4.
  int line_bits() const { return inputs[0] & 0x1F; }
  void set_line_bits(int line) {
    inputs[0] = static_cast<std::uint16_t>((inputs[0] & ~0x1Fu) | (static_cast<unsigned>(line) & 0x1Fu));
  }

  friend bool operator==(const IoImage&, const IoImage&) = default;

 private:
  static constexpr std::size_t idx(int module) { return static_cast<std::size_t>(module); }
  static void put(std::uint16_t& w, int bit, bool v) {
    const auto m = static_cast<std::uint16_t>(1u << bit);
    w = static_cast<std::uint16_t>(v ? (w | m) : (w & ~m));
  }
};

// "I0.7", "Q2.3" (either case) → address, or nothing if malformed or outside S-6's address space.
std::optional<IoAddress> parse_address(std::string_view text);
// Named system signal ("STOP", "CLK_A", "READY", "B0".."B4", ...) → address, or nothing.
std::optional<IoAddress> signal_address(std::string_view name);
// "I0.7" / "Q2.13" into buf (at least 6 chars); returns buf.
const char* format_address(IoAddress a, char* buf);

}  // namespace softmc::control::spc
