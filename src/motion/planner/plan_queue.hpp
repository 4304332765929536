// The look-ahead window between planner and interpolator: committed blocks plus one pending block
// (and, in jerk mode, an arc held after it until the next move shows whether it is a fillet).
//
//   push ─► [ held arc ] [ pending ] ─commit─► ring: [ front (executing) | 1 | ... | back ] ─► interpolator
//                          (its end may still be cut by the next corner's blend)  (its exit = 0: always stoppable)
//
// Committed blocks never change geometry again; the planner only raises their v2_entry_max, so an
// exit speed the interpolator has committed to stays feasible. rt-safe throughout.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include "core/ring.hpp"
#include "motion/planner/block.hpp"
#include "motion/planner/path_request.hpp"

namespace softmc::motion {

// A line held back before blending while the next lines may still merge into it (naive-CAM merge,
// docs/planner.md): the request it will become, and the programmed points it stands for.
struct MergeStage {
  static constexpr std::size_t kMaxPoints = 16;  // bounds the work per push
  PathRequest req;                               // the merged line (first start → last end), first tag
  std::uint32_t tag_last = 0;                    // the last instruction merged
  double q_mm = 0;                               // largest distance a merged point may lie off the line
  double dev_mm = 0;                             // largest distance one does
  std::array<Vec, kMaxPoints> offsets{};         // programmed corners inside it, minus its start
  std::array<double, kMaxPoints> offset2{};      // their squared distances from the start
  std::size_t n = 0;
};

class PlanQueue {
 public:
  // Spare slots beyond what is asked: a push may commit up to six blocks (the merged line held back,
  // releasing a held arc: the line before it, their blend, the arc and its blend; then the new move
  // with its blend) and a flush after it up to three more (a held arc released, and its end).
  static constexpr std::size_t kSpare = 10;
  explicit PlanQueue(std::size_t capacity) : ring_(capacity + kSpare) {}

  // Free slots for one push and the flush after it: eleven.
  bool full() const { return ring_.capacity() - ring_.size() < kSpare + 1; }
  bool empty() const { return ring_.empty() && !has_pending_ && !has_stage_ && !has_held_; }
  std::size_t size() const {
    return ring_.size() + (has_pending_ ? 1 : 0) + (has_stage_ ? 1 : 0) + (has_held_ ? 1 : 0);
  }
  std::size_t capacity() const { return ring_.capacity() - kSpare; }
  // The blocks the jerk follower may plan with: all of them but an open back (Planner::commit may
  // still lower its jerk when the next block arrives: the curvature step at their junction). So
  // the limits of a block never tighten once a brake may have been planned with them; the next
  // commit or the flush at the end of what is planned closes the back. (An open back is always the
  // block committed last: the path is at rest at its start when it is the only one.) Whatever else
  // changes a visible block's limits in place (a stop's raised limits, their restoring) must
  // Ring::touch the ring: the jerk guard's index and its cruise certificates, which the follower
  // keeps for up to 16 cycles, hold only while the ring's changes() moved by pops alone.
  std::size_t visible() const { return ring_.size() - (back_open_ && !ring_.empty() ? 1 : 0); }
  // Drops everything planned, pending included (a fault, or the end of a stop).
  void clear() {
    ring_.clear();
    has_pending_ = false;
    has_stage_ = false;
    has_held_ = false;
    unsettled_ = 0;
    back_open_ = false;
  }

  // rt-safe. The backward pass (entry limits from the tail, exit 0, backwards), run once for all the
  // blocks committed since the last call — once per cycle, not once per push. It stops at the first
  // older block whose limit does not change: limits only rise as blocks are appended.
  void settle() {
    if (unsettled_ == 0) return;
    double exit2 = 0;
    const std::size_t n = ring_.size();
    for (std::size_t k = n; k-- > 0;) {
      Block& b = ring_.at(k);
      const double e2 = std::min(b.v2_junction, b.law.root(exit2, 2 * b.length));
      if (k + unsettled_ < n && e2 == b.v2_entry_max) break;
      b.v2_entry_max = e2;
      exit2 = e2;
    }
    unsettled_ = 0;
  }

  core::Ring<Block>& ring() { return ring_; }
  const core::Ring<Block>& ring() const { return ring_; }
  bool has_pending() const { return has_pending_; }

 private:
  friend class Planner;
  core::Ring<Block> ring_;
  Block pending_;
  double pending_full_length_ = 0;  // its length before the blend at its start shortened it
  bool has_pending_ = false;
  MergeStage stage_;                // the line before the pending block's, still merging
  bool has_stage_ = false;
  Block held_;                      // a fillet arc after the pending line, waiting for the line after it
  double held_p_mm_ = 0;            // its tolerance P
  bool has_held_ = false;
  std::size_t unsettled_ = 0;  // blocks committed since the last settle()
  bool back_open_ = false;     // the back block's jerk may still be lowered by the next commit
};

}  // namespace softmc::motion
