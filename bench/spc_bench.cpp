// Cost of the SPC tasks per cycle: both tasks executing non-motion instructions, and a #TNI wait.
#include <benchmark/benchmark.h>

#include <cstdlib>

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

}  // namespace
