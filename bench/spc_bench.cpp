// Cost of the SPC tasks per cycle: both tasks executing non-motion instructions, a #TNI wait, and whole
// controller cycles (modes, tasks, axes) in Record Select with the reference PLC and in Start/Stop.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>

#include "control/spc/controller.hpp"
#include "control/spc/plc_client.hpp"
#include "control/spc/task.hpp"

using namespace softmc;
using namespace softmc::control::spc;

namespace {

struct SpcRig {
  program::spc::ProgramStore store;
  Registers regs;
  TaskAxes axes{[] {
    SpcAxesConfig c;
    for (auto& a : c.axis) a = SpcAxisConfig{true, 500, 5000, -100, 2000};
    return c;
  }()};
  IoImage io;
  Task a{TaskId::A, store, regs, axes};
  Task b{TaskId::B, store, regs, axes};

  void load(int n, const char* text) {
    core::Diagnostics d;
    if (!store.add(n, text, "bench.spc", {false, n}, d)) std::abort();
  }
};

// Registers, flags, outputs and jumps only: every cycle runs kMaxInstructionsPerCycle per task.
// Each task counts in its own register (R1 / R2): the registers are shared by both tasks.
constexpr const char* kBusyA =
    "N000 #AR1=1\nN001 #SF3\nN002 #SQ2.0\nN003 G29 @4 X0.01\nN004 #RF3\nN005 #RQ2.0\n"
    "N006 #TR1=30000 8\nN007 E05 0\nN008 #LR1=0\nN009 G28 @4 X0\nN010 E05 0\n";
constexpr const char* kBusyB =
    "N000 #AR2=1\nN001 #SF4\nN002 #SQ2.1\nN003 G29 @5 Y0.01\nN004 #RF4\nN005 #RQ2.1\n"
    "N006 #TR2=30000 8\nN007 E05 0\nN008 #LR2=0\nN009 G28 @5 Y0\nN010 E05 0\n";

void BM_SpcTwoTasksNonMotionCycle(benchmark::State& state) {
  SpcRig r;
  r.load(1, kBusyA);
  r.load(2, kBusyB);
  r.a.set_program(1);
  r.b.set_program(2);
  r.a.start();
  r.b.start();
  for (auto _ : state) {
    r.a.update(0.001, r.io);
    r.b.update(0.001, r.io);
    benchmark::DoNotOptimize(r.io.outputs);
  }
  if (r.a.status().error || r.b.status().error) state.SkipWithError(r.a.status().error ? r.a.status().message : r.b.status().message);
  const double n = static_cast<double>(r.a.instructions_executed() + r.b.instructions_executed());
  state.counters["instr_per_cycle"] = n / static_cast<double>(state.iterations());
  state.counters["ns_per_instr"] = benchmark::Counter(n, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_SpcTwoTasksNonMotionCycle);

// `N102 #TNI0.0 102` in both tasks: one evaluation per task per cycle.
void BM_SpcWaitLoopCycle(benchmark::State& state) {
  SpcRig r;
  r.load(1, "N102 #TNI0.0 102\nN103 #SQ2.0\nN104 M30\n");
  r.a.set_program(1);
  r.b.set_program(1);
  r.a.start();
  r.b.start();
  for (auto _ : state) {
    r.a.update(0.001, r.io);
    r.b.update(0.001, r.io);
    benchmark::DoNotOptimize(r.io.outputs);
  }
  state.counters["instr_per_cycle"] = static_cast<double>(r.a.instructions_executed() + r.b.instructions_executed()) /
                                      static_cast<double>(state.iterations());
}
BENCHMARK(BM_SpcWaitLoopCycle);

SpcAxesConfig modes_axes() {
  SpcAxesConfig c;
  c.period_s = 0.001;
  for (auto& a : c.axis) a = SpcAxisConfig{true, 1000.0, 20000.0, -10.0, 1000.0};
  return c;
}

// One controller cycle plus one PLC scan in Record Select, both tasks kept busy with orders: X by G01
// trapezoids (task A), Y by G02 sine-squared moves (task B), handshakes on the wires (S-9, S-10).
void BM_SpcRecordSelectCycleWithPlc(benchmark::State& state) {
  program::spc::ProgramStore store;
  std::string a, b;
  for (int n = 0; n < 32; ++n) {
    a += "N" + std::to_string(100 + n).substr(1) + " G01 X" + std::to_string(10 + 20 * n) + " FX0\n";
    b += "N" + std::to_string(100 + n).substr(1) + " G02 Y" + std::to_string(10 + 20 * n) + " FY50\n";
  }
  core::Diagnostics d;
  if (!store.add(1, a, "P1.spc", {true, 1}, d) || !store.add(2, b, "P2.spc", {true, 2}, d)) std::abort();
  Registers regs;
  TaskAxes axes{modes_axes()};
  ControllerConfig c;
  c.mode = SpcMode::RecordSelect;
  c.program_a = 1;
  c.program_b = 2;
  c.self_test_s = 0.01;
  Controller ctl(c, store, regs, axes);
  PlcClient plc({}, 1 << 20);
  ctl.terminals().set(sig::kEnable, true);
  ctl.terminals().set(sig::kStop, true);
  long i = 0;
  for (auto _ : state) {
    if (plc.pending(TaskId::A) < 2) {
      plc.order(TaskId::A, static_cast<int>((i * 7) % 32));
      plc.order(TaskId::B, static_cast<int>((i * 11) % 32));
    }
    plc.cycle(0.001, ctl.terminals());
    ctl.update(0.001);
    ++i;
  }
  if (ctl.status().error) state.SkipWithError(ctl.status().message);
  state.counters["orders_done"] = static_cast<double>(plc.counters(TaskId::A).completed + plc.counters(TaskId::B).completed);
}
BENCHMARK(BM_SpcRecordSelectCycleWithPlc);

// One controller cycle in Start/Stop with task A waiting on an input (`#TNI2.0 0`): the idle floor.
void BM_SpcStartStopIdleCycle(benchmark::State& state) {
  program::spc::ProgramStore store;
  core::Diagnostics d;
  if (!store.add(1, "N000 #TNI2.0 0\nN001 M30\n", "P1.spc", {false, 1}, d)) std::abort();
  Registers regs;
  TaskAxes axes{modes_axes()};
  ControllerConfig c;
  c.program_a = 1;
  c.self_test_s = 0.001;
  Controller ctl(c, store, regs, axes);
  ctl.terminals().set(sig::kEnable, true);
  ctl.terminals().set(sig::kStop, true);
  for (int k = 0; k < 5; ++k) ctl.update(0.001);
  ctl.terminals().set(sig::kStart, true);
  for (int k = 0; k < 20; ++k) ctl.update(0.001);  // START through the 5 ms input filter: task A runs
  if (!ctl.task(TaskId::A).status().running) state.SkipWithError("task A is not waiting");
  for (auto _ : state) ctl.update(0.001);
}
BENCHMARK(BM_SpcStartStopIdleCycle);

}  // namespace
