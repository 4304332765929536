// Registers from outside (S-5, S-12): names like @3X, R5, F2; range checks as the language has; one transaction per write.
//
// The one API `softmc registers` and, later, the Modbus/HTTP servers use on the retentive store. A write
// is validated as a whole (every name, every value, on a scratch copy of the registers) before the
// SQLite transaction that stores all of it — or, on any error, nothing.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/retentive_store.hpp"

namespace softmc::io {

enum class RegisterKind : std::uint8_t { Position, Integer, Flag };

struct RegisterRef {
  RegisterKind kind = RegisterKind::Integer;
  int axis = 0;   // position registers: 0..3 = X Y Z U
  int index = 0;  // @0..@99, R0..R99, F0..F63
  std::string name() const;  // "@3X", "R5", "F2"
  friend bool operator==(const RegisterRef&, const RegisterRef&) = default;
};

// A value in the register's own unit: 0.01 mm for position registers, the integer for R, 0/1 for F.
struct RegisterValue {
  RegisterRef ref;
  std::int64_t value = 0;
  std::string text() const;  // "@3X=12.50", "R5=-7"
};

struct RegisterArgs {
  std::vector<RegisterRef> refs;      // `get` names
  std::vector<RegisterValue> writes;  // `set` assignments
  std::vector<std::string> errors;    // one message per bad argument
};

// Parses command-line words: `@3 X`, `@3X`, `R5`, `F2` (get) or `@3 X=12.5`, `@3X=-0.25`, `R5=7` (set).
// Letters may be lower case. Ranges as the language has them (S-5): @ two decimals, ±9999.99; R
// −32767..32767; indexes 0..99 (F 0..63).
RegisterArgs parse_register_args(const std::vector<std::string>& words, bool assignments);

// A position value "12.5" → 1250 (0.01 mm): at most two decimals, within ±9999.99; nothing otherwise.
std::optional<std::int64_t> parse_position_centi(std::string_view s, std::string& error);

inline constexpr const char* kFlagsNotRetentive =
    "flags are not retentive (S-5): they start at 0 in every run and are not kept in the register file";

class RegisterAccess {
 public:
  // Opens (creating) the SQLite register file; throws StoreError.
  explicit RegisterAccess(const std::string& path);

  // Current values; errors (flags) in `errors`, nothing returned for them.
  std::vector<RegisterValue> get(const std::vector<RegisterRef>& refs, std::vector<std::string>& errors);
  // Every register that is not 0, position registers first (axis, index), then R.
  std::vector<RegisterValue> nonzero();
  // Writes all or nothing, in one transaction. Returns the errors (empty = written).
  std::vector<std::string> set(const std::vector<RegisterValue>& writes);

 private:
  RetentiveStore store_;
};

}  // namespace softmc::io
