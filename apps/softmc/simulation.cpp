// Simulated run: one cycle = read drives → update channel and interpolator → write setpoints → supervise.
#include "simulation.hpp"

#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <vector>

#include "control/channel.hpp"
#include "machine/sim_drive.hpp"
#include "motion/interp/interpolator.hpp"
#include "motion/planner/planner.hpp"
#include "runtime/executor.hpp"

namespace softmc::app {

std::vector<std::string> cycle_order() { return {"read", "update", "write", "supervise"}; }

SimResult simulate(const program::Program& prog, const machine::MachineConfig& cfg, const SimOptions& opt) {
  SimResult res;
  const auto limits = cfg.limits();
  motion::Planner planner(limits, cfg.planner_queue);
  motion::Interpolator interp(planner.queue(), prog.start);
  control::Channel channel(planner, interp);
  channel.load(prog);

  // One drive per configured axis, indexed by axis; the machine starts where the program assumes.
  std::array<std::unique_ptr<machine::SimDrive>, core::kMaxAxes> drives{};
  for (const auto& a : cfg.axes)
    if (a.enabled) drives[a.index] = std::make_unique<machine::SimDrive>(a, prog.start[a.index]);

  core::Vec measured = prog.start;
  std::string fault;  // set by supervision; read after the cycle (not rt: simulation front end)
  char fault_buf[256] = {0};

  runtime::VirtualExecutor exec(cfg.period_s);
  exec.add("read", [&](const runtime::CycleClock&) {
    for (std::size_t i = 0; i < core::kMaxAxes; ++i)
      if (drives[i]) measured[i] = drives[i]->measured_mm();
  });
  exec.add("update", [&](const runtime::CycleClock& c) {
    channel.update(c.dt_s);
    interp.step(c.dt_s);
  });
  exec.add("write", [&](const runtime::CycleClock& c) {
    const auto& sp = interp.setpoint();
    for (std::size_t i = 0; i < core::kMaxAxes; ++i)
      if (drives[i]) drives[i]->update(sp.pos[i], sp.vel[i], c.dt_s);
  });
  exec.add("supervise", [&](const runtime::CycleClock& c) {
    if (channel.state() == control::ChannelState::Fault) return;
    for (const auto& a : cfg.axes) {
      const auto* d = drives[a.index].get();
      if (!d) continue;
      const double fe = d->following_error_mm();
      if (std::abs(fe) > a.ferror_limit_mm) {
        std::snprintf(fault_buf, sizeof fault_buf, "following error on %c: %.3f mm exceeds %.3f mm at t=%.3f s",
                      core::letter(a.index), fe, a.ferror_limit_mm, c.t_s + c.dt_s);
        channel.fault(fault_buf);
      } else if (d->limit_negative() || d->limit_positive()) {
        std::snprintf(fault_buf, sizeof fault_buf, "limit switch %c%c closed at t=%.3f s", core::letter(a.index),
                      d->limit_negative() ? '-' : '+', c.t_s + c.dt_s);
        channel.fault(fault_buf);
      }
    }
    if (channel.state() == control::ChannelState::Fault) {
      planner.queue().clear();  // stop: the setpoint stays where it is
    }
  });

  res.trace.period_s = cfg.period_s;
  res.trace.axes = cfg.axis_mask();
  channel.start(prog.start);

  const std::uint64_t max_cycles = static_cast<std::uint64_t>(opt.max_time_s / cfg.period_s);
  const std::size_t n_ins = std::max<std::size_t>(1, prog.instructions.size());
  std::uint64_t next_progress = 0;
  while (true) {
    exec.step();
    if (opt.record) {
      const auto& sp = interp.setpoint();
      report::TraceRow row;
      row.t_s = static_cast<double>(exec.clock().cycle) * cfg.period_s;
      row.cmd = sp.pos;
      row.vel = sp.vel;
      for (std::size_t i = 0; i < core::kMaxAxes; ++i) row.act[i] = drives[i] ? drives[i]->measured_mm() : sp.pos[i];
      row.path_v = sp.path_v;
      row.tag = sp.tag;
      row.moving = sp.moving;
      row.rapid = sp.rapid;
      row.tool_on = channel.tool_on();
      res.trace.rows.push_back(row);
    }
    if (opt.on_progress && exec.clock().cycle >= next_progress) {
      opt.on_progress(static_cast<double>(channel.pc()) / static_cast<double>(n_ins));
      next_progress = exec.clock().cycle + 1000;
    }
    const auto st = channel.state();
    if (st == control::ChannelState::Finished) {
      res.ok = true;
      break;
    }
    if (st == control::ChannelState::Fault) {
      const auto& loc = prog.instructions.empty() ? core::SourceLoc{} : prog.instructions[std::min<std::size_t>(
                                                                              channel.fault_instruction(),
                                                                              prog.instructions.size() - 1)].loc;
      res.result = fmt::format("{}:{}:{}: {}", prog.files.empty() ? "" : prog.files[0], loc.line, loc.col,
                               channel.fault_message());
      break;
    }
    if (exec.clock().cycle >= max_cycles) {
      res.result = fmt::format("timeout: program still running after {} s", opt.max_time_s);
      break;
    }
  }
  if (opt.on_progress) opt.on_progress(1.0);
  res.cycles = exec.clock().cycle;
  return res;
}

}  // namespace softmc::app
