// `softmc programs STORE ...` and `softmc registers ...`: the SPC program store and registers from outside (S-12).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace softmc::app {

struct ProgramsArgs {
  std::string store;               // the folder of P<n>.spc
  std::string action;              // list, show, import, export, delete, check
  std::vector<std::string> items;  // program numbers (show/export/delete) or files (import)
  std::optional<int> as;           // import one file as P<as>
  std::string to_dir = ".";        // export target
  bool force = false;              // delete although called
  bool json = false;               // list as JSON
  std::string machine;             // configuration: [spc] mode (Record Select rules) and start programs
};

// Exit codes (docs/cli.md): 0 done; 1 refused or invalid, nothing changed; 2 a file could not be written.
int run_programs_command(const ProgramsArgs& args);

struct RegistersArgs {
  std::string store;                // the store folder: registers.sqlite in it by default
  std::string registers;            // the SQLite file, over [spc] registers_file and the store's
  std::string machine;              // for [spc] registers_file
  std::string action;               // get or set
  std::vector<std::string> words;   // @n X, Rn, Fn [=value]
  bool json = false;
};

// Exit codes: 0 done; 1 a bad name or value (nothing written); 2 the register file cannot be used.
int run_registers_command(const RegistersArgs& args);

// Adds the `programs` and `registers` subcommands to `app`; after parsing, `run()` runs the one given
// (or returns nothing when neither was).
class SpcAdminCli {
 public:
  explicit SpcAdminCli(CLI::App& app);
  std::optional<int> run() const;

 private:
  ProgramsArgs programs_;
  RegistersArgs registers_;
  CLI::App* programs_cmd_ = nullptr;
  CLI::App* registers_cmd_ = nullptr;
};

}  // namespace softmc::app
