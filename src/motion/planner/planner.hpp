// The look-ahead planner: geometric requests in, blocks with corner blends and backward-pass speed
// limits out, into a fixed-size window the interpolator executes (docs/planner.md).
//
//   push(A) push(B) push(C) ...                      flush()  (program end, dwell, M function)
//      │  blend A|B, commit A' and the blend arc        │  commit the pending block: it ends at rest
//      ▼                                                ▼
//   ring: A' (A|B) B' (B|C) ...  ◄── backward pass from the tail (exit 0) up to the first block whose
//                                    entry limit does not change (grbl's planner.c, incremental),
//                                    run once per cycle by the interpolator (PlanQueue::settle)
//
// The forward pass is not stored: the interpolator does it lazily, one block at a time, from the
// actual state (speed, override, hold), so override and hold never require re-planning the window.
#pragma once

#include <array>
#include <cstdint>
#include <limits>

#include "motion/geometry/segment.hpp"
#include "motion/limits.hpp"
#include "motion/planner/block.hpp"
#include "motion/planner/path_request.hpp"
#include "motion/planner/plan_queue.hpp"
#include "motion/profile/profile.hpp"

namespace softmc::motion {

struct PlannerConfig {
  double tolerance_mm = 0.05;       // default P: largest distance of the path from a programmed corner
  double max_feed_override = 2.0;   // the backward pass plans for this, so any override up to it is safe
  double tangent_rad = 1e-9;        // junctions turning less than this are tangent (no blend, no stop)
  // Split of an axis's acceleration on curved pieces: centripetal share cn, tangential share ct,
  // cn² + ct² = 1 so that |a_t·t_i + a_n·n_i| ≤ a_max_i at every point of a circle.
  // Jerk blocks only: trapezoid blocks use the speed-dependent law (tangent_law.hpp) unless
  // speed_dependent_tangential is false (then the split applies to them too).
  double centripetal_share = 0.8;
  bool speed_dependent_tangential = true;
  // Trapezoid curves cruise at most where the law still leaves this share of the tangential
  // acceleration it allows at rest (a hold or stop then brakes with at least that; on a circle the
  // cap is √(1 − 0.25²) ≈ 0.968 of the full centripetal limit in v², 0.984 in v).
  double tangential_reserve = 0.25;
  // Corners that are not blended but nearly tangent (arcs in rounded G-code) are crossed at speed
  // within this share of each axis's acceleration/jerk per cycle; the neighbours keep the rest.
  // 0.05 since 2026-12-02 (0.25 before): most such corners are blended now, and the neighbours'
  // acceleration is worth more than the speed of the few left (docs/planner.md, "kinks").
  double kink_share = 0.05;
  // Jerk mode: an unblended step of the curvature at a junction (a line into a tangent arc) moves
  // each axis's acceleration by at most this share of j·dt in its cycle; the neighbours give up the
  // share the step takes.
  double curvature_step_share = 0.25;
  double min_kink_speed_mm_s = 1.0;  // below this the corner is an exact stop instead
  // Naive-CAM merge (LinuxCNC's G64 Q): consecutive lines of one feed become one line while every
  // programmed corner in between lies within Q = merge_share·P of it; 0 = off. With Q ≤ P the path
  // stays within P of the program (docs/planner.md).
  double merge_share = 0.5;
  // Jerk mode: runs of lines turning less than this at each point are executed as a curvature-
  // continuous B-spline within smoothing_share·P of them (polyline_smoothing.hpp; the Channel builds
  // it at load); 0 = off.
  double smoothing_max_turn_rad = 20 * 3.14159265358979323846 / 180;
  double smoothing_share = 0.9;
  // Before smoothing, points within smoothing_thin_share·P of the chord of their neighbours along a
  // collinear stretch are dropped (motion::thin_polyline); the spline then keeps within
  // (smoothing_share − smoothing_thin_share)·P of the remaining legs. 0 = never.
  double smoothing_thin_share = 0.02;
  // Jerk mode: a corner between two lines turning at least this is blended by a curvature-continuous
  // quintic (make_corner_blend) instead of a circular arc, whose curvature step at each end caps
  // the corner at the speed one cycle's share of jerk allows (docs/planner.md, "Corner blends");
  // below it the arc is as fast and cheaper to run (at 0.1 rad, 5° corners between 10 mm lines
  // crossed on arcs took 2.5 times as long as on quintics). ∞: always arcs.
  double g2_blend_min_rad = 0.01;
  // A corner between two lines is a stop where stopping on it is estimated quicker than crossing
  // its blend (Planner::join; docs/planner.md, "Blend or stop"). false: every corner that fits a
  // blend is blended.
  bool corner_stop_when_quicker = true;
  // Jerk mode: a curve (Poly) block entered or left at rest takes the limits of the speed it can
  // reach within its length, not those of its cap (Planner::limit_to_reach; docs/planner.md,
  // "Blocks at rest"). A switch for comparisons and the tests.
  bool limit_to_reach = true;
  double g2_blend_gain = 1.5;  // ... where its speed cap is at least this times the arc's corner speed
  // Jerk mode: an arc between two lines it is tangent to (a CAM fillet) is replaced by one quintic
  // from line to line within P of the three (docs/planner.md, "Fillets") where that quintic's speed
  // cap is at least this share of the arc's; 0 = off.
  double fillet_share = 0.8;
};

enum class PlanResult : std::uint8_t { Ok, QueueFull, BadFeed, OutsideTravel, Infeasible };
const char* to_string(PlanResult r);

// Path speed and acceleration limits a segment allows, from the axis limits (the slowest axis rules).
struct SegmentLimits {
  double v_max_mm_s = 0;
  double a_max_mm_s2 = 0;
  double j_max_mm_s3 = 0;  // path jerk; infinite when no axis of the segment has a jerk limit
  // ≠ 1 on an arc in its plane (a circle, or the slight spiral of a G-code arc whose end is off its
  // circle): its jerk shares are scaled to the Euclidean bound (docs/planner.md "Jerk"), about 1.387;
  // a curvature step at its ends then takes its share off the tangential jerk by jerk_left_by_step.
  double jerk_scale = 1;
};
// v_target: the fastest the segment will be asked to go (feed × the highest override; ∞ unknown):
// a Poly piece that could go faster trades the centripetal share it does not need for acceleration.
// jerk_norm: a Poly piece's 3·v·a_t·κ may take what the norm of its jerk vector leaves (false: only
// what the plain sum of the shares leaves; the planner's own blends, docs/planner.md "Poly segments").
SegmentLimits segment_limits(const Segment& g, const MachineLimits& lim, double centripetal_share = 0.8,
                             double v_target = std::numeric_limits<double>::infinity(), bool jerk_norm = true);
SegmentLimits blend_limits(const BlendArc& b, const MachineLimits& lim, double centripetal_share = 0.8);

// |κ'|/κ² bound of an arc in a coordinate plane (0 on a circle; a G-code arc whose end is off its
// circle by the program's rounding is a slight spiral: about 2·|dradius|/length), ∞ for helices and
// arcs whose radius changes by more than 1 %.
double plane_arc_spiral(const Segment& g);

// The factor on a block's path jerk (its tangential jerk) that leaves room for a curvature step
// putting step_j[i] of jerk on axis i at the block's end `s_end` (0 or its length), crossed at
// speeds up to v_mm_s: the crossing cycle sees the step on top of the block's own jerk. Plain shares
// (lines, helices, blends, Poly): 1 − the largest step_j[i]/j_i. A plane arc's shares are scaled to
// the Euclidean bound and have no slack there: each in-plane axis sees at most √((f·j + v³κ²)² +
// (3·v·a·κ + v³·|κ'|)²) + step_j[i], so f is taken from that at the crossing's speed (capped at the
// block's) and curvature, axis by axis. At a slow crossing it is above 1 − used; at the arc's cap
// speed with its full acceleration it is lower (a stiff axis next to a soft one can bring it below).
double jerk_left_by_step(const Vec& step_j, const Block& b, double s_end, double v_mm_s, const MachineLimits& lim);

// Trapezoid blocks (no jerk limit) use the speed-dependent law instead of the fixed split
// (tangent_law.hpp): the law, and the speed cap where the centripetal acceleration alone takes some
// axis's whole limit (or its speed limit is reached).
struct CurveLaw {
  TangentLaw law;
  double v_max_mm_s = 0;
};
CurveLaw segment_law(const Segment& g, const MachineLimits& lim);
CurveLaw blend_law(const BlendArc& b, const MachineLimits& lim);

class Planner {
 public:
  // Configuration time: sizes the look-ahead window (blocks; a corner makes two).
  Planner(const MachineLimits& limits, std::size_t queue_capacity, const PlannerConfig& config = {});

  // rt-safe. Validates `req` (feed, soft limits on the whole curve, axis limits), then plans it in.
  // A zero-length move is accepted and produces nothing.
  PlanResult push(const PathRequest& req);
  // rt-safe. No more motion for now: the pending block is committed and the path ends at rest there.
  void flush();
  // rt-safe. A stop was taken with the path at speed v, acceleration a, s_front into the front block
  // (Interpolator::path_speed, path_acceleration, front_progress): the blocks within reach of the
  // brake get the limits their geometry allows up to the speed the path can still have, no more
  // than that (docs/planner.md, "Stops in curves").
  // A feed hold or an enable drop (P-8, P-2) brakes the same way; at rest, restore_limits() gives
  // the blocks their planned limits back before the path goes on.
  void limit_for_stop(double v, double a, double s_front);
  static constexpr std::size_t kStopBlocks = 256;
  // rt-safe. The path is at rest: every block limit_for_stop changed takes back the cap, acceleration
  // and jerk it was planned with (from rest any limits can be met; the follower plans anew). Nothing
  // to do, and no walk, when no block was changed since the last call.
  void restore_limits();
  bool limits_raised() const { return limits_raised_; }

  PlanQueue& queue() { return queue_; }
  const PlanQueue& queue() const { return queue_; }
  const MachineLimits& limits() const { return limits_; }
  // Pushes that gave the path something to move (a zero-length one is taken and plans nothing).
  std::uint64_t pushes_taken() const { return pushes_taken_; }
  const PlannerConfig& config() const { return config_; }
  // Speed the backward pass plans a block for: hard cap, and the feed at the largest override.
  double plan_cap_mm_s(const Block& b) const;
  // Curves push has tried to build so far (corner quintics, curve blends, fillets: each one's fit or
  // search, whether it is taken or not): the costly part of planning, which the Channel bounds per
  // cycle. (Counting only those taken let a cycle's failed fillet searches run unbounded: 3 ms at
  // pocket.ngc's start.)
  std::uint64_t curves_tried() const { return curves_tried_; }
  // Blocks committed to the window so far: each costs a blend or junction, its limits and the
  // backward pass's step; a line merged into the one held back commits none (the Channel bounds both).
  std::uint64_t blocks_committed() const { return blocks_committed_; }

 private:
  PlanResult plan(const PathRequest& req, double merge_dev_mm = 0, std::uint32_t tag_last = 0);
  bool merge(const PathRequest& req);
  void stage(const PathRequest& req);
  PlanResult emit_stage();
  void commit(const Block& b);
  void dense_cap(Block& b);  // see kDenseBlocks
  // A Poly block entered or left at rest gets the limits of the speed it can reach (see planner_stops.cpp).
  bool limit_to_reach(Block& b, bool from_rest, double d_more, double a_more, double j_more) const;
  bool relimit(const Block& b, double c, double a0, double j0, double& A, double& J, SegmentLimits* out = nullptr) const;
  // Since the last rest point: distance, largest acceleration and jerk (−1: too far to matter).
  double reach_d_ = -1, reach_a_ = 0, reach_j_ = 0;
  static constexpr std::size_t kReachBlocks = 64;  // the blocks before a new stop limit_to_reach looks at
  void kink(Block& a, Block& b) const;
  // Speed at which a and b's corner may be crossed unblended (0: an exact stop).
  double kink_speed(const Block& a, const Block& b) const;
  // Blends a junction of lines and arcs with at least one arc (a corner, or in jerk mode a
  // curvature step) by a curvature-continuous quintic within tol, trimming a and b; false: none.
  bool blend_curves(Block& a, Block& b, double tol, double da_half, Block& blend) const;  // da_half: half of a as programmed
  void advance(Block& b, double p_mm);
  void join(Block& b, double p_mm);
  bool holds_fillet(const Block& b, double p_mm) const;
  bool fillet(Block& c, double p_mm);
  void release_held();
  bool inside_travel(const Segment& g) const;
  static double min_length_mm(const MachineLimits& lim);
  static constexpr double kFilletMaxRad = 2.7;   // fillets turn less (arc and corners together)
  static constexpr double kFilletMaxTurn = 1.5;  // |Δt| at either end of the arc: about 97°
  // The fastest a move is asked to go: its feed at the highest override (∞ for rapids: the axes').
  double target_speed(bool rapid, double feed_mm_s) const {
    return rapid ? std::numeric_limits<double>::infinity() : feed_mm_s * config_.max_feed_override;
  }
  template <class MakeLaw>
  void set_law(Block& b, const MakeLaw& make_law) const;

  MachineLimits limits_;
  PlannerConfig config_;
  PlanQueue queue_;
  bool limits_raised_ = false;  // limit_for_stop changed a block since the last restore_limits()
  double min_length_mm_;  // min_length_mm(limits_)
  std::uint64_t pushes_taken_ = 0;
  // The interpolator passes at most InterpolatorConfig::max_blocks_per_cycle (512) blocks a cycle.
  // A block is capped at the speed at which the kDenseBlocks blocks ending with it take one cycle
  // (dense_cap), so a cycle never needs more than the budget (half of it: the speed may change
  // within the cycle). Lengths of the last kDenseBlocks blocks committed since the window was empty:
  static constexpr std::size_t kDenseBlocks = 256;
  std::array<double, kDenseBlocks> dense_len_{};
  std::uint64_t dense_n_ = 0;
  double dense_sum_mm_ = 0;
  mutable std::uint64_t curves_tried_ = 0;
  std::uint64_t blocks_committed_ = 0;
};

}  // namespace softmc::motion
