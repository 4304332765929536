// `softmc run STORE`: the SPC run's command line: options over the [spc] configuration, load, run, report.
#pragma once

#include <optional>
#include <string>

#include "machine/config.hpp"

namespace softmc::app {

struct SpcCommandArgs {
  std::string store;                  // a folder of P<n>.spc, or one P<n>.spc file
  std::string mode;                   // "" = [spc] mode
  std::optional<int> task_a, task_b;  // override [spc] task_a / task_b
  std::string stimulus;               // input stimulus file; "" = power up (and START in Start/Stop)
  std::string plc;                    // orders file for the reference PLC (S-10); "" = no PLC
  std::string registers;              // SQLite file; "" = [spc] registers_file or <store>/registers.sqlite
  double until_s = 0;                 // 0 = until the machine is at rest after the last scripted event
  std::string trace_csv, plot;
  bool json = false;
  std::string machine_label;          // for the report
};

// Prints diagnostics and the report; returns the exit code: 0 ran without error, 1 bad input, 2 the
// controller latched an error during the run (each printed with time, task, program and line).
int run_spc_command(const SpcCommandArgs& args, const machine::MachineConfig& cfg);

}  // namespace softmc::app
