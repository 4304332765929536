// The start-up homing sequence on simulated drives (T-4, T-5, P-9).
#include "homing_run.hpp"

#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "machine/homing.hpp"

namespace softmc::app {

core::Vec mid_travel(const machine::MachineConfig& cfg) {
  core::Vec p{};
  for (const auto& a : cfg.axes) p[a.index] = 0.5 * (a.min_mm + a.max_mm);
  return p;
}

HomingRunResult run_homing(const machine::MachineConfig& cfg, const core::Vec& power_up, double max_time_s) {
  HomingRunResult res;
  const double dt = cfg.period_s;
  std::vector<machine::AxisHoming> homing;
  std::array<int, core::kMaxAxes> slot{};
  slot.fill(-1);
  std::array<double, core::kMaxAxes> cmd{}, cmd_v{};
  for (const auto& a : cfg.axes) {
    if (!a.enabled) continue;
    res.drives[a.index] = std::make_unique<machine::SimDrive>(a, 0.0, power_up[a.index]);
    res.axis[a.index].power_up_mm = power_up[a.index];
    if (a.limit_switches) {
      slot[a.index] = static_cast<int>(homing.size());
      homing.emplace_back(a);
    }
  }
  const auto max_cycles = static_cast<std::uint64_t>(max_time_s / dt);
  std::uint64_t cycle = 0;
  const auto fail = [&](const machine::AxisConfig& a, const std::string& what) {
    res.result = fmt::format("homing {}: {} at t = {:.3f} s", core::letter(a.index), what,
                             static_cast<double>(cycle) * dt);
  };
  // Two groups: positive homing first, then negative.
  for (const auto side : {machine::HomeSide::Positive, machine::HomeSide::Negative}) {
    bool any = false;
    for (const auto& a : cfg.axes)
      if (slot[a.index] >= 0 && a.home_side == side) {
        homing[static_cast<std::size_t>(slot[a.index])].start(cmd[a.index]);
        any = true;
      }
    if (!any) continue;
    while (true) {
      bool busy = false;
      for (const auto& a : cfg.axes) {
        auto* d = res.drives[a.index].get();
        if (!d) continue;
        double vel = 0;
        if (slot[a.index] >= 0 && a.home_side == side) {
          auto& h = homing[static_cast<std::size_t>(slot[a.index])];
          const bool sw = side == machine::HomeSide::Negative ? d->limit_negative() : d->limit_positive();
          const auto c = h.step(sw, d->measured_mm(), dt);
          if (c.shift_mm != 0) d->shift_reference(c.shift_mm);
          cmd[a.index] = c.pos_mm;
          vel = c.vel_mm_s;
          if (h.failed()) {
            fail(a, h.error());
            return res;
          }
          if (!h.done()) busy = true;
        }
        cmd_v[a.index] = vel;
        d->update(cmd[a.index], vel, dt);
      }
      ++cycle;
      // Supervision: the following error, and a switch the sequence does not look for.
      for (const auto& a : cfg.axes) {
        const auto* d = res.drives[a.index].get();
        if (!d) continue;
        if (std::abs(d->following_error_mm()) > a.ferror_limit_mm) {
          fail(a, fmt::format("following error {:.3f} mm exceeds {:.3f} mm", std::abs(d->following_error_mm()),
                              a.ferror_limit_mm));
          return res;
        }
        // A closed switch is a fault where the axis is commanded towards it, except the home switch
        // while its search finds it and brakes past it. An axis standing on a switch it is not
        // moving into (waiting for its group, or moving off it) is not.
        const double v = cmd_v[a.index];
        const auto phase = slot[a.index] >= 0 ? homing[static_cast<std::size_t>(slot[a.index])].phase()
                                              : machine::HomingPhase::Idle;
        const bool searching = a.home_side == side && (phase == machine::HomingPhase::Search ||
                                                       phase == machine::HomingPhase::Brake);
        const bool neg_home = a.home_side == machine::HomeSide::Negative;
        const bool into_neg = d->limit_negative() && v < 0 && !(searching && neg_home);
        const bool into_pos = d->limit_positive() && v > 0 && !(searching && !neg_home);
        if (into_neg || into_pos) {
          fail(a, fmt::format("limit switch {}{} closed", core::letter(a.index), into_neg ? '-' : '+'));
          return res;
        }
        if (slot[a.index] >= 0)
          res.axis[a.index].overshoot_mm = std::max(res.axis[a.index].overshoot_mm,
                     neg_home ? machine::home_switch_mm(a) - d->true_mm() : d->true_mm() - machine::home_switch_mm(a));
      }
      for (const auto& a : cfg.axes)
        if (slot[a.index] >= 0 && a.home_side == side && homing[static_cast<std::size_t>(slot[a.index])].done() &&
            res.axis[a.index].time_s == 0)
          res.axis[a.index].time_s = static_cast<double>(cycle) * dt;
      if (!busy) break;
      if (cycle >= max_cycles) {
        std::string busy_axes;
        for (const auto& a : cfg.axes)
          if (slot[a.index] >= 0 && a.home_side == side && !homing[static_cast<std::size_t>(slot[a.index])].done())
            busy_axes += core::letter(a.index);
        res.result = fmt::format("homing {}: not done after {} s (home_vel_mm_s too low for the travel?)", busy_axes,
                                 max_time_s);
        return res;
      }
    }
  }
  // In position (P-7): every drive's following error within an encoder count of its command.
  for (;; ++cycle) {
    bool settled = true;
    for (const auto& a : cfg.axes) {
      auto* d = res.drives[a.index].get();
      if (d && std::abs(d->following_error_mm()) > a.mm_per_count()) settled = false;
    }
    if (settled) break;
    if (cycle >= max_cycles) {
      res.result = fmt::format("homing: the drives were not in position after {} s", max_time_s);
      return res;
    }
    for (const auto& a : cfg.axes)
      if (auto* d = res.drives[a.index].get()) d->update(cmd[a.index], 0, dt);
  }
  res.time_s = static_cast<double>(cycle) * dt;
  for (const auto& a : cfg.axes) {
    const auto* d = res.drives[a.index].get();
    if (!d) continue;
    auto& r = res.axis[a.index];
    r.homed = slot[a.index] >= 0;
    r.switch_mm = r.homed ? machine::home_switch_mm(a) : 0;
    r.position_mm = cmd[a.index];
    r.true_mm = d->true_mm();
    r.reference_error_mm = d->reference_offset_mm();
    res.position[a.index] = cmd[a.index];
  }
  res.ok = true;
  return res;
}

}  // namespace softmc::app
