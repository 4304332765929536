// Per-bit input debounce (S-9, 5 ms by default).
#include "control/spc/input_filter.hpp"

namespace softmc::control::spc {

namespace {
// Sums of dt drift by ulps; a sample that reaches the filter time within this counts as reaching it.
constexpr double kTimeEpsS = 1e-9;
}  // namespace

void InputFilter::set_all(double filter_s) {
  for (auto& m : filter_s_) m.fill(filter_s < 0 ? 0 : filter_s);
}

void InputFilter::set(int module, int bit, double filter_s) {
  if (!valid_input(module, bit)) return;
  filter_s_[static_cast<std::size_t>(module)][static_cast<std::size_t>(bit)] = filter_s < 0 ? 0 : filter_s;
}

double InputFilter::filter_s(int module, int bit) const {
  if (!valid_input(module, bit)) return 0;
  return filter_s_[static_cast<std::size_t>(module)][static_cast<std::size_t>(bit)];
}

void InputFilter::preset(const std::array<std::uint16_t, kIoModules>& raw) {
  filtered_ = raw;
  for (auto& m : pending_s_) m.fill(0);
}

// rt-safe
const std::array<std::uint16_t, kIoModules>& InputFilter::update(const std::array<std::uint16_t, kIoModules>& raw,
                                                                   double dt_s) {
  for (std::size_t m = 0; m < kIoModules; ++m) {
    const auto diff = static_cast<std::uint16_t>(raw[m] ^ filtered_[m]);
    if (diff == 0) {  // the common case: nothing moving on this module
      pending_s_[m].fill(0);
      continue;
    }
    const int nbits = kInputBits[m];
    for (int b = 0; b < nbits; ++b) {
      auto& pend = pending_s_[m][static_cast<std::size_t>(b)];
      if (!((diff >> b) & 1u)) {
        pend = 0;
        continue;
      }
      pend += dt_s;
      if (pend + kTimeEpsS >= filter_s_[m][static_cast<std::size_t>(b)]) {
        filtered_[m] = static_cast<std::uint16_t>(filtered_[m] ^ (1u << b));
        pend = 0;
      }
    }
  }
  return filtered_;
}

}  // namespace softmc::control::spc
