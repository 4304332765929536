// Test rig: streams path requests through Planner and Interpolator like the Channel does, cycle by
// cycle, and feeds every setpoint to the trace checker.
#pragma once

#include <cmath>
#include <functional>
#include <vector>

#include "motion/interp/interpolator.hpp"
#include "motion/planner/planner.hpp"
#include "trace_checker.hpp"

namespace softmc::motion::testing {

struct RunResult {
  TraceFigures fig;
  core::Vec end;
  std::uint64_t cycles = 0;  // cycles until idle
  double max_path_v = 0;
  bool finished = false;
  PlanResult error = PlanResult::Ok;
  // The blocks' own limits (jerk mode: the contract between planner and follower, finer than the
  // axes' in the trace): the largest path speed over the executing block's hard cap, and the
  // largest mean path acceleration of a cycle, |Δv|/dt, over the larger acceleration limit of the
  // blocks it began and ended on (lenient where a cycle passes a whole block in between).
  // Likewise the mean path jerk of two cycles, |Δv_k − Δv_k−1|/dt², over the largest jerk limit of
  // the blocks they touched at their ends.
  double block_v_ratio = 0, block_a_ratio = 0, block_j_ratio = 0;
};

// Called before every cycle with the cycle number; may act on the interpolator (override, hold...).
using CycleHook = std::function<void(std::uint64_t, Interpolator&)>;

inline RunResult run_path(const MachineLimits& lim, const std::vector<PathRequest>& reqs, std::size_t capacity,
                          const PlannerConfig& pc = {}, const CycleHook& hook = {},
                          std::uint64_t max_cycles = 20'000'000, const InterpolatorConfig& ic = {},
                          std::vector<core::Vec>* trace = nullptr) {
  std::vector<Segment> path;
  for (const auto& r : reqs) path.push_back(r.geom);
  Planner planner(lim, capacity, pc);
  Interpolator in(planner.queue(), reqs.empty() ? core::Vec{} : reqs.front().geom.start, ic);
  TraceChecker chk(lim, lim.period_s, path);
  RunResult res;
  chk.add(in.setpoint().pos, 0);
  std::size_t next = 0;
  bool flushed = false;
  double dv_prev = 0, j_prev = 0;  // the block-jerk check's last cycle
  bool have_dv = false;
  for (res.cycles = 0; res.cycles < max_cycles; ++res.cycles) {
    while (next < reqs.size() && !planner.queue().full()) {
      const auto r = planner.push(reqs[next]);
      if (r != PlanResult::Ok) {
        res.error = r;
        return res;
      }
      ++next;
    }
    if (next == reqs.size() && !flushed) {
      planner.flush();
      flushed = true;
    }
    if (flushed && in.idle()) break;
    if (hook) hook(res.cycles, in);
    const auto& ring = planner.queue().ring();
    const double v_before = in.setpoint().path_v;
    const double a_before = ring.empty() ? 0.0 : ring.front().a_mm_s2;
    const double j_before = ring.empty() ? 0.0 : ring.front().j_mm_s3;
    const auto& sp = in.step(lim.period_s);
    res.max_path_v = std::max(res.max_path_v, sp.path_v);
    if (!ring.empty() && std::isfinite(ring.front().j_mm_s3)) {
      const Block& f = ring.front();
      res.block_v_ratio = std::max(res.block_v_ratio, sp.path_v / f.v_cap_mm_s);
      const double a_lim = std::max(a_before, f.a_mm_s2);
      if (a_lim > 0) res.block_a_ratio = std::max(res.block_a_ratio, std::abs(sp.path_v - v_before) / lim.period_s / a_lim);
      const double j_lim = std::max({j_prev, j_before, f.j_mm_s3});
      const double dv = sp.path_v - v_before;
      if (have_dv && j_lim > 0)
        res.block_j_ratio = std::max(res.block_j_ratio, std::abs(dv - dv_prev) / (lim.period_s * lim.period_s) / j_lim);
      dv_prev = dv;
      have_dv = true;
    } else {
      have_dv = false;
    }
    j_prev = j_before;
    chk.add(sp.pos, sp.tag);
    if (trace) trace->push_back(sp.pos);
  }
  // Two more samples at rest: the checker sees the stop at the end.
  chk.add(in.step(lim.period_s).pos, in.setpoint().tag);
  chk.add(in.step(lim.period_s).pos, in.setpoint().tag);
  res.fig = chk.figures();
  res.end = in.setpoint().pos;
  res.finished = in.idle();
  return res;
}

inline MachineLimits xyz_limits(double v = 100, double a = 1000) {
  MachineLimits m;
  for (int i = 0; i < 3; ++i) m.axis[i] = {v, a, 0, -1000, 1000};
  m.period_s = 0.001;
  return m;
}

inline core::Vec xyz(double x, double y, double z = 0) {
  core::Vec v;
  v[0] = x;
  v[1] = y;
  v[2] = z;
  return v;
}

inline PathRequest line_req(const core::Vec& a, const core::Vec& b, double feed, std::uint32_t tag,
                            double tol = -1) {
  PathRequest r;
  r.geom = make_line(a, b);
  r.feed_mm_s = feed;
  r.tag = tag;
  r.tolerance_mm = tol;
  return r;
}

// An arc request (make_arc's arguments) at `feed`, tagged.
inline PathRequest arc_req(const Segment& arc, double feed, std::uint32_t tag) {
  PathRequest r;
  r.geom = arc;
  r.feed_mm_s = feed;
  r.tag = tag;
  return r;
}

}  // namespace softmc::motion::testing
