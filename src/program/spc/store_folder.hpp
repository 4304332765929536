// The program store on disk (S-1, S-12): list, read, import, export, delete and check a folder of P<n>.spc.
//
// The one API the CLI (`softmc programs`) and, later, the Modbus/HTTP servers call. Every change is
// validated as a whole before anything is written: an import is parsed with the store's rules and the
// store that would result is checked across programs (calls, S-4); only a store that checks clean is
// written, each file atomically (temp file + fsync + rename), so a reader sees the old or the new
// program, never half of one.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/diagnostic.hpp"
#include "program/spc/store.hpp"

namespace softmc::program::spc {

struct ProgramInfo {
  int number = -1;
  std::size_t lines = 0;  // instructions (N lines)
  std::string title;      // the first comment of the file, trimmed; "" when it has none
  std::string file;       // path in the store
};

struct ImportItem {
  int number = -1;     // P<number> in the store
  std::string text;    // the program, stored byte for byte
  std::string source;  // where it came from, for diagnostics (a file name, "upload", ...)
};

struct StoreChange {
  core::Diagnostics diagnostics;  // every error (nothing changed when there is one) and notes
  std::vector<int> changed;       // programs written, deleted or exported
  bool write_failed = false;      // validation passed but the file system refused (disk full, permissions)
  bool ok() const { return !core::has_errors(diagnostics); }
};

class StoreFolder {
 public:
  // `opt.record_select` = the rules of the configured mode (S-9), as `softmc run` loads the store.
  explicit StoreFolder(std::string dir, ParseOptions opt = {});

  const std::string& dir() const { return dir_; }
  // Where program n is (its existing file, whatever the case of its name) or goes (dir/P<n>.spc).
  std::string path_of(int n) const;

  // Loads and checks the whole store, exactly as `softmc run` does.
  core::Diagnostics check() const;
  // Every program that parses, in number order; problems of the others go to `out`.
  std::vector<ProgramInfo> list(core::Diagnostics& out) const;
  // The stored text of program n, byte for byte.
  std::optional<std::string> read(int n, core::Diagnostics& out) const;
  // Programs whose literal calls (L<n>) name n (LR calls through a register cannot be known before run time).
  std::vector<int> callers_of(int n, core::Diagnostics& out) const;

  // Adds or replaces programs; all or nothing (see the file comment).
  StoreChange import(const std::vector<ImportItem>& items) const;
  // Deletes program n; refused while another program calls it, unless `force`.
  StoreChange remove(int n, bool force) const;
  // Copies programs to `to_dir` as P<n>.spc, byte for byte; all must exist before anything is written.
  StoreChange export_to(const std::vector<int>& numbers, const std::string& to_dir) const;

 private:
  core::Diagnostic error(std::string message) const;

  std::string dir_;
  ParseOptions opt_;
};

// The first `;` comment of a program text, trimmed.
std::string program_title(std::string_view text);

// Writes `text` to `path` atomically: a temp file in the same folder, fsync, rename over, fsync the folder.
// Returns an error message, or "" on success.
std::string write_file_atomically(const std::string& path, std::string_view text);

}  // namespace softmc::program::spc
