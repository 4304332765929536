// Test fixtures for the reports: small programs, a hand-made table, and traces sampled from a program.
#pragma once

#include <algorithm>
#include <cmath>

#include "control/path.hpp"
#include "machine/config.hpp"
#include "program/ir/program.hpp"
#include "report/trace.hpp"

namespace softmc::report::testing {

inline core::Vec xy(double x, double y) {
  core::Vec v;
  v[0] = x;
  v[1] = y;
  return v;
}

inline program::Instruction ins(program::Op op) { return program::Instruction{core::SourceLoc{}, std::move(op)}; }

// A 600 × 400 mm two-axis table, built by hand so the tests do not depend on the TOML loader.
inline machine::MachineConfig test_table() {
  machine::MachineConfig cfg;
  cfg.name = "test_table";
  cfg.period_s = 0.001;
  for (std::size_t i = 0; i < 2; ++i) {
    machine::AxisConfig a;
    a.name = i == 0 ? "x" : "y";
    a.index = i;
    a.min_mm = 0;
    a.max_mm = i == 0 ? 600 : 400;
    a.max_vel_mm_s = 500;
    a.max_acc_mm_s2 = 2000;
    cfg.axes.push_back(a);
  }
  return cfg;
}

// Rapid to the part, a rectangle with one rounded corner cut with the tool on, a feed move with
// the tool off, a dwell, and a rapid home:
//   cut   = 30 + 5π + 20 + 40 + 30 = 120 + 5π
//   feed  = cut + 10√2
//   rapid = 10√2 + 20√2
inline program::Program rounded_square() {
  using namespace program;
  Program p;
  p.files = {"rounded_square.ngc"};
  p.start = xy(0, 0);
  p.instructions = {
      ins(Rapid{xy(10, 10)}),                        // 0
      ins(ToolSwitch{true}),                         // 1
      ins(Linear{xy(40, 10), 20}),                   // 2
      ins(Arc{xy(50, 20), 40, 20, 0, 1, 2, 1, 20}),  // 3: centre (40,20), CCW 90°
      ins(Linear{xy(50, 40), 20}),                   // 4
      ins(Linear{xy(10, 40), 20}),                   // 5
      ins(Linear{xy(10, 10), 20}),                   // 6
      ins(ToolSwitch{false}),                        // 7
      ins(Linear{xy(20, 20), 20}),                   // 8
      ins(Dwell{0.5}),                               // 9
      ins(Rapid{xy(0, 0)}),                          // 10
      ins(ProgramEnd{}),                             // 11
  };
  return p;
}

struct SampleOptions {
  double period_s = 0.001;
  double rapid_mm_s = 300;
  double acc_mm_s2 = 0;   // 0: constant speed along each move; else a trapezoid, stopping at each end
  double lag_tau_s = 0;   // first-order lag of the "measured" position behind the command
  double quantum_mm = 0;  // encoder quantisation of the measured position
};

// One row per period, walking the program's segments as a simple exact-stop controller would.
inline Trace sample_program(const program::Program& prog, const SampleOptions& o = {}) {
  Trace tr;
  tr.period_s = o.period_s;
  tr.axes = core::axis_bit(0) | core::axis_bit(1);
  core::Vec pos = prog.start, act = prog.start;
  bool tool = false;
  std::uint64_t cycle = 0;
  auto push = [&](const core::Vec& cmd, const core::Vec& vel, double v, std::uint32_t tag, bool moving, bool rapid) {
    ++cycle;
    if (o.lag_tau_s > 0)
      act = act + (cmd - act) * (o.period_s / o.lag_tau_s);
    else
      act = cmd;
    TraceRow r;
    r.t_s = static_cast<double>(cycle) * o.period_s;
    r.cmd = cmd;
    r.act = act;
    if (o.quantum_mm > 0)
      for (auto& x : r.act.v) x = std::round(x / o.quantum_mm) * o.quantum_mm;
    r.vel = vel;
    r.path_v = v;
    r.tag = tag;
    r.moving = moving;
    r.rapid = rapid;
    r.tool_on = tool;
    tr.rows.push_back(r);
  };
  for (std::uint32_t i = 0; i < prog.instructions.size(); ++i) {
    const auto& op = prog.instructions[i].op;
    if (const auto* t = std::get_if<program::ToolSwitch>(&op)) tool = t->on;
    if (const auto* d = std::get_if<program::Dwell>(&op)) {
      const auto n = static_cast<int>(std::lround(d->seconds / o.period_s));
      for (int k = 0; k < n; ++k) push(pos, core::Vec{}, 0, i, false, false);
    }
    const auto seg = control::to_segment(op, pos);
    if (!seg || seg->length <= 0) continue;
    const bool rapid = std::holds_alternative<program::Rapid>(op);
    double v = o.rapid_mm_s;
    if (const auto* l = std::get_if<program::Linear>(&op)) v = l->feed_mm_s;
    if (const auto* a = std::get_if<program::Arc>(&op)) v = a->feed_mm_s;
    const double len = seg->length;
    if (o.acc_mm_s2 <= 0) {
      const auto n = static_cast<int>(std::ceil(len / (v * o.period_s)));
      const double vv = len / (n * o.period_s);
      for (int k = 1; k <= n; ++k) {
        const double s = len * k / n;
        push(seg->point(s), seg->tangent(s) * vv, vv, i, true, rapid);
      }
    } else {
      const double a = o.acc_mm_s2;
      const double vp = std::min(v, std::sqrt(a * len));  // triangle when the move is too short to cruise
      const double ta = vp / a, tc = (len - vp * ta) / vp, total = 2 * ta + tc;
      for (double t = o.period_s;; t += o.period_s) {
        const double tt = std::min(t, total);
        double s, sv;
        if (tt < ta) {
          s = 0.5 * a * tt * tt;
          sv = a * tt;
        } else if (tt < ta + tc) {
          s = 0.5 * a * ta * ta + vp * (tt - ta);
          sv = vp;
        } else {
          const double td = total - tt;
          s = len - 0.5 * a * td * td;
          sv = a * td;
        }
        push(seg->point(s), seg->tangent(s) * sv, sv, i, true, rapid);
        if (t >= total) break;
      }
    }
    pos = seg->end;
  }
  // The simulation records one more cycle after the program has ended.
  push(pos, core::Vec{}, 0, static_cast<std::uint32_t>(prog.instructions.size() - 1), false, false);
  return tr;
}

}  // namespace softmc::report::testing
