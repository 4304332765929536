// Results of the curve constructors: what was wrong with the input, or the segments it made.
#pragma once

#include <cstdint>
#include <vector>

#include "motion/geometry/segment.hpp"

namespace softmc::motion {

enum class CurveError : std::uint8_t {
  Ok,
  TooFewPoints,    // fewer points than the curve needs
  TooManyPoints,   // more than a fixed-size segment holds (Newton: 16 nodes)
  RepeatedPoint,   // two consecutive points (or nodes) coincide
  NotMonotonic,    // nodes not strictly increasing or decreasing in the independent axis
  BadDegree,       // degree/order outside what a segment holds
  BadWeight,       // a weight not finite and positive
  BadKnots,        // knot vector of the wrong size, decreasing, or not clamped
  BadValue,        // a coordinate or derivative is not finite
};
const char* to_string(CurveError e);

// One segment, or the reason there is none.
struct SegmentResult {
  CurveError error = CurveError::Ok;
  Segment segment;
  bool ok() const { return error == CurveError::Ok; }
};

// Consecutive segments joined end to start (configuration time: the vector allocates, the
// segments themselves do not).
struct CurveResult {
  CurveError error = CurveError::Ok;
  std::vector<Segment> segments;
  bool ok() const { return error == CurveError::Ok; }
};

}  // namespace softmc::motion
