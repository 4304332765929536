// Formatting of diagnostics.
#include "core/diagnostic.hpp"

#include <fmt/format.h>

namespace softmc::core {

std::string Diagnostic::format() const {
  const char* sev = severity == Severity::Error ? "error" : severity == Severity::Warning ? "warning" : "note";
  return fmt::format("{}:{}:{}: {}: {}", file, line, col, sev, message);
}

}  // namespace softmc::core
