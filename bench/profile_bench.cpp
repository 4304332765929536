// Cost of 1-D profile planning and sampling: plan_scurve, plan_sin2, Otg1::update (the on-the-fly takeover),
// and the per-cycle sampling at(t) / step(dt).
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "motion/profile/otg1.hpp"
#include "motion/profile/profile.hpp"

using namespace softmc::motion;

namespace {

struct Case {
  double length, v0, v1;
};

// Seeded mix of long (cruising) and short (no cruise) moves with entry/exit speeds that fit.
std::vector<Case> cases() {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> U(0, 1);
  std::vector<Case> c;
  for (int i = 0; i < 1024; ++i) c.push_back({std::pow(10, -1 + 3 * U(rng)), 20 * U(rng), 20 * U(rng)});
  return c;
}

}  // namespace

static void BM_PlanScurve(benchmark::State& state) {
  const auto c = cases();
  std::size_t i = 0;
  for (auto _ : state) {
    const Case& k = c[i++ & 1023];
    benchmark::DoNotOptimize(plan_scurve(k.length, k.v0, k.v1, 200, 2000, 50000));
  }
}
BENCHMARK(BM_PlanScurve);

static void BM_PlanSin2(benchmark::State& state) {
  const auto c = cases();
  std::size_t i = 0;
  for (auto _ : state) {
    const Case& k = c[i++ & 1023];
    benchmark::DoNotOptimize(plan_sin2(k.length, k.v0, k.v1, 200, 2000, 0));
  }
}
BENCHMARK(BM_PlanSin2);

static void BM_ProfileAt(benchmark::State& state) {
  const auto kind = static_cast<ProfileKind>(state.range(0));
  const Profile p = *plan_profile(kind, 100, 0, 0, 200, 2000, 50000);
  double t = 0;
  const double T = p.duration();
  for (auto _ : state) {
    benchmark::DoNotOptimize(p.at(t));
    t += 0.001;
    if (t > T) t = 0;
  }
  state.SetLabel(to_string(kind));
}
BENCHMARK(BM_ProfileAt)->Arg(0)->Arg(1)->Arg(2);

// A moving axis given a new target: the SPC takeover on the fly (spc200.md S-2), from random states.
static void BM_OtgUpdate(benchmark::State& state) {
  const OtgLimits lim{200, 2000, 50000};
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> U(-1, 1);
  std::vector<ProfileState> from;
  std::vector<double> targets;
  for (int i = 0; i < 1024; ++i) {
    from.push_back({100 * U(rng), 150 * U(rng), 1000 * U(rng), 0});
    targets.push_back(300 * U(rng));
  }
  Otg1 g;
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++ & 1023;
    g.reset(from[k]);
    benchmark::DoNotOptimize(g.update(targets[k], lim));
  }
}
BENCHMARK(BM_OtgUpdate);

static void BM_OtgStep(benchmark::State& state) {
  const OtgLimits lim{200, 2000, 50000};
  Otg1 g(0);
  g.update(1e6, lim);
  for (auto _ : state) benchmark::DoNotOptimize(g.step(0.001));
}
BENCHMARK(BM_OtgStep);
