// S-9 input filter: each input bit's level counts once it has been stable for its filter time.
#pragma once

#include <array>

#include "control/spc/io_image.hpp"

namespace softmc::control::spc {

// Per-bit debounce of the input half of an IoImage.
//
//   raw      ─────┐▁▁▁▁▁▁▁▁▁▁▁▁▁▁▁▁▁▁▁▁▁┌──── (a change is sampled on cycle n)
//   filtered ──────────────────┐▁▁▁▁▁▁▁▁▁▁▁▁▁▁▁▁▁▁┌──
//                   ◄─ filter ─►
// A bit takes the raw level on the cycle where the raw level has differed from the filtered one on
// consecutive samples covering the filter time (5 ms at 1 ms = the 5th sample). A shorter glitch never
// reaches the filtered image, and a pulse longer than the filter passes with its width unchanged, only
// delayed — which keeps the S-9 "RESET pulse ≥ 10 ms" measurable on the filtered side.
class InputFilter {
 public:
  static constexpr double kDefaultFilterS = 0.005;  // S-9

  InputFilter() { set_all(kDefaultFilterS); }

  // Configuration: the same time for every bit, or one bit's own time (0 = no filter).
  void set_all(double filter_s);
  void set(int module, int bit, double filter_s);
  double filter_s(int module, int bit) const;

  // rt-safe: one sample of the raw inputs; returns the filtered inputs (also kept in filtered()).
  const std::array<std::uint16_t, kIoModules>& update(const std::array<std::uint16_t, kIoModules>& raw, double dt_s);
  const std::array<std::uint16_t, kIoModules>& filtered() const { return filtered_; }
  // Start from a known level without waiting (power-up: the terminals' state is the initial image).
  void preset(const std::array<std::uint16_t, kIoModules>& raw);

 private:
  static constexpr int kBits = 16;
  std::array<std::array<double, kBits>, kIoModules> filter_s_{};
  std::array<std::array<double, kBits>, kIoModules> pending_s_{};  // time the raw level has differed
  std::array<std::uint16_t, kIoModules> filtered_{};
};

}  // namespace softmc::control::spc
