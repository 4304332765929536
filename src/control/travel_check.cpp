// Whole-program soft-limit check.
#include "control/travel_check.hpp"

#include <fmt/format.h>

#include <set>
#include <tuple>

#include "control/path.hpp"

namespace softmc::control {

core::Diagnostics check_travel(const program::Program& prog, const motion::MachineLimits& limits) {
  constexpr double kEps = 1e-9;  // the planner's own slack: a path exactly on the travel end is inside
  core::Diagnostics out;
  // A line inside a loop or subroutine yields many instructions: report each source location once.
  std::set<std::tuple<std::uint16_t, std::uint32_t, std::uint32_t>> reported;
  // Piece by piece as the walk builds them, none kept (a large CAM program's pieces are hundreds of MB).
  const auto [error, error_instruction] = visit_program_geometry(prog, [&](std::uint32_t at, const motion::Segment& seg) {
    const auto& ins = prog.instructions[at];
    core::Vec lo, hi;
    seg.bounds(lo, hi);
    for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
      std::string what;
      if (!limits.present(i)) {
        if (lo[i] != 0 || hi[i] != 0) what = fmt::format("the machine has no {} axis", core::letter(i));
      } else if (lo[i] < limits.axis[i].min_mm - kEps) {
        what = fmt::format("{} leaves the travel: {:.3f} mm < min {:.3f} mm", core::letter(i), lo[i],
                           limits.axis[i].min_mm);
      } else if (hi[i] > limits.axis[i].max_mm + kEps) {
        what = fmt::format("{} leaves the travel: {:.3f} mm > max {:.3f} mm", core::letter(i), hi[i],
                           limits.axis[i].max_mm);
      }
      if (what.empty()) continue;
      if (!reported.emplace(ins.loc.file, ins.loc.line, ins.loc.col).second) break;
      out.push_back({prog.file_of(ins.loc), ins.loc.line, ins.loc.col, core::Severity::Error, std::move(what)});
      break;  // one message per instruction
    }
  });
  if (error != motion::CurveError::Ok) {
    const auto& ins = prog.instructions[error_instruction];
    out.push_back({prog.file_of(ins.loc), ins.loc.line, ins.loc.col, core::Severity::Error,
                   fmt::format("the curve cannot be built: {}", motion::to_string(error))});
  }
  return out;
}

}  // namespace softmc::control
