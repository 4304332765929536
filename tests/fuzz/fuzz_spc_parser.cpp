// libFuzzer target: any bytes into the SPC parser (both rule sets) and a program store; no crash, and a
// program exactly when there is no error.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "program/spc/store.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace softmc;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  for (const bool record : {false, true}) {
    const auto r = program::spc::parse(text, "P7.spc", {record, 7});
    if (r.program.has_value() == core::has_errors(r.diagnostics)) std::abort();
    for (const auto& d : r.diagnostics) (void)d.format();
    if (r.program) {
      (void)program::dump(r.program->ir);
      // Every instruction has its N line, and index() finds it again.
      if (r.program->lines.size() != r.program->size()) std::abort();
      for (std::size_t i = 0; i < r.program->size(); ++i)
        if (r.program->index(r.program->lines[i]) != static_cast<int>(i)) std::abort();
    }
    // The store's cross-program checks on the same text (calls of programs it does not have).
    program::spc::ProgramStore store;
    core::Diagnostics d;
    if (store.add(7, text, "P7.spc", {record, 7}, d)) (void)store.validate();
  }
  return 0;
}
