// The composition root of a simulated run: machine + planner + interpolator + channel + drives,
// wired as cycle functions on a virtual clock; records the trace the reports are made from.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "control/channel.hpp"
#include "control/channel_stimulus.hpp"
#include "machine/config.hpp"
#include "machine/sim_drive.hpp"
#include "motion/interp/interpolator.hpp"
#include "motion/planner/planner.hpp"
#include "program/ir/program.hpp"
#include "report/trace.hpp"
#include "runtime/executor.hpp"

namespace softmc::app {

// One simulated machine running one program. Built (and every buffer sized) in the constructor;
// `step()` is exactly one interpolation cycle and is rt-safe.
class Simulation {
 public:
  // `stimulus` (may be null; must outlive the simulation): the PLC's motion signals over time.
  // `drives` (may be null): the simulated drives to run on, taken over as they are (after homing,
  // run_homing); by default each starts at rest where the program assumes.
  using Drives = std::array<std::unique_ptr<machine::SimDrive>, core::kMaxAxes>;
  Simulation(const program::Program& prog, const machine::MachineConfig& cfg,
             const control::ChannelStimulus* stimulus = nullptr, Drives* drives = nullptr);
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // rt-safe: one cycle, read → update → write → supervise.
  void step() { exec_.step(); }

  bool finished() const { return channel_.state() == control::ChannelState::Finished; }
  bool faulted() const { return channel_.state() == control::ChannelState::Fault; }
  bool stopped() const { return channel_.state() == control::ChannelState::Stopped; }
  // Held at rest on the path (feed hold, an axis disabled, override 0) with no stimulus event left
  // that could release it: the run cannot go on.
  bool held_for_good() const;
  std::uint64_t cycle() const { return exec_.clock().cycle; }
  double time_s() const { return static_cast<double>(exec_.clock().cycle) * cfg_.period_s; }
  const control::Channel& channel() const { return channel_; }
  const motion::Setpoint& setpoint() const { return interp_.setpoint(); }
  const machine::SimDrive* drive(std::size_t axis) const { return drives_[axis].get(); }
  const runtime::VirtualExecutor& executor() const { return exec_; }
  // What stopped the run, with the program location ("file:line:col: message").
  std::string fault_text() const;
  // Where and how a P-5 stop ended the run ("stopped by stop_request at file:line:col").
  std::string stop_text() const;
  // Why the run is held for good ("feed_hold is 1 ... at file:line:col").
  std::string held_text() const;
  const control::MotionSignals& signals() const { return signals_; }
  // The current state as a trace row (not rt: for the recorder).
  report::TraceRow row() const;

 private:
  void supervise(const runtime::CycleClock& c);

  const program::Program& prog_;
  machine::MachineConfig cfg_;
  motion::Planner planner_;
  motion::Interpolator interp_;
  control::Channel channel_;
  control::MotionSignals signals_;
  std::optional<control::ChannelStimulusPlayer> player_;
  std::array<std::unique_ptr<machine::SimDrive>, core::kMaxAxes> drives_{};
  runtime::VirtualExecutor exec_;
  char fault_buf_[256] = {0};
};

struct SimOptions {
  bool record = true;                        // keep one TraceRow per cycle in SimResult::trace
  std::function<void(const report::TraceRow&)> on_row;  // called with every row, recorded or not
  double max_time_s = 24 * 3600.0;           // a program still running then is reported as a timeout
  std::function<void(double fraction)> on_progress;  // called now and then with 0..1
  const control::ChannelStimulus* stimulus = nullptr;  // the PLC's motion signals over time (--stimulus)
  // The drives to run on (taken over: after homing, run_homing's), or null: each at rest where the
  // program starts.
  std::array<std::unique_ptr<machine::SimDrive>, core::kMaxAxes>* drives = nullptr;
};

struct SimResult {
  bool ok = false;             // the program ran to its end, or a P-5 stop from the stimulus ended it
  bool stopped = false;        // a P-5 stop ended it (result says which and where)
  std::string result = "ok";  // "ok", or what stopped the run (with the program line)
  report::Trace trace;
  std::uint64_t cycles = 0;
};

// Runs `prog` from its start position to its end on the simulated machine, in virtual time.
SimResult simulate(const program::Program& prog, const machine::MachineConfig& cfg, const SimOptions& opt = {});

}  // namespace softmc::app
