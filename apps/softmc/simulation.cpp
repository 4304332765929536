// Simulated run: one cycle = read drives → update channel and interpolator → write setpoints → supervise.
#include "simulation.hpp"

#include "control/travel_check.hpp"
#include "report/programmed_path.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <cstdio>

namespace softmc::app {

namespace {
// The [planner] keys (docs/configuration.md) as the planner and the interpolator take them.
motion::PlannerConfig planner_config(const machine::MachineConfig& cfg) {
  motion::PlannerConfig pc;
  pc.tolerance_mm = cfg.planner.tolerance_mm;
  pc.max_feed_override = cfg.planner.max_feed_override;
  pc.merge_share = cfg.planner.merge_share;
  pc.fillet_share = cfg.planner.fillet_share;
  pc.corner_stop_when_quicker = cfg.planner.corner_stops;
  pc.smoothing_max_turn_rad = cfg.planner.smoothing_turn_deg * std::numbers::pi / 180;
  return pc;
}
motion::InterpolatorConfig interpolator_config(const machine::MachineConfig& cfg) {
  motion::InterpolatorConfig ic;
  ic.max_feed_override = cfg.planner.max_feed_override;
  ic.emergency_accel_scale = cfg.planner.emergency_accel_scale;
  ic.max_horizon_blocks = static_cast<int>(cfg.planner_window());
  ic.guard_simulate = cfg.planner.jerk_guard_simulate;
  ic.axis_limits = cfg.limits();
  ic.corner_overlap = cfg.planner.corner_overlap;
  return ic;
}
}  // namespace

Simulation::Simulation(const program::Program& prog, const machine::MachineConfig& cfg,
                       const control::ChannelStimulus* stimulus, Drives* drives)
    : prog_(prog),
      cfg_(cfg),
      planner_(cfg.limits(), cfg.planner_window(), planner_config(cfg)),
      interp_(planner_.queue(), prog.start, interpolator_config(cfg)),
      channel_(planner_, interp_),
      exec_(cfg.period_s) {
  channel_.load(prog);
  if (stimulus) player_.emplace(*stimulus);
  // One drive per configured axis; the machine starts where the program assumes.
  for (const auto& a : cfg_.axes) {
    if (!a.enabled) continue;
    if (drives && (*drives)[a.index])
      drives_[a.index] = std::move((*drives)[a.index]);
    else
      drives_[a.index] = std::make_unique<machine::SimDrive>(a, prog.start[a.index]);
  }

  // The cycle's fixed order (docs/code_flow.md). The drives are read implicitly: SimDrive keeps its
  // measured position from the last write, which is what a real drive's feedback would deliver.
  exec_.add("update", [this](const runtime::CycleClock& c) {
    // The PLC's writes due by this cycle's start take effect now, at the cycle boundary.
    if (player_) player_->apply(c.t_s, signals_);
    channel_.apply(signals_);
    channel_.update(c.dt_s);
    interp_.step(c.dt_s);
    channel_.sync_outputs();
  });
  exec_.add("write", [this](const runtime::CycleClock& c) {
    const auto& sp = interp_.setpoint();
    for (std::size_t i = 0; i < core::kMaxAxes; ++i)
      if (drives_[i]) drives_[i]->update(sp.pos[i], sp.vel[i], c.dt_s);
  });
  exec_.add("supervise", [this](const runtime::CycleClock& c) { supervise(c); });
  channel_.start(prog.start);
}

// rt-safe
void Simulation::supervise(const runtime::CycleClock& c) {
  if (channel_.state() == control::ChannelState::Fault) return;
  for (const auto& a : cfg_.axes) {
    const auto* d = drives_[a.index].get();
    if (!d) continue;
    const double fe = d->following_error_mm();
    if (std::abs(fe) > a.ferror_limit_mm) {
      std::snprintf(fault_buf_, sizeof fault_buf_, "following error on %c: %.3f mm exceeds %.3f mm at t=%.3f s",
                    core::letter(a.index), std::abs(fe), a.ferror_limit_mm, c.t_s + c.dt_s);
      channel_.fault(fault_buf_);
    } else if (d->limit_negative() || d->limit_positive()) {
      std::snprintf(fault_buf_, sizeof fault_buf_, "limit switch %c%c closed at t=%.3f s", core::letter(a.index),
                    d->limit_negative() ? '-' : '+', c.t_s + c.dt_s);
      channel_.fault(fault_buf_);
    }
    if (channel_.state() == control::ChannelState::Fault) break;
  }
  // Stop at once: the setpoint stays where it is and nothing more is interpolated.
  if (channel_.state() == control::ChannelState::Fault) planner_.queue().clear();
}

namespace {
std::string location(const program::Program& prog, std::uint32_t instruction) {
  const auto& ins = prog.instructions;
  const core::SourceLoc loc = ins.empty() ? core::SourceLoc{} : ins[std::min<std::size_t>(instruction, ins.size() - 1)].loc;
  return fmt::format("{}:{}:{}", prog.files.empty() ? "" : prog.file_of(loc), loc.line, loc.col);
}
}  // namespace

std::string Simulation::fault_text() const {
  return fmt::format("{}: {}", location(prog_, channel_.fault_instruction()), channel_.fault_message());
}

bool Simulation::held_for_good() const {
  if ((player_ && !player_->finished()) || channel_.state() != control::ChannelState::Running) return false;
  const auto& sp = interp_.setpoint();
  return sp.moving && sp.path_v == 0 && !interp_.overlapping() &&
         (interp_.halted_at_rest() || interp_.feed_override() == 0);
}

std::string Simulation::stop_text() const {
  const char* by = channel_.stop_kind() == motion::StopKind::Emergency ? "P-5 emergency stop" : "P-5 stop";
  // The instruction whose programmed motion the machine stands on: a smoothing piece or a blend
  // carries its neighbour's tag over part of its length.
  const auto& sp = interp_.setpoint();
  const auto at = channel_.stopped_in_motion()
                      ? report::programmed_path(prog_).nearest_instruction(sp.pos, sp.tag, sp.tag_last)
                      : std::nullopt;
  return fmt::format("stopped ({}) at {}, t = {:.3f} s", by,
                     location(prog_, at ? static_cast<std::uint32_t>(*at) : channel_.stop_instruction()), time_s());
}

std::string Simulation::held_text() const {
  std::string why;
  const auto add = [&](const std::string& s) { why += why.empty() ? s : ", " + s; };
  if (signals_.feed_hold) add("feed_hold is 1");
  for (const auto& a : cfg_.axes)
    if (a.enabled && !signals_.axis_enable[a.index]) add(fmt::format("axis_enable[{}] is 0", core::letter(a.index)));
  if (interp_.feed_override() == 0) add("the feed override is 0");
  return fmt::format("{}: held at rest at t = {:.3f} s ({}) and no stimulus event left to release it",
                     location(prog_, interp_.setpoint().tag), time_s(), why);
}

report::TraceRow Simulation::row() const {
  const auto& sp = interp_.setpoint();
  report::TraceRow r;
  r.t_s = time_s();
  r.cmd = sp.pos;
  r.vel = sp.vel;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) r.act[i] = drives_[i] ? drives_[i]->measured_mm() : sp.pos[i];
  r.path_v = sp.path_v;
  r.tag = sp.tag;
  r.tag_last = sp.tag_last;
  r.moving = sp.moving;
  r.rapid = sp.rapid;
  r.tool_on = channel_.tool_on();
  r.dout = channel_.digital_outputs();
  r.aout = channel_.analog_outputs();
  // From the cycle the brake ends in (the channel sees it in the next one) to the end of the run.
  r.stopped = (channel_.state() == control::ChannelState::Stopping || channel_.state() == control::ChannelState::Stopped) &&
              channel_.stopped_in_motion();
  return r;
}

SimResult simulate(const program::Program& prog, const machine::MachineConfig& cfg, const SimOptions& opt) {
  SimResult res;
  res.trace.period_s = cfg.period_s;
  res.trace.axes = cfg.axis_mask();
  // Soft limits before motion (P-9): a path that leaves the travel never starts.
  if (const auto travel = control::check_travel(prog, cfg.limits()); !travel.empty()) {
    res.result = travel.front().format();
    return res;
  }
  Simulation sim(prog, cfg, opt.stimulus, opt.drives);
  const auto take = [&] {
    if (!opt.record && !opt.on_row) return;
    const report::TraceRow row = sim.row();
    if (opt.on_row) opt.on_row(row);
    if (opt.record) res.trace.rows.push_back(row);
  };
  take();  // t = 0: where the machine starts

  const auto max_cycles = static_cast<std::uint64_t>(opt.max_time_s / cfg.period_s);
  const double n_ins = static_cast<double>(std::max<std::size_t>(1, prog.instructions.size()));
  std::uint64_t next_progress = 0;
  while (true) {
    sim.step();
    take();
    if (opt.on_progress && sim.cycle() >= next_progress) {
      opt.on_progress(static_cast<double>(sim.setpoint().tag) / n_ins);
      next_progress = sim.cycle() + 1000;
    }
    if (sim.finished()) {
      res.ok = true;
      break;
    }
    if (sim.faulted()) {
      res.result = sim.fault_text();
      break;
    }
    if (sim.stopped()) {
      res.ok = res.stopped = true;
      res.result = sim.stop_text();
      break;
    }
    if (sim.held_for_good()) {
      res.result = sim.held_text();
      break;
    }
    if (sim.cycle() >= max_cycles) {
      res.result = fmt::format("timeout: program still running after {} s", opt.max_time_s);
      break;
    }
  }
  if (opt.on_progress) opt.on_progress(1.0);
  res.cycles = sim.cycle();
  return res;
}

}  // namespace softmc::app
