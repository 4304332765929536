// Run summary: the figures `softmc run` prints and its --json contract (docs/cli.md).
#pragma once

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "machine/config.hpp"
#include "program/ir/program.hpp"
#include "report/programmed_path.hpp"
#include "report/trace.hpp"

namespace softmc::report {

// Where a largest value was first reached: the trace row's time and the program line of the
// instruction it was tagged with (a difference: its newest row). line 0: never reached (no row).
struct Where {
  double t_s = 0;
  std::uint32_t line = 0;
  std::uint32_t file = 0;  // index into the program's files: 0 the main program, else a subroutine file
};

struct AxisSummary {
  double max_vel_mm_s = 0;            // largest |Δcmd/Δt| in the trace
  double max_acc_mm_s2 = 0;           // largest |Δ²cmd/Δt²|
  double max_jerk_mm_s3 = 0;          // largest |Δ³cmd/Δt³|
  double max_following_error_mm = 0;  // largest |cmd − act|
  Where vel_at, acc_at, jerk_at;      // where each of the first three was reached
};

struct Summary {
  std::string program;
  std::string machine;
  std::string result = "ok";   // "ok", or the fault that stopped the run
  double period_s = 0;
  std::uint64_t cycles = 0;    // interpolation cycles run: trace rows after the t = 0 row
  double cycle_time_s = 0;     // t_s of the last row; recording stops one cycle after the program ends
  double cut_mm = 0;           // path length of feed moves with the tool on
  double feed_mm = 0;          // path length of all feed moves
  double rapid_mm = 0;         // path length of rapid moves
  double max_path_deviation_mm = 0;  // largest distance of a setpoint from the programmed path
  double max_following_error_mm = 0;  // largest of the axes' following errors
  double max_path_speed_mm_s = 0;
  core::AxisMask axes = 0;
  std::array<AxisSummary, core::kMaxAxes> axis{};
  Where deviation_at;          // where max_path_deviation_mm was reached
  std::vector<std::string> files;  // the program's files, for Where::file
};

// Computes every figure from the program (the programmed geometry) and the trace, row by row as
// the simulation makes them: a run of hours need not keep its trace (230 B a cycle) in memory.
// Each instruction's source location, by instruction index (the tag of a trace row): one copy shared
// by the summary and the trace writer, so that neither needs the program to outlive it.
using SourceLocations = std::shared_ptr<const std::vector<core::SourceLoc>>;
SourceLocations source_locations(const program::Program* prog);

class SummaryBuilder {
 public:
  SummaryBuilder(const program::Program& prog, const machine::MachineConfig& cfg, double period_s, core::AxisMask axes);
  void add(const TraceRow& row);
  Summary finish() const;
  const SourceLocations& locations() const { return loc_; }  // for a trace writer of the same run

 private:
  Summary s_;
  ProgrammedPath path_;
  SourceLocations loc_;  // each instruction's source location (Where)
  std::array<TraceRow, 3> last_{};  // the rows before, newest first
  std::size_t rows_ = 0;
};

// The same over a recorded trace.
Summary summarize(const program::Program& prog, const machine::MachineConfig& cfg, const Trace& trace);

// The trace as CSV, row by row: t_s, then per configured axis <a>_cmd_mm, <a>_act_mm, <a>_vel_mm_s;
// then path_v_mm_s, tool, line (the source line of the instruction the row was tagged with; 0
// without a program). Throws std::runtime_error when the file cannot be written.
class TraceCsvWriter {
 public:
  // `loc` gives the line column (0 for every row without it).
  TraceCsvWriter(const std::string& path, core::AxisMask axes, SourceLocations loc = nullptr);
  ~TraceCsvWriter();
  TraceCsvWriter(const TraceCsvWriter&) = delete;
  TraceCsvWriter& operator=(const TraceCsvWriter&) = delete;
  void add(const TraceRow& r);
  void close();  // flushes and closes; throws on a write error

 private:
  void flush();
  std::string path_;
  std::FILE* f_ = nullptr;
  std::array<std::size_t, core::kMaxAxes> axes_{};
  std::size_t n_axes_ = 0;
  SourceLocations loc_;  // instruction → source location
  fmt::memory_buffer buf_;
};

std::string to_text(const Summary& s);   // short human-readable block
std::string to_json(const Summary& s);   // one JSON object (nlohmann-json), stable field names
nlohmann::ordered_json to_json_object(const Summary& s);  // the same, to add members to (run --home)

// CSV: t_s, then per configured axis <a>_cmd_mm, <a>_act_mm, <a>_vel_mm_s; then path_v_mm_s, tool, line.
void write_trace_csv(const std::string& path, const Trace& trace, const program::Program* prog = nullptr);

}  // namespace softmc::report
