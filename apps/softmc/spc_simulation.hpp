// The composition root of an SPC run (spc200.md): the SPC controller with its two tasks, the four SPC axes
// on SimDrives, a stimulus file and/or the reference PLC on the terminals, retentive registers in SQLite,
// wired as cycle functions on a virtual clock; records the SPC trace.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "control/spc/controller.hpp"
#include "control/spc/plc_client.hpp"
#include "control/spc/plc_script.hpp"
#include "control/spc/stimulus.hpp"
#include "machine/config.hpp"
#include "machine/sim_drive.hpp"
#include "report/spc_trace.hpp"
#include "runtime/executor.hpp"

namespace softmc::app {

struct SpcRunConfig {
  control::spc::ControllerConfig controller;         // mode, start programs, times
  std::optional<control::spc::Stimulus> stimulus;    // writes the input terminals
  std::optional<control::spc::PlcScript> plc;        // the reference PLC (S-10) drives the system inputs
  control::spc::PlcTiming plc_timing;
  double until_s = 0;  // run length; 0 = until 1 s after the last scripted event and the machine is at rest
  double max_s = 3600; // a run never goes beyond this (a machine that never comes to rest)
  bool record = true;  // keep one trace row per cycle
};

// One simulated SPC machine. Built (and every buffer sized) in the constructor; step() is one cycle, rt-safe.
//   read       drives' measured positions → axes.set_actual_mm; stimulus and PLC script → PLC → terminals
//   update     Controller::update (modes, tasks A and B, axes step)
//   write      drives: enable (ENABLE), mass factor (M37), setpoint and speed
//   supervise  following error, limit switches → Controller::raise_fault
class SpcSimulation {
 public:
  SpcSimulation(const program::spc::ProgramStore& store, const machine::MachineConfig& cfg, const SpcRunConfig& rc,
                control::spc::Registers& regs);
  SpcSimulation(const SpcSimulation&) = delete;
  SpcSimulation& operator=(const SpcSimulation&) = delete;

  void step() { exec_.step(); }  // rt-safe

  std::uint64_t cycle() const { return exec_.clock().cycle; }
  double time_s() const { return static_cast<double>(exec_.clock().cycle) * cfg_.period_s; }
  const control::spc::Controller& controller() const { return ctl_; }
  control::spc::Controller& controller() { return ctl_; }
  const control::spc::TaskAxes& axes() const { return axes_; }
  const machine::SimDrive* drive(std::size_t spc_axis) const { return drives_[spc_axis].get(); }
  const control::spc::PlcClient* plc() const { return plc_.get(); }
  control::spc::PlcClient* plc() { return plc_.get(); }
  const runtime::VirtualExecutor& executor() const { return exec_; }
  // The time of the last scripted event (stimulus or PLC orders); 0 without any.
  double last_event_s() const { return last_event_s_; }
  bool scripts_finished() const;
  // Nothing moves and the PLC has nothing to do (tasks may still wait on an input).
  bool at_rest() const;
  // The latched error as "task A, P3 N012: message" (or the message alone for a fault from outside). Not rt.
  std::string error_text() const;
  report::SpcTraceRow row() const;

 private:
  void read(const runtime::CycleClock& c);
  void write(const runtime::CycleClock& c);
  void supervise(const runtime::CycleClock& c);

  machine::MachineConfig cfg_;
  control::spc::TaskAxes axes_;
  control::spc::Controller ctl_;
  std::array<std::unique_ptr<machine::SimDrive>, program::kSpcAxes> drives_{};
  std::array<double, program::kSpcAxes> ferror_limit_mm_{};
  std::optional<control::spc::StimulusPlayer> stim_;
  std::unique_ptr<control::spc::PlcClient> plc_;
  std::optional<control::spc::PlcScriptPlayer> plc_script_;
  double last_event_s_ = 0;
  runtime::VirtualExecutor exec_;
  char fault_buf_[160] = {0};
};

struct SpcErrorEvent {
  double t_s = 0;
  int task = -1, program = -1, line = -1;  // -1: not from a task
  std::string message;                     // the controller's message
  std::string text;                        // "t=12.345 s: task A, P3 N012: message"
};

struct SpcRunResult {
  bool ok = false;  // no error was latched during the run
  report::SpcTrace trace;
  std::vector<SpcErrorEvent> errors;
  std::uint64_t cycles = 0;
  double t_end_s = 0;
  std::array<double, program::kSpcAxes> final_mm{};
  control::spc::ControllerStatus status;
  std::array<control::spc::TaskStatus, 2> tasks{};
  std::array<std::uint64_t, 2> instructions{};
  std::optional<std::array<control::spc::PlcCounters, 2>> plc;
  std::array<std::uint16_t, control::spc::kIoModules> outputs{};
};

// Runs a store on the simulated machine in virtual time. `registers_file` is the SQLite file of the
// retentive registers (restored before the first cycle, written in the background, flushed at the end);
// ":memory:" keeps nothing. Throws io::StoreError when the file cannot be opened.
SpcRunResult run_spc(const program::spc::ProgramStore& store, const machine::MachineConfig& cfg, const SpcRunConfig& rc,
                     const std::string& registers_file);

// The stimulus a run gets when none is given: power up (ENABLE=1, STOP=1) and, in Start/Stop, a START
// pulse 0.1 s after the self-test.
control::spc::Stimulus default_stimulus(const control::spc::ControllerConfig& c);

}  // namespace softmc::app
