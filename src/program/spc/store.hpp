// The program store: P0..P99 (S-1), loaded from a folder of P<n>.spc files and checked as a whole.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/diagnostic.hpp"
#include "program/spc/parser.hpp"

namespace softmc::program::spc {

class ProgramStore {
 public:
  // rt-safe: program n, or nullptr.
  const SpcProgram* get(int n) const { return n >= 0 && n < kPrograms ? programs_[n].get() : nullptr; }

  // Parses `text` as program n and stores it when it has no error (replacing an older P<n>).
  // Diagnostics are appended. Calls to other programs are checked by validate().
  bool add(int n, std::string_view text, const std::string& file, const ParseOptions& opt, core::Diagnostics& out);
  void add(SpcProgram p);
  void remove(int n) { if (get(n)) programs_[n].reset(); }
  std::vector<int> numbers() const;

  // Loads every P<n>.spc of `dir` (other .spc names are errors) and validates the whole store.
  core::Diagnostics load_folder(const std::string& dir, const ParseOptions& opt = {});
  // Cross-program checks (S-4): a literal call names a program that exists and is not empty.
  core::Diagnostics validate() const;

 private:
  std::array<std::unique_ptr<SpcProgram>, kPrograms> programs_{};
};

// "P12.spc" (any case of P and the extension) → 12; -1 when the name is not a program file name.
int program_number_from_file_name(std::string_view name);

// The program files of a store folder: one path per program number (-1 ... none), and an error for every
// .spc file that is not named P<n>.spc or that holds a number another file holds too (P3.spc and P03.spc).
struct FolderFiles {
  std::array<std::string, kPrograms> path{};
  core::Diagnostics diagnostics;
};
FolderFiles scan_folder(const std::string& dir);

// Reads a whole file as bytes; nothing when it cannot be read.
std::optional<std::string> read_text_file(const std::string& path);

// Each program file of a store folder (scan_folder), in number order, read whole: fn(n, path, text).
// The folder's naming errors and a file that cannot be read ("cannot read the file") go to `out`.
void read_folder(const std::string& dir, core::Diagnostics& out,
                 const std::function<void(int n, const std::string& path, const std::string& text)>& fn);

}  // namespace softmc::program::spc
