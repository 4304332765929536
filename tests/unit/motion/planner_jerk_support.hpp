// Helpers the PlannerJerk tests share: jerk limits, the within-every-limit check, random limits and path draws.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "planner_run.hpp"

namespace softmc::motion::testing {

inline constexpr double kRatioNoise = 1e-4;  // third differences of closed-form setpoints: rounding / dt³

inline MachineLimits jerk_limits(double v = 100, double a = 1000, double j = 20000) {
  auto m = xyz_limits(v, a);
  for (int i = 0; i < 3; ++i) m.axis[i].j_max_mm_s3 = j;
  return m;
}

inline void expect_within(const RunResult& res, double tol, const char* what) {
  ASSERT_EQ(res.error, PlanResult::Ok) << what;
  ASSERT_TRUE(res.finished) << what;
  EXPECT_TRUE(res.fig.finite) << what;
  EXPECT_LE(res.fig.v_ratio, 1 + kRatioNoise) << what << ": " << res.fig.describe();
  EXPECT_LE(res.fig.a_ratio, 1 + kRatioNoise) << what << ": " << res.fig.describe();
  EXPECT_LE(res.fig.j_ratio, 1 + kRatioNoise) << what << ": " << res.fig.describe();
  EXPECT_LE(res.fig.deviation_mm, tol + 1e-9) << what << ": " << res.fig.describe();
}

// Per-axis limits drawn at random: speed 20–320 mm/s, acceleration 200–5200 mm/s², jerk
// 2 000–102 000 mm/s³, travel ±1000 mm, 1 ms cycle.
inline MachineLimits random_jerk_limits(std::mt19937_64& rng, std::uniform_real_distribution<double>& u) {
  MachineLimits lim;
  for (int i = 0; i < 3; ++i) lim.axis[i] = {20 + 300 * u(rng), 200 + 5000 * u(rng), 2000 + 100000 * u(rng), -1000, 1000};
  lim.period_s = 0.001;
  return lim;
}

// A chain of n requests from the origin, each from where the last one ended, tagged 0..n−1 with
// tolerance tol: draw(k, at, before, r) sets the k-th one's geometry and feed (`before`: the
// requests so far).
template <typename Draw>
std::vector<PathRequest> chain(int n, double tol, Draw draw) {
  std::vector<PathRequest> reqs;
  core::Vec at = xyz(0, 0, 0);
  for (int k = 0; k < n; ++k) {
    PathRequest r;
    r.tag = static_cast<std::uint32_t>(k);
    r.tolerance_mm = tol;
    draw(k, at, reqs, r);
    reqs.push_back(r);
    at = r.geom.end;
  }
  return reqs;
}

// X, Y, Z with the given speed, acceleration and jerk each (travel ±1000 mm), at `period_s`: the
// limits of a seed found by exploration, written out.
inline MachineLimits limits_vaj(const std::array<std::array<double, 3>, 3>& vaj, double period_s) {
  MachineLimits lim;
  for (std::size_t i = 0; i < 3; ++i) lim.axis[i] = {vaj[i][0], vaj[i][1], vaj[i][2], -1000, 1000};
  lim.period_s = period_s;
  return lim;
}

// Seeded random paths with random per-axis limits (speed, acceleration, jerk) and a tolerance
// drawn from `tols`: `make` draws the path; every setpoint must keep every axis's limits and P, and
// the end must be exact.
inline void expect_random_jerk_paths(std::uint64_t seeds, std::initializer_list<double> tols,
                              const std::function<std::vector<PathRequest>(std::mt19937_64&,
                                                                           std::uniform_real_distribution<double>&, double)>& make) {
  const std::vector<double> tol_of(tols);
  for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const MachineLimits lim = random_jerk_limits(rng, u);
    const double tol = tol_of[rng() % tol_of.size()];
    const std::vector<PathRequest> reqs = make(rng, u, tol);
    const auto res = run_path(lim, reqs, 3 + rng() % 200);
    expect_within(res, tol, ("seed " + std::to_string(seed)).c_str());
    EXPECT_LE(res.block_v_ratio, 1 + 1e-9) << "seed " << seed;
    EXPECT_LE(res.block_a_ratio, 1 + 1e-6) << "seed " << seed;
    EXPECT_LE(res.block_j_ratio, 1 + 1e-4) << "seed " << seed;
    EXPECT_EQ(res.end, reqs.back().geom.end) << "seed " << seed;
    if (::testing::Test::HasFailure()) break;
  }
}

// A chain of lines and arcs joined tangentially, with a corner now and then (the draws of
// RandomTangentChainsOfLinesAndArcsKeepTheLimits).
inline std::vector<PathRequest> tangent_chain(std::mt19937_64& rng, std::uniform_real_distribution<double>& u, double tol) {
  std::vector<PathRequest> reqs;
  core::Vec at = xyz(0, 0, 0);
  double h = 2 * std::numbers::pi * u(rng);  // heading
  const int n = 3 + static_cast<int>(rng() % 30);
  for (int k = 0; k < n; ++k) {
    PathRequest r;
    r.feed_mm_s = 5 + 300 * u(rng);
    r.tag = static_cast<std::uint32_t>(k);
    r.tolerance_mm = tol;
    if (rng() % 8 == 0) h += (u(rng) < 0.5 ? -1 : 1) * (0.05 + 2.5 * u(rng));  // a corner
    if (rng() % 2 == 0) {
      const double len = rng() % 4 == 0 ? 0.01 + 0.1 * u(rng) : 0.5 + 20 * u(rng);
      r.geom = make_line(at, at + xyz(std::cos(h), std::sin(h)) * len);
    } else {
      const double rad = rng() % 4 == 0 ? 0.2 + 0.5 * u(rng) : 0.5 + 20 * u(rng);
      const double dir = rng() % 2 ? 1.0 : -1.0, sweep = 0.05 + 3 * u(rng);
      const double c0 = at[0] - dir * rad * std::sin(h), c1 = at[1] + dir * rad * std::cos(h);
      const double a0 = std::atan2(at[1] - c1, at[0] - c0), a1 = a0 + dir * sweep;
      const core::Vec to = xyz(c0 + rad * std::cos(a1), c1 + rad * std::sin(a1));
      r.geom = make_arc(at, to, 0, 1, c0, c1, dir > 0 ? 1 : -1);
      h += dir * sweep;
    }
    reqs.push_back(r);
    at = r.geom.end;
  }
  return reqs;
}

}  // namespace softmc::motion::testing
