// The interpreter's state between blocks: modal settings, feed in effect and current position.
#pragma once

#include <optional>

#include "core/axes.hpp"
#include "program/iso/modes.hpp"

namespace softmc::program::iso {

// Starts as LinuxCNC starts: G80 (no motion mode) G17 G21 G90 G91.1 G94, no feed.
struct ModalState {
  Motion motion = Motion::None;
  Plane plane = Plane::XY;
  Units units = Units::Mm;
  Distance distance = Distance::Absolute;
  Distance arc_distance = Distance::Incremental;  // G91.1: I/J relative to the arc's start point
  std::optional<double> feed_mm_s;                // F converted when programmed; keeps its speed across G20/G21
  core::Vec position;                             // machine coordinates, mm (no offsets yet)
  bool ended = false;                             // M2/M30 executed: later text is not part of the program

  // Set by the parser after a block failed that may have set the feed or the motion mode: the
  // errors that would only echo that failure ("feed rate missing", "no motion mode") are then not
  // reported again. The program is already refused, so what these blocks emit does not matter.
  bool feed_uncertain = false;
  bool motion_uncertain = false;
};

}  // namespace softmc::program::iso
