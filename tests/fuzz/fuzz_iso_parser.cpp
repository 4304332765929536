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
  const auto r = program::iso::parse(text, "fuzz.ngc");
  // The contract: a program exactly when there is no error, and a dump that can always be made.
  if (r.program.has_value() == core::has_errors(r.diagnostics)) std::abort();
  for (const auto& d : r.diagnostics) (void)d.format();
  if (r.program) (void)program::dump(*r.program);
  return 0;
}
