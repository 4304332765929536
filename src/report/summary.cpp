// Run summary from the trace and the programmed geometry, and its text and JSON forms.
#include "report/summary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <nlohmann/json.hpp>


namespace softmc::report {

namespace {

template <typename F>
void for_each_axis(core::AxisMask mask, F&& f) {
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (mask & core::axis_bit(i)) f(i);
}

char lower_letter(std::size_t axis) {
  return static_cast<char>(std::tolower(static_cast<unsigned char>(core::letter(axis))));
}

// "line 12" (the main program) or "sub.ngc:12", and the time.
std::string where_text(const Summary& s, const Where& w) {
  const std::string line = w.file > 0 && w.file < s.files.size() ? fmt::format("{}:{}", s.files[w.file], w.line)
                                                                 : fmt::format("line {}", w.line);
  return fmt::format("{} at {:.3f} s", line, w.t_s);
}

// {"t_s": …, "line": …} (and "file" when not the main program), or null where nothing was reached.
nlohmann::ordered_json where_json(const Summary& s, const Where& w) {
  if (w.line == 0) return nullptr;
  nlohmann::ordered_json j;
  j["t_s"] = w.t_s;
  j["line"] = w.line;
  if (w.file > 0 && w.file < s.files.size()) j["file"] = s.files[w.file];
  return j;
}

}  // namespace

SourceLocations source_locations(const program::Program* prog) {
  auto loc = std::make_shared<std::vector<core::SourceLoc>>();
  if (!prog) return loc;
  loc->reserve(prog->instructions.size());
  for (const auto& ins : prog->instructions) loc->push_back(ins.loc);
  return loc;
}

SummaryBuilder::SummaryBuilder(const program::Program& prog, const machine::MachineConfig& cfg, double period_s,
                               core::AxisMask axes)
    : path_(programmed_path(prog)) {
  s_.program = prog.files.empty() ? std::string{} : prog.files[0];
  s_.machine = cfg.name;
  s_.period_s = period_s;
  s_.axes = axes;
  s_.files = prog.files;
  loc_ = source_locations(&prog);
  // Lengths are the programmed ones: what the part needs, not what the planner made of it.
  for (const auto& m : path_.moves) {
    if (m.kind == MoveKind::Rapid) {
      s_.rapid_mm += m.length;
    } else {
      s_.feed_mm += m.length;
      if (m.kind == MoveKind::Cut) s_.cut_mm += m.length;
    }
  }
}

void SummaryBuilder::add(const TraceRow& row) {
  Summary& s = s_;
  // A row at t = 0 records the state before the first cycle, not a cycle.
  if (row.t_s > 0) ++s.cycles;
  // The simulation records one row per cycle and stops one cycle after the program ends (after its
  // last motion or dwell), so the last row's time is the program's cycle time.
  s.cycle_time_s = row.t_s;
  const double dt = s.period_s;
  const std::size_t r = rows_;
  const auto note = [&](Where& w) {
    w.t_s = row.t_s;
    const auto& loc = *loc_;
    w.line = row.tag < loc.size() ? loc[row.tag].line : 0;
    w.file = row.tag < loc.size() ? loc[row.tag].file : 0;
  };
  // A new largest value, and where: the first row that reaches it.
  const auto raise = [&](double& max, double v, Where& w) {
    if (!(v > max)) return;
    max = v;
    note(w);
  };
  raise(s.max_path_deviation_mm, path_.deviation_mm(row.cmd, row.tag, row.tag_last, row.moving || row.stopped, s.max_path_deviation_mm),
        s.deviation_at);
  s.max_path_speed_mm_s = std::max(s.max_path_speed_mm_s, row.path_v);
  for_each_axis(s.axes, [&](std::size_t i) {
    AxisSummary& a = s.axis[i];
    a.max_following_error_mm = std::max(a.max_following_error_mm, std::abs(row.cmd[i] - row.act[i]));
    s.max_following_error_mm = std::max(s.max_following_error_mm, a.max_following_error_mm);
    if (dt <= 0) return;
    // Finite differences of the setpoints: the planner's own velocity is not trusted here.
    if (r >= 1) raise(a.max_vel_mm_s, std::abs(row.cmd[i] - last_[0].cmd[i]) / dt, a.vel_at);
    if (r >= 2) {
      const double d2 = row.cmd[i] - 2 * last_[0].cmd[i] + last_[1].cmd[i];
      raise(a.max_acc_mm_s2, std::abs(d2) / (dt * dt), a.acc_at);
    }
    if (r >= 3) {
      const double d3 = row.cmd[i] - 3 * last_[0].cmd[i] + 3 * last_[1].cmd[i] - last_[2].cmd[i];
      raise(a.max_jerk_mm_s3, std::abs(d3) / (dt * dt * dt), a.jerk_at);
    }
  });
  last_[2] = last_[1];
  last_[1] = last_[0];
  last_[0] = row;
  ++rows_;
}

Summary SummaryBuilder::finish() const { return s_; }

Summary summarize(const program::Program& prog, const machine::MachineConfig& cfg, const Trace& trace) {
  SummaryBuilder b(prog, cfg, trace.period_s, trace.axes);
  for (const TraceRow& row : trace.rows) b.add(row);
  return b.finish();
}

std::string to_text(const Summary& s) {
  // Labels are 13 columns wide, as are the lines `softmc run` appends (trace, plot).
  std::string out;
  auto line = [&](std::string_view label, const std::string& value) {
    fmt::format_to(std::back_inserter(out), "{:<13}{}\n", label, value);
  };
  line("program", s.program);
  line("machine", s.machine);
  line("result", s.result);
  line("cycle time", fmt::format("{:.3f} s  ({} cycles of {:g} ms)", s.cycle_time_s, s.cycles, s.period_s * 1e3));
  line("cut", fmt::format("{:.3f} mm", s.cut_mm));
  line("feed", fmt::format("{:.3f} mm", s.feed_mm));
  line("rapid", fmt::format("{:.3f} mm", s.rapid_mm));
  line("path speed", fmt::format("{:.3f} mm/s max", s.max_path_speed_mm_s));
  line("deviation", fmt::format("{:.6f} mm max (setpoints from the programmed path){}", s.max_path_deviation_mm,
                                s.deviation_at.line > 0 ? ", " + where_text(s, s.deviation_at) : std::string{}));
  line("foll. error", fmt::format("{:.6f} mm max", s.max_following_error_mm));
  fmt::format_to(std::back_inserter(out), "{:<13}{:>14}{:>16}{:>18}{:>14}\n", "axis", "max vel mm/s", "max acc mm/s²",
                 "max jerk mm/s³", "max ferr mm");
  for_each_axis(s.axes, [&](std::size_t i) {
    const auto& a = s.axis[i];
    fmt::format_to(std::back_inserter(out), "  {:<11}{:>14.3f}{:>16.1f}{:>18.0f}{:>14.6f}\n", core::letter(i), a.max_vel_mm_s,
                   a.max_acc_mm_s2, a.max_jerk_mm_s3, a.max_following_error_mm);
  });
  return out;
}

std::string to_json(const Summary& s) {
  return to_json_object(s).dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

nlohmann::ordered_json to_json_object(const Summary& s) {
  // ordered_json keeps the documented field order (docs/cli.md), so diffs of outputs stay readable.
  nlohmann::ordered_json j;
  j["program"] = s.program;
  j["machine"] = s.machine;
  j["result"] = s.result;
  j["period_s"] = s.period_s;
  j["cycles"] = s.cycles;
  j["cycle_time_s"] = s.cycle_time_s;
  j["cut_mm"] = s.cut_mm;
  j["feed_mm"] = s.feed_mm;
  j["rapid_mm"] = s.rapid_mm;
  j["max_path_deviation_mm"] = s.max_path_deviation_mm;
  j["max_following_error_mm"] = s.max_following_error_mm;
  j["max_path_speed_mm_s"] = s.max_path_speed_mm_s;
  nlohmann::ordered_json axes = nlohmann::ordered_json::object();
  for_each_axis(s.axes, [&](std::size_t i) {
    const auto& a = s.axis[i];
    nlohmann::ordered_json ja;
    ja["max_vel_mm_s"] = a.max_vel_mm_s;
    ja["max_acc_mm_s2"] = a.max_acc_mm_s2;
    ja["max_following_error_mm"] = a.max_following_error_mm;
    ja["max_jerk_mm_s3"] = a.max_jerk_mm_s3;  // added 2026-12-03: new fields go at the end (docs/cli.md)
    ja["max_vel_at"] = where_json(s, a.vel_at);  // added 2026-12-05
    ja["max_acc_at"] = where_json(s, a.acc_at);
    ja["max_jerk_at"] = where_json(s, a.jerk_at);
    axes[std::string(1, lower_letter(i))] = std::move(ja);
  });
  j["axes"] = std::move(axes);
  j["max_path_deviation_at"] = where_json(s, s.deviation_at);  // added 2026-12-05
  // A file name or fault text that is not UTF-8 must not make the summary itself fail.
  return j;
}

}  // namespace softmc::report
