// One problem found while reading a line: the column it points at and what is wrong.
#pragma once

#include <cstdint>
#include <string>

namespace softmc::program::iso {

// The parser turns it into a core::Diagnostic once it knows the file and line.
struct LineError {
  std::uint32_t col = 0;  // 1-based; the letter of the offending word where there is one
  std::string message;
};

}  // namespace softmc::program::iso
