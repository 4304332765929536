// Test rig for SPC tasks: a program store, registers, four axes and the I/O image, stepped by cycles.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "control/spc/task.hpp"

namespace softmc::control::spc::testing {

inline SpcAxesConfig rig_axes() {
  SpcAxesConfig c;
  c.period_s = 0.001;
  for (auto& a : c.axis) a = SpcAxisConfig{true, 500.0, 5000.0, -100.0, 2000.0};
  return c;
}

struct Rig {
  program::spc::ProgramStore store;
  Registers regs;
  TaskAxes axes{rig_axes()};
  IoImage io;
  Task a{TaskId::A, store, regs, axes};
  Task b{TaskId::B, store, regs, axes};
  long cycles = 0;

  void load(int n, const std::string& text, bool record_select = false) {
    core::Diagnostics d;
    const bool ok = store.add(n, text, "P" + std::to_string(n) + ".spc", {record_select, n}, d);
    for (const auto& x : d) ADD_FAILURE() << x.format();
    ASSERT_TRUE(ok);
  }
  void load_folder(const std::string& dir, bool record_select = false) {
    for (const auto& x : store.load_folder(dir, {record_select, -1})) ADD_FAILURE() << x.format();
  }
  // The cycle order of task.hpp: tasks, then axes.
  void cycle() {
    a.update(0.001, io);
    b.update(0.001, io);
    axes.step();
    ++cycles;
  }
  // Cycles until `done` holds (checked after each cycle); returns the number run, or -1 on timeout.
  long run_until(const std::function<bool()>& done, long max_cycles = 100000) {
    for (long i = 1; i <= max_cycles; ++i) {
      cycle();
      if (done()) return i;
    }
    return -1;
  }
  double x() const { return axes.setpoint_mm(0); }
};

}  // namespace softmc::control::spc::testing
