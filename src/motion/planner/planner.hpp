// The planner: turns geometric segments with a requested feed into timed, profiled segments.
//
// Today it plans each segment on its own, from rest to rest (exact stop), with the path speed and
// acceleration limited so that no axis exceeds its own limits along the segment. The look-ahead
// planner replaces `plan_one` and keeps this interface: requests in, a queue of TimedSegments out.
#pragma once

#include <cstdint>

#include "core/ring.hpp"
#include "motion/geometry/segment.hpp"
#include "motion/limits.hpp"
#include "motion/profile/trapezoid.hpp"

namespace softmc::motion {

struct PathRequest {
  Segment geom;
  double feed_mm_s = 0;  // requested path speed; ignored for rapids
  bool rapid = false;
  std::uint32_t tag = 0;  // the instruction index it came from, carried to the setpoints
};

struct TimedSegment {
  Segment geom;
  Trapezoid profile;
  bool rapid = false;
  std::uint32_t tag = 0;
};

enum class PlanResult : std::uint8_t { Ok, QueueFull, BadFeed, OutsideTravel, Infeasible };
const char* to_string(PlanResult r);

// Path speed and acceleration limits a segment allows, from the axis limits (the slowest axis rules).
struct SegmentLimits {
  double v_max_mm_s = 0;
  double a_max_mm_s2 = 0;
};
SegmentLimits segment_limits(const Segment& g, const MachineLimits& lim);

class Planner {
 public:
  // Configuration time: sizes the queue.
  Planner(const MachineLimits& limits, std::size_t queue_capacity);

  // rt-safe. Plans `req` and appends it to the queue.
  PlanResult push(const PathRequest& req);

  core::Ring<TimedSegment>& queue() { return queue_; }
  const MachineLimits& limits() const { return limits_; }

 private:
  MachineLimits limits_;
  core::Ring<TimedSegment> queue_;
};

}  // namespace softmc::motion
