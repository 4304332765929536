// Source locations and diagnostics: the `file:line:col: error: message` contract of every parser.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace softmc::core {

// Where an instruction came from. `file` indexes Program::files (0 = the main file).
struct SourceLoc {
  std::uint16_t file = 0;
  std::uint32_t line = 0;  // 1-based; 0 = unknown
  std::uint32_t col = 0;   // 1-based
  friend bool operator==(const SourceLoc&, const SourceLoc&) = default;
};

enum class Severity : std::uint8_t { Error, Warning, Note };

struct Diagnostic {
  std::string file;
  std::uint32_t line = 0;
  std::uint32_t col = 0;
  Severity severity = Severity::Error;
  std::string message;

  // "file:line:col: error: message"
  std::string format() const;
};

using Diagnostics = std::vector<Diagnostic>;

inline bool has_errors(const Diagnostics& d) {
  for (const auto& x : d)
    if (x.severity == Severity::Error) return true;
  return false;
}

}  // namespace softmc::core
