// SPC run: one cycle = read drives and scripts → controller update → write drives → supervise.
#include "spc_simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "io/retentive_store.hpp"

namespace softmc::app {

using namespace control::spc;

namespace {

std::array<double, program::kSpcAxes> start_positions(const SpcAxesConfig& c) {
  std::array<double, program::kSpcAxes> p{};
  for (std::size_t i = 0; i < program::kSpcAxes; ++i)
    if (c.axis[i].present) p[i] = std::clamp(0.0, c.axis[i].min_mm, c.axis[i].max_mm);
  return p;
}

}  // namespace

Stimulus default_stimulus(const ControllerConfig& c) {
  Stimulus s;
  s.events.push_back({0, sig::kEnable, false, 1, 0});
  s.events.push_back({0, sig::kStop, false, 1, 0});
  if (c.mode == SpcMode::StartStop) {
    const double t = c.self_test_s + 0.1;
    s.events.push_back({t, sig::kStart, false, 1, 0});
    s.events.push_back({t + 0.05, sig::kStart, false, 0, 0});
  }
  return s;
}

SpcSimulation::SpcSimulation(const program::spc::ProgramStore& store, const machine::MachineConfig& cfg,
                             const SpcRunConfig& rc, Registers& regs)
    : cfg_(cfg),
      axes_(spc_axes_from(cfg), start_positions(spc_axes_from(cfg))),
      ctl_(rc.controller, store, regs, axes_),
      exec_(cfg.period_s) {
  for (std::size_t i = 0; i < program::kSpcAxes; ++i)
    if (const auto* a = cfg_.axis(core_axis(i))) {
      drives_[i] = std::make_unique<machine::SimDrive>(*a, axes_.setpoint_mm(static_cast<int>(i)));
      ferror_limit_mm_[i] = a->ferror_limit_mm;
    }
  if (rc.stimulus) {
    stim_.emplace(*rc.stimulus);
    if (!rc.stimulus->events.empty()) last_event_s_ = rc.stimulus->events.back().t_s;
  }
  if (rc.plc) {
    plc_ = std::make_unique<PlcClient>(rc.plc_timing, std::max<std::size_t>(64, rc.plc->entries.size() + 1));
    plc_script_.emplace(*rc.plc);
    if (!rc.plc->entries.empty()) last_event_s_ = std::max(last_event_s_, rc.plc->entries.back().t_s);
  }
  exec_.add("read", [this](const runtime::CycleClock& c) { read(c); });
  exec_.add("update", [this](const runtime::CycleClock& c) { ctl_.update(c.dt_s); });
  exec_.add("write", [this](const runtime::CycleClock& c) { write(c); });
  exec_.add("supervise", [this](const runtime::CycleClock& c) { supervise(c); });
}

// rt-safe
void SpcSimulation::read(const runtime::CycleClock& c) {
  // Measured positions first: the controller's G61 windows and M38 read them in this cycle's update.
  for (std::size_t i = 0; i < program::kSpcAxes; ++i)
    if (drives_[i]) axes_.set_actual_mm(static_cast<int>(i), drives_[i]->measured_mm());
  auto& wires = ctl_.terminals();
  if (stim_) stim_->apply(c.t_s, wires);
  if (plc_) {
    plc_script_->apply(c.t_s, *plc_);
    plc_->cycle(c.dt_s, wires);  // the PLC writes its outputs (B0..B4, CLK, STOP, RESET, ENABLE) last
  }
}

// rt-safe
void SpcSimulation::write(const runtime::CycleClock& c) {
  const bool enabled = ctl_.status().drives_enabled;  // ENABLE=0 opens the position loops (S-8/S-9)
  const auto& out = axes_.output();
  for (std::size_t i = 0; i < program::kSpcAxes; ++i) {
    auto* d = drives_[i].get();
    if (!d) continue;
    d->set_enabled(enabled);
    d->set_mass_factor(out.mass_factor[i]);  // M37
    d->update(out.setpoint_mm[i], out.velocity_mm_s[i], c.dt_s);
  }
}

// rt-safe: a following error or a closed limit switch is a fault from outside the tasks: every axis stops,
// READY=0 (S-8/S-9). Raised every cycle while it lasts, so that a reset cannot clear a fault still present.
void SpcSimulation::supervise(const runtime::CycleClock& c) {
  if (!ctl_.status().drives_enabled) return;
  for (std::size_t i = 0; i < program::kSpcAxes; ++i) {
    const auto* d = drives_[i].get();
    if (!d) continue;
    const double fe = std::fabs(d->following_error_mm());
    const bool lim = d->limit_negative() || d->limit_positive();
    if (fe <= ferror_limit_mm_[i] && !lim) continue;
    if (!ctl_.status().error) {  // keep the latched message's text stable while it is shown
      if (lim)
        std::snprintf(fault_buf_, sizeof fault_buf_, "limit switch %c%c closed at t=%.3f s", program::kSpcAxisLetters[i],
                      d->limit_negative() ? '-' : '+', c.t_s + c.dt_s);
      else
        std::snprintf(fault_buf_, sizeof fault_buf_, "following error on %c: %.3f mm exceeds %.3f mm at t=%.3f s",
                      program::kSpcAxisLetters[i], fe, ferror_limit_mm_[i], c.t_s + c.dt_s);
    }
    ctl_.raise_fault(fault_buf_);
    return;
  }
}

bool SpcSimulation::scripts_finished() const {
  return (!stim_ || stim_->finished()) && (!plc_script_ || plc_script_->finished());
}

bool SpcSimulation::at_rest() const {
  for (std::size_t i = 0; i < program::kSpcAxes; ++i)
    if (axes_.moving(static_cast<int>(i))) return false;
  return !plc_ || plc_->idle();
}

std::string SpcSimulation::error_text() const {
  const auto st = ctl_.status();
  if (!st.error) return "";
  if (st.error_task < 0) return st.message;
  std::string where = fmt::format("task {}", st.error_task == 0 ? 'A' : 'B');
  if (st.error_program >= 0) where += fmt::format(", P{}", st.error_program);
  if (st.error_line >= 0) where += fmt::format(" N{:03}", st.error_line);
  return where + ": " + st.message;
}

report::SpcTraceRow SpcSimulation::row() const {
  report::SpcTraceRow r;
  r.t_s = time_s();
  for (std::size_t i = 0; i < program::kSpcAxes; ++i) {
    r.cmd[i] = axes_.setpoint_mm(static_cast<int>(i));
    r.act[i] = drives_[i] ? drives_[i]->measured_mm() : r.cmd[i];
  }
  r.in = ctl_.terminals().inputs;
  r.out = ctl_.terminals().outputs;
  r.ready = ctl_.terminals().get(sig::kReady);
  return r;
}

SpcRunResult run_spc(const program::spc::ProgramStore& store, const machine::MachineConfig& cfg, const SpcRunConfig& rc,
                     const std::string& registers_file) {
  SpcRunResult res;
  Registers regs;
  io::RetentiveStore retentive(registers_file);
  retentive.restore(regs);
  SpcSimulation sim(store, cfg, rc, regs);
  // The cycle writes registers in memory only; the store writes the dirty ones outside it (S-5).
  retentive.start(regs, std::chrono::milliseconds(20));

  const auto spc_axes = spc_axes_from(cfg);
  res.trace.period_s = cfg.period_s;
  res.trace.record_select = rc.controller.mode == SpcMode::RecordSelect;
  for (std::size_t i = 0; i < program::kSpcAxes; ++i)
    if (spc_axes.axis[i].present) res.trace.axes |= static_cast<std::uint8_t>(1u << i);
  if (rc.record) res.trace.rows.push_back(sim.row());

  const auto max_cycles = static_cast<std::uint64_t>(std::llround(rc.max_s / cfg.period_s));
  const auto until_cycles = static_cast<std::uint64_t>(std::llround(rc.until_s / cfg.period_s));
  const double quiet_s = sim.last_event_s() + 1.0;
  bool prev_error = false;
  while (sim.cycle() < max_cycles) {
    sim.step();
    if (rc.record) res.trace.rows.push_back(sim.row());
    const auto st = sim.controller().status();
    if (st.error && !prev_error) {
      SpcErrorEvent e{sim.time_s(), st.error_task, st.error_program, st.error_line, st.message, ""};
      e.text = fmt::format("t={:.3f} s: {}", e.t_s, sim.error_text());
      res.errors.push_back(std::move(e));
    }
    prev_error = st.error;
    if (rc.until_s > 0) {
      if (sim.cycle() >= until_cycles) break;
    } else if (sim.scripts_finished() && sim.time_s() >= quiet_s && sim.at_rest()) {
      break;
    }
  }
  retentive.stop();  // flushes once more

  res.cycles = sim.cycle();
  res.t_end_s = sim.time_s();
  res.status = sim.controller().status();
  for (std::size_t i = 0; i < program::kSpcAxes; ++i) res.final_mm[i] = sim.axes().setpoint_mm(static_cast<int>(i));
  for (int t = 0; t < 2; ++t) {
    const auto& task = sim.controller().task(t == 0 ? TaskId::A : TaskId::B);
    res.tasks[static_cast<std::size_t>(t)] = task.status();
    res.instructions[static_cast<std::size_t>(t)] = task.instructions_executed();
  }
  if (const auto* plc = sim.plc()) res.plc = std::array<PlcCounters, 2>{plc->counters(TaskId::A), plc->counters(TaskId::B)};
  res.outputs = sim.controller().terminals().outputs;
  res.ok = res.errors.empty() && !res.status.fatal;
  return res;
}

}  // namespace softmc::app
