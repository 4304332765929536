// From IR motion instructions to geometric segments: the one place the program meets the planner.
#pragma once

#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "motion/geometry/curve_result.hpp"
#include "motion/geometry/segment.hpp"
#include "program/ir/program.hpp"

namespace softmc::control {

// The segment a motion instruction describes when it starts at `from`; nothing for a non-motion op.
// rt-safe.
std::optional<motion::Segment> to_segment(const program::Op& op, const core::Vec& from);
// The same written into `out` (false, `out` untouched, for a non-motion op): a line is set in place
// (motion::set_line), without building a whole Segment. rt-safe.
bool to_segment(const program::Op& op, const core::Vec& from, motion::Segment& out);

// True for the curve ops (G5/G5.1 Bezier, G5.2 NURBS) that become several segments.
bool is_curve(const program::Op& op);

// Appends the segments of a curve op that starts at `from` (not rt: the curve constructors
// allocate, so a Channel expands its program's curves when it loads it). Returns the construction
// error, or Ok; appends nothing for a non-curve op.
motion::CurveError append_curve_segments(const program::Op& op, const core::Vec& from,
                                         std::vector<motion::Segment>& out);

// Every motion of a program as geometric segments, in program order, each handed to
// fn(instruction, segment) as it is built (a curve gives several) and none kept: a Segment is
// 1.3 kB, a 200 000-line program's pieces 260 MB. Not rt. Returns the first curve that cannot be
// built and its instruction index (CurveError::Ok when all could).
std::pair<motion::CurveError, std::uint32_t> visit_program_geometry(
    const program::Program& prog, const std::function<void(std::uint32_t, const motion::Segment&)>& fn);

}  // namespace softmc::control
