// Exact-stop planning of single segments under per-axis limits.
#include "motion/planner/planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace softmc::motion {

const char* to_string(PlanResult r) {
  switch (r) {
    case PlanResult::Ok: return "ok";
    case PlanResult::QueueFull: return "planner queue full";
    case PlanResult::BadFeed: return "feed must be positive";
    case PlanResult::OutsideTravel: return "path leaves the axis travel (soft limits)";
    case PlanResult::Infeasible: return "segment cannot be planned within the axis limits";
  }
  return "?";
}

// rt-safe
SegmentLimits segment_limits(const Segment& g, const MachineLimits& lim) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double v = kInf, a = kInf;
  if (g.kind == SegmentKind::Line) {
    // Each axis moves at v·|dir_i|: the path speed is limited by v_max_i / |dir_i|, likewise acceleration.
    for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
      const double d = std::abs(g.dir[i]);
      if (d < 1e-12) continue;
      v = std::min(v, lim.axis[i].v_max_mm_s / d);
      a = std::min(a, lim.axis[i].a_max_mm_s2 / d);
    }
  } else {
    // Arc: the tangent turns through every direction of the plane, so an in-plane axis may carry the
    // whole in-plane speed. The acceleration budget of the in-plane axes is split evenly between the
    // tangential and the centripetal part: |a_t·t_i + κv²·n_i| ≤ √(a_t² + (κv²)²) ≤ a_max.
    const double inplane = g.length > 0 ? g.radius * std::abs(g.sweep) / g.length : 0;
    const double kappa = g.length > 0 ? g.radius * (g.sweep / g.length) * (g.sweep / g.length) : 0;
    for (std::size_t i : {std::size_t{g.axis0}, std::size_t{g.axis1}}) {
      if (inplane < 1e-12) break;
      v = std::min(v, lim.axis[i].v_max_mm_s / inplane);
      const double a_axis = lim.axis[i].a_max_mm_s2 / std::sqrt(2.0);
      a = std::min(a, a_axis / inplane);
      if (kappa > 0) v = std::min(v, std::sqrt(a_axis / kappa));
    }
    for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
      const double d = std::abs(g.linear[i]);
      if (d < 1e-12) continue;
      v = std::min(v, lim.axis[i].v_max_mm_s / d);
      a = std::min(a, lim.axis[i].a_max_mm_s2 / d);
    }
  }
  return {v, a};
}

Planner::Planner(const MachineLimits& limits, std::size_t queue_capacity) : limits_(limits), queue_(queue_capacity) {}

// rt-safe
PlanResult Planner::push(const PathRequest& req) {
  if (queue_.full()) return PlanResult::QueueFull;
  if (!req.rapid && !(req.feed_mm_s > 0)) return PlanResult::BadFeed;
  // Validate, then act: a segment that would leave the travel never enters the queue.
  Vec lo, hi;
  req.geom.bounds(lo, hi);
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    if (!limits_.present(i)) {
      if (lo[i] != 0 || hi[i] != 0) return PlanResult::OutsideTravel;  // an axis the machine lacks
      continue;
    }
    constexpr double kEps = 1e-9;
    if (lo[i] < limits_.axis[i].min_mm - kEps || hi[i] > limits_.axis[i].max_mm + kEps) return PlanResult::OutsideTravel;
  }
  const auto sl = segment_limits(req.geom, limits_);
  double v = sl.v_max_mm_s;
  if (!req.rapid) v = std::min(v, req.feed_mm_s);
  TimedSegment ts;
  ts.geom = req.geom;
  ts.rapid = req.rapid;
  ts.tag = req.tag;
  if (req.geom.length <= 0) {
    ts.profile = Trapezoid{};  // zero length, zero duration
  } else {
    if (!std::isfinite(v) || !std::isfinite(sl.a_max_mm_s2) || !(v > 0)) return PlanResult::Infeasible;
    auto p = plan_trapezoid(req.geom.length, 0, 0, v, sl.a_max_mm_s2);
    if (!p) return PlanResult::Infeasible;
    ts.profile = *p;
  }
  queue_.push(ts);
  return PlanResult::Ok;
}

}  // namespace softmc::motion
