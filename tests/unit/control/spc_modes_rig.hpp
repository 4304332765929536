// Test rig for the SPC operating modes: a real Controller (real tasks, real axes) whose terminals a
// test drives like wires; the axes' actual positions follow their setpoints unless a test blocks one.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <string>

#include "control/spc/controller.hpp"

namespace softmc::control::spc::modes_testing {

inline constexpr double kDt = 0.001;

inline SpcAxesConfig modes_axes() {
  SpcAxesConfig c;
  c.period_s = kDt;
  for (auto& a : c.axis) a = SpcAxisConfig{true, 1000.0, 20000.0, -10.0, 1000.0};
  return c;
}

struct ModesRig {
  program::spc::ProgramStore store;
  Registers regs;
  TaskAxes axes{modes_axes()};
  std::unique_ptr<Controller> ctl;
  std::array<bool, kSpcAxes> blocked{};
  std::array<double, kSpcAxes> block_mm{};
  long cycles = 0;

  void load(int n, const std::string& text, bool record_select) {
    core::Diagnostics d;
    const bool ok = store.add(n, text, "P" + std::to_string(n) + ".spc", {record_select, n}, d);
    for (const auto& x : d) ADD_FAILURE() << x.format();
    ASSERT_TRUE(ok);
  }
  // Builds the controller; the terminals start as wired at power-up: ENABLE=1, STOP=1 (S-8/S-9).
  void power_up(ControllerConfig cfg, bool enable = true, bool stop = true) {
    ctl = std::make_unique<Controller>(cfg, store, regs, axes);
    wires().set(sig::kEnable, enable);
    wires().set(sig::kStop, stop);
  }
  IoImage& wires() { return ctl->terminals(); }
  bool out(IoAddress a) { return wires().get(a); }
  void set(IoAddress a, bool v) { wires().set(a, v); }

  // A blocked axis: the load stays where it was blocked whatever the setpoint (an obstruction).
  void block(int axis) {
    blocked[static_cast<std::size_t>(axis)] = true;
    block_mm[static_cast<std::size_t>(axis)] = axes.actual_mm(axis);
  }
  void unblock(int axis) { blocked[static_cast<std::size_t>(axis)] = false; }

  void cycle() {
    for (int a = 0; a < static_cast<int>(kSpcAxes); ++a) {
      const auto i = static_cast<std::size_t>(a);
      axes.set_actual_mm(a, blocked[i] ? block_mm[i] : axes.setpoint_mm(a));
    }
    ctl->update(kDt);
    ++cycles;
  }
  void run(double seconds) {
    const long n = static_cast<long>(seconds / kDt + 0.5);
    for (long i = 0; i < n; ++i) cycle();
  }
  // Cycles until `done` holds; returns the cycles run, or -1 on timeout.
  long run_until(const std::function<bool()>& done, double max_s = 10.0) {
    const long n = static_cast<long>(max_s / kDt);
    for (long i = 1; i <= n; ++i) {
      cycle();
      if (done()) return i;
    }
    return -1;
  }
  // A pulse of `seconds` on an input, then the input back to 0.
  void pulse(IoAddress a, double seconds) {
    set(a, true);
    run(seconds);
    set(a, false);
  }
  double x() const { return axes.setpoint_mm(0); }
  double y() const { return axes.setpoint_mm(1); }
};

}  // namespace softmc::control::spc::modes_testing
