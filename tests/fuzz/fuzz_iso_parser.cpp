// libFuzzer target: any bytes into the ISO parser; it must neither crash nor disagree with itself.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "program/iso/parser.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace softmc;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  // The product's work limits (parser.hpp) keep any input under ~0.2 s natively; ASan and UBSan
  // make each block ~20 times slower, so the budgets shrink by that much to keep every input well
  // under libFuzzer's -timeout (a loop up to the limit must not count as a hang).
  program::iso::ParseOptions opt;
  opt.max_blocks = 50000;
  opt.max_instructions = 50000;
  const auto r = program::iso::parse(text, "fuzz.ngc", opt);
  // The contract: a program exactly when there is no error, and a dump that can always be made.
  if (r.program.has_value() == core::has_errors(r.diagnostics)) std::abort();
  std::string all;
  for (const auto& d : r.diagnostics) all += d.format() + '\n';
  if (r.program) all += program::dump(*r.program);
  // The fast path for plain straight moves (fast_block.hpp) must change nothing.
  opt.fast_path = false;
  const auto slow = program::iso::parse(text, "fuzz.ngc", opt);
  std::string slow_all;
  for (const auto& d : slow.diagnostics) slow_all += d.format() + '\n';
  if (slow.program) slow_all += program::dump(*slow.program);
  if (all != slow_all) std::abort();
  return 0;
}
