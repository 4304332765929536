// Sample-based checks shared by the profile tests: limits, continuity and finite differences at a fixed step.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "motion/profile/profile_state.hpp"

namespace softmc::motion::test {

struct Bounds {
  double v = INFINITY, a = INFINITY, j = INFINITY;  // magnitudes the samples must respect
  bool a_continuous = true;                        // false for jerk-unlimited profiles
  double scale = 1;                                // mm, for absolute position tolerances
};

// Samples `at` on [0, T] at step dt (plus the end) and checks every sample and every consecutive pair.
// Returns the number of failures (stops reporting after a few, so a broken case does not flood the log).
template <class At>
int check_samples(const At& at, double T, double dt, const Bounds& b, const std::string& what) {
  int fails = 0;
  auto fail = [&](const std::string& m, double t) {
    if (++fails <= 3) ADD_FAILURE() << what << ": " << m << " at t=" << t << " of " << T;
  };
  const double rel = 1e-9;
  const double abs_v = 1e-9 * std::max(1.0, b.v), abs_a = 1e-9 * std::max(1.0, b.a);
  ProfileState prev = at(0.0);
  double t_prev = 0;
  const long steps = static_cast<long>(std::ceil(T / dt));
  for (long k = 0; k <= steps + 1 && fails < 10; ++k) {
    const double t = std::min(T, static_cast<double>(k) * dt);
    const ProfileState x = at(t);
    if (!std::isfinite(x.s) || !std::isfinite(x.v) || !std::isfinite(x.a) || !std::isfinite(x.j)) fail("NaN", t);
    if (std::abs(x.v) > b.v * (1 + rel) + abs_v) fail("speed " + std::to_string(x.v), t);
    if (std::abs(x.a) > b.a * (1 + rel) + abs_a) fail("acceleration " + std::to_string(x.a), t);
    if (std::abs(x.j) > b.j * (1 + rel) + 1e-9 * std::max(1.0, b.j)) fail("jerk " + std::to_string(x.j), t);
    const double h = t - t_prev;
    if (h > 0) {
      // Speed continuous and consistent with |a| ≤ a_max; acceleration continuous with |j| ≤ j_max.
      if (std::abs(x.v - prev.v) > b.a * h * (1 + 1e-7) + abs_v) fail("speed jump " + std::to_string(x.v - prev.v), t);
      if (b.a_continuous && std::abs(x.a - prev.a) > b.j * h * (1 + 1e-7) + abs_a)
        fail("acceleration jump " + std::to_string(x.a - prev.a), t);
      // Position consistent with speed: the trapezoid rule's error is at most a_max·h²/4.
      const double ds = x.s - prev.s, ds_v = 0.5 * (x.v + prev.v) * h;
      if (std::abs(ds - ds_v) > 0.25 * b.a * h * h * (1 + 1e-7) + 1e-12 * b.scale)
        fail("position/speed mismatch " + std::to_string(ds - ds_v), t);
    }
    prev = x;
    t_prev = t;
    if (t >= T) break;
  }
  return fails;
}

// The sampling step the tests use: 1 ms, finer for short profiles so that every phase is seen.
inline double sample_step(double T) { return std::min(1e-3, std::max(T / 400, 1e-9)); }

}  // namespace softmc::motion::test
