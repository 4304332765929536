// The SPC200 I/O address space (S-6) and its system outputs (S-8, S-9), as the parser checks them.
#pragma once

namespace softmc::program::spc {

// Modules 0, 2, 4, 5: inputs .0...9, outputs .0...7; CP buses 1 and 3: 16 bits each way.
constexpr bool valid_input(int module, int bit) {
  if (module == 1 || module == 3) return bit >= 0 && bit <= 15;
  if (module == 0 || module == 2 || module == 4 || module == 5) return bit >= 0 && bit <= 9;
  return false;
}
constexpr bool valid_output(int module, int bit) {
  if (module == 1 || module == 3) return bit >= 0 && bit <= 15;
  if (module == 0 || module == 2 || module == 4 || module == 5) return bit >= 0 && bit <= 7;
  return false;
}
// Q0.3..Q0.7: MC/RC, SYNC/ACK and READY belong to the controller in both modes.
constexpr bool system_output(int module, int bit) { return module == 0 && bit >= 3 && bit <= 7; }

}  // namespace softmc::program::spc
