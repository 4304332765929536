// Every interpolation cycle of the real CAM programs in examples/gcode/bench/ on the comparison
// machine (bench/compare_linuxcnc.py's: X, Y, Z at 100 mm/s, 1 000 mm/s², jerk 10 000 mm/s³ or
// none, P0.05, window 200), each cycle (Simulation::step: the channel feeding the planner, the
// interpolator, the simulated drives) timed alone on the thread's CPU clock. The mean is what a
// cycle costs; the 99.9th percentile and the maximum are what a real-time period must leave room
// for. One iteration runs the whole program (17–56 s of machine time).
#include <benchmark/benchmark.h>
#include <linux/perf_event.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>

#include <algorithm>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "gcode_setup.hpp"
#include "simulation.hpp"
#include "machine/config.hpp"
#include "program/iso/parser.hpp"

namespace {
using namespace softmc;

constexpr std::array<const char*, 4> kPrograms = {"surfacing", "pocket", "engraving", "plasma"};

machine::MachineConfig comparison_machine(bool jerk) {
  auto cfg = machine::default_machine();
  for (const char* ax : {"x", "y", "z"}) {
    const std::string k = std::string("axes.") + ax;
    machine::apply_override(cfg, k + ".max_vel_mm_s=100");
    machine::apply_override(cfg, k + ".max_acc_mm_s2=1000");
    machine::apply_override(cfg, k + (jerk ? ".max_jerk_mm_s3=10000" : ".max_jerk_mm_s3=0"));
    machine::apply_override(cfg, k + ".min_mm=-1000");
    machine::apply_override(cfg, k + ".max_mm=1000");
    machine::apply_override(cfg, k + ".ferror_limit_mm=1000");
  }
  machine::apply_override(cfg, "planner.tolerance_mm=0.05");
  machine::apply_override(cfg, "planner.lookahead=200");
  machine::validate(cfg);
  return cfg;
}

double cpu_us() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e6 * static_cast<double>(t.tv_sec) + 1e-3 * static_cast<double>(t.tv_nsec);
}

// The page faults this thread has taken (a software counter the kernel keeps: no hardware counter
// needed), or -1 where perf events are not allowed.
int open_page_faults() {
  perf_event_attr a{};
  a.type = PERF_TYPE_SOFTWARE;
  a.size = sizeof a;
  a.config = PERF_COUNT_SW_PAGE_FAULTS;
  a.exclude_kernel = 1;  // the thread's own faults: allowed without root at perf_event_paranoid 2
  a.exclude_hv = 1;
  return static_cast<int>(syscall(SYS_perf_event_open, &a, 0, -1, -1, 0));
}
double read_count(int fd) {
  std::uint64_t v = 0;
  if (fd < 0 || read(fd, &v, sizeof v) != sizeof v) return 0;
  return static_cast<double>(v);
}

// examples/gcode/bench/NAME.ngc as the machine's interpreter reads it (nothing where it cannot).
std::optional<program::Program> bench_program(const std::string& name, const machine::MachineConfig& cfg) {
  const auto setup = app::gcode_setup(cfg);
  auto parsed = program::iso::parse_file(std::string(SOFTMC_SOURCE_DIR) + "/examples/gcode/bench/" + name + ".ngc",
                                         setup->options());
  return std::move(parsed.program);
}

// Args: the program (index into kPrograms), jerk limits (0: trapezoids, 1: 10 000 mm/s³).
void BM_ProgramCycle(benchmark::State& state) {
  const std::string name = kPrograms[static_cast<std::size_t>(state.range(0))];
  const auto cfg = comparison_machine(state.range(1) != 0);
  const auto parsed = bench_program(name, cfg);
  if (!parsed) {
    state.SkipWithError(("cannot read " + name + ".ngc").c_str());
    return;
  }
  const program::Program& prog = *parsed;
  std::vector<double> us, faults;
  us.reserve(4'000'000);
  faults.reserve(us.capacity());
  const int pf = open_page_faults();
  for (auto _ : state) {
    state.PauseTiming();
    us.clear();
    faults.clear();
    app::Simulation sim(prog, cfg);
    state.ResumeTiming();
    while (!sim.finished() && !sim.faulted() && us.size() < us.capacity()) {
      const double f0 = read_count(pf);
      const double t0 = cpu_us();
      sim.step();
      us.push_back(cpu_us() - t0);
      faults.push_back(read_count(pf) - f0);
    }
    if (!sim.finished()) state.SkipWithError((name + " did not finish").c_str());
  }
  std::vector<double> sorted = us;
  std::sort(sorted.begin(), sorted.end());
  const auto pct = [&](double p) { return sorted.empty() ? 0.0 : sorted[static_cast<std::size_t>(p * static_cast<double>(sorted.size() - 1))]; };
  double sum = 0;
  for (double x : us) sum += x;
  state.SetLabel(name + (state.range(1) ? ", jerk 10000" : ", trapezoids"));
  state.counters["cycles"] = static_cast<double>(us.size());
  state.counters["mean_us"] = us.empty() ? 0.0 : sum / static_cast<double>(us.size());
  state.counters["p99_us"] = pct(0.99);
  state.counters["p999_us"] = pct(0.999);
  state.counters["max_us"] = sorted.empty() ? 0.0 : sorted.back();
  // Which cycle it was (the first ~30 fill the window), to find it again (callgrind, a trace).
  state.counters["max_cycle"] =
      us.empty() ? 0.0 : static_cast<double>(std::max_element(us.begin(), us.end()) - us.begin());
  if (pf >= 0) {
    double total = 0;
    for (double f : faults) total += f;
    state.counters["faults"] = total;
    state.counters["faults_max_cycle"] = faults.empty() ? 0.0 : faults[static_cast<std::size_t>(state.counters["max_cycle"])];
    close(pf);
  }
}
// Channel::load of each bench program on the comparison machine with jerk limits (its runs of
// lines thinned and smoothed into compact pieces), wall time. Args: the program; load threads (1:
// one after the other; 0: one a hardware thread, as softmc loads). The pieces are the same.
void BM_ChannelLoad(benchmark::State& state) {
  const std::string name = kPrograms[static_cast<std::size_t>(state.range(0))];
  const auto cfg = comparison_machine(true);
  const auto parsed = bench_program(name, cfg);
  if (!parsed) {
    state.SkipWithError(("cannot read " + name + ".ngc").c_str());
    return;
  }
  const program::Program& prog = *parsed;
  motion::PlannerConfig pc;
  pc.tolerance_mm = cfg.planner.tolerance_mm;
  pc.smoothing_max_turn_rad = cfg.planner.smoothing_turn_deg * 3.14159265358979323846 / 180;
  motion::Planner planner(cfg.limits(), cfg.planner_window(), pc);
  motion::Interpolator interp(planner.queue(), prog.start);
  control::Channel ch(planner, interp);
  ch.set_load_threads(static_cast<std::size_t>(state.range(1)));
  for (auto _ : state) ch.load(prog);
  state.SetLabel(name + (state.range(1) == 1 ? ", one thread" : ", every hardware thread"));
}
BENCHMARK(BM_ChannelLoad)->ArgsProduct({{0, 1, 2, 3}, {1, 0}})->UseRealTime()->Unit(benchmark::kMillisecond);

BENCHMARK(BM_ProgramCycle)->ArgsProduct({{0, 1, 2, 3}, {0, 1}})->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
