// From IR motion instructions to geometric segments: the one place the program meets the planner.
#pragma once

#include <optional>

#include "motion/geometry/segment.hpp"
#include "program/ir/program.hpp"

namespace softmc::control {

// The segment a motion instruction describes when it starts at `from`; nothing for a non-motion op.
// rt-safe.
std::optional<motion::Segment> to_segment(const program::Op& op, const core::Vec& from);

}  // namespace softmc::control
