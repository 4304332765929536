// Look-ahead planning: validation, corner blends, junction limits, incremental backward pass.
#include "motion/planner/planner.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "motion/geometry/bezier.hpp"
#include "motion/planner/planner_detail.hpp"

namespace softmc::motion {

using namespace planner_detail;

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

Planner::Planner(const MachineLimits& limits, std::size_t queue_capacity, const PlannerConfig& config)
    : limits_(limits), config_(config), queue_(queue_capacity), min_length_mm_(min_length_mm(limits)) {}

// The shortest piece that is planned as a block: a nanometre, or a twentieth of the least jerk per
// cycle, j·dt³, where that is smaller. A piece left out leaves its length as a step in the
// setpoints, a jerk of up to 2·δ/dt³: 10 times the limit for a nanometre at the old floor of 2e-10
// mm, once at motion::kMinJerkStep_mm, nothing on a machine with 1e-5 mm of jerk per cycle.
double Planner::min_length_mm(const MachineLimits& lim) {
  double m = kMinLength_mm;
  const double dt3 = lim.period_s * lim.period_s * lim.period_s;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (lim.present(i) && lim.axis[i].j_max_mm_s3 > 0) m = std::min(m, 0.05 * lim.axis[i].j_max_mm_s3 * dt3);
  return m;
}

// rt-safe. A blend the planner built lies inside every present axis's travel (P-9): the programmed
// moves were checked when pushed, a blend within P of them may still pass a limit they touch.
bool Planner::inside_travel(const Segment& g) const {
  Vec lo, hi;
  g.bounds(lo, hi);
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (limits_.present(i) && (lo[i] < limits_.axis[i].min_mm || hi[i] > limits_.axis[i].max_mm)) return false;
  return true;
}

// rt-safe
double Planner::plan_cap_mm_s(const Block& b) const {
  return std::min(b.v_cap_mm_s, b.feed_mm_s * config_.max_feed_override);
}

// rt-safe
PlanResult Planner::push(const PathRequest& req) {
  if (queue_.full()) return PlanResult::QueueFull;
  if (!req.rapid && !(req.feed_mm_s > 0)) return PlanResult::BadFeed;
  // Validate, then act: a segment that would leave the travel never enters the queue (P-9, arcs
  // included: bounds() holds the extreme points an arc passes over). Blends stay inside the convex
  // hull of the corner they cut, so checking the programmed curves covers them.
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
  if (!(req.geom.length > min_length_mm_)) return PlanResult::Ok;  // nothing to move
  const auto sl = segment_limits(req.geom, limits_, config_.centripetal_share);
  if (!std::isfinite(sl.v_max_mm_s) || !std::isfinite(sl.a_max_mm_s2) || !(sl.v_max_mm_s > 0) ||
      !(sl.a_max_mm_s2 > 0))
    return PlanResult::Infeasible;
  ++pushes_taken_;
  // Validated: now act. Lines pass through the merge stage; anything else first releases it.
  if (queue_.has_stage_ && merge(req)) return PlanResult::Ok;
  const PlanResult r = emit_stage();
  if (r != PlanResult::Ok) return r;
  const double tol = req.tolerance_mm < 0 ? config_.tolerance_mm : req.tolerance_mm;
  if (req.geom.kind == SegmentKind::Line && req.mergeable && tol > 0 && config_.merge_share > 0) {
    stage(req);
    return PlanResult::Ok;
  }
  return plan(req);
}

// rt-safe. Holds a line back: the next lines may still merge into it.
void Planner::stage(const PathRequest& req) {
  MergeStage& m = queue_.stage_;
  m.req = req;
  m.tag_last = std::max(req.tag, req.tag_last);
  m.q_mm = kInf;
  m.dev_mm = 0;
  m.n = 0;
  queue_.has_stage_ = true;
}

// rt-safe. Naive-CAM merge (LinuxCNC's G64 Q):
//
//   S ──●──●───●──● E ──► req          ● programmed corners, each within Q of the chord S → req's end,
//   S ────────────────────► end        every piece moving forward along it: the chord is planned instead
//
// Every point of the chord then lies within Q of the programmed polyline (its points project in
// order onto the chord, and between two corners the offset is a blend of theirs), and the blends at
// the chord's ends stay within P of the programmed corners S and E: the whole path within max(Q, P).
// Merging removes the short and noisy pieces of CAM polylines that otherwise force tiny blend radii.
bool Planner::merge(const PathRequest& req) {
  MergeStage& m = queue_.stage_;
  const double tol = req.tolerance_mm < 0 ? config_.tolerance_mm : req.tolerance_mm;
  if (req.geom.kind != SegmentKind::Line || !req.mergeable || !(tol > 0) || req.rapid != m.req.rapid || req.profile != m.req.profile ||
      (!req.rapid && req.feed_mm_s != m.req.feed_mm_s) || m.n + 1 >= MergeStage::kMaxPoints)
    return false;
  const double q = std::min(m.q_mm, config_.merge_share * tol);
  const Vec s = m.req.geom.start, e = req.geom.end;
  const Vec chord = e - s;
  const double len = core::norm(chord);
  if (!(len > min_length_mm_)) return false;
  const Vec c = chord * (1 / len);
  // The corner at the stage's end joins the merged points for the check. Each point's offset from
  // S is kept, so a push costs one dot product per point: the distance off the chord is
  // √(|d|² − (d·c)²), and the pieces move forward along it while d·c grows.
  m.offsets[m.n] = m.req.geom.end - s;
  m.offset2[m.n] = core::dot(m.offsets[m.n], m.offsets[m.n]);
  const double q2 = q * q;
  double prev = 0, dev2 = 0;
  for (std::size_t k = 0; k <= m.n; ++k) {
    const double along = core::dot(m.offsets[k], c);
    if (!(along > prev)) return false;
    dev2 = std::max(dev2, m.offset2[k] - along * along);
    if (dev2 > q2) return false;
    prev = along;
  }
  if (!(len > prev)) return false;
  ++m.n;
  m.q_mm = q;
  m.dev_mm = std::sqrt(std::max(0.0, dev2));
  // The merged line S → e, as make_line builds it (only its end, length and direction change).
  m.req.geom.end = e;
  m.req.geom.length = len;
  m.req.geom.dir = c;
  m.tag_last = std::max(req.tag, req.tag_last);
  return true;
}

// rt-safe. Plans the held-back line (merged or not).
PlanResult Planner::emit_stage() {
  if (!queue_.has_stage_) return PlanResult::Ok;
  queue_.has_stage_ = false;
  const MergeStage& m = queue_.stage_;
  return plan(m.req, m.dev_mm, m.tag_last);
}

// rt-safe. Plans a validated move in: blend with the pending block, commit, hold the new one pending.
PlanResult Planner::plan(const PathRequest& req, double merge_dev_mm, std::uint32_t tag_last) {
  const auto sl = segment_limits(req.geom, limits_, config_.centripetal_share, target_speed(req.rapid, req.feed_mm_s));
  if (!std::isfinite(sl.v_max_mm_s) || !std::isfinite(sl.a_max_mm_s2) || !(sl.v_max_mm_s > 0) ||
      !(sl.a_max_mm_s2 > 0))
    return PlanResult::Infeasible;

  Block b;
  b.seg = req.geom;
  b.rapid = req.rapid;
  b.tag = req.tag;
  b.tag_last = std::max({req.tag, req.tag_last, tag_last});
  b.length = req.geom.length;
  b.merge_q_mm = std::max(merge_dev_mm, req.offset_mm);
  set_limits(b, sl, req.profile == ProfileKind::Trapezoid ? kInf : sl.j_max_mm_s3, target_speed(req.rapid, req.feed_mm_s));
  set_law(b, [&] { return segment_law(req.geom, limits_); });
  b.feed_mm_s = req.rapid ? kInf : req.feed_mm_s;
  advance(b, req.tolerance_mm < 0 ? config_.tolerance_mm : req.tolerance_mm);
  return PlanResult::Ok;
}

// rt-safe. The next block b (as programmed, with tolerance p_mm) after the pending one: a held arc
// first becomes a fillet with b or is planned on its own; an arc that may become a fillet is held.
void Planner::advance(Block& b, double p_mm) {
  if (queue_.has_held_) {
    if (fillet(b, p_mm)) return;
    release_held();
  }
  if (holds_fillet(b, p_mm)) {
    queue_.held_ = b;
    queue_.held_p_mm_ = p_mm;
    queue_.has_held_ = true;
    return;
  }
  join(b, p_mm);
}

// rt-safe. Plans a held arc on its own: the next block was no line, or the fillet did not fit, or
// was slower.
void Planner::release_held() {
  if (!queue_.has_held_) return;
  queue_.has_held_ = false;
  Block h = queue_.held_;
  join(h, queue_.held_p_mm_);
}

// rt-safe. Blends the pending block's end with b's start (or kinks or stops there), commits the
// pending block and the blend, and holds b pending.
void Planner::join(Block& b, double p_mm) {
  const double full_length = b.length;
  if (queue_.has_pending_) {
    Block& a = queue_.pending_;
    // A merged line lies up to merge_q_mm off the program: the blend keeps the rest of P.
    const double tol = p_mm - std::max(a.merge_q_mm, b.merge_q_mm);
    Block blend;
    bool blended = false;
    if (tol > 0 && !a.is_blend && a.seg.kind == SegmentKind::Line && b.seg.kind == SegmentKind::Line) {
      // Deflection: 0 = straight on, π = reversal (from the chord |t2 − t1| = 2 sin(δ/2): exact near 0).
      const double chord = core::norm(b.seg.dir - a.seg.dir);
      const double delta = 2 * std::asin(std::min(1.0, chord / 2));
      // Within 2e-3 rad of a reversal, a stop, as kink() takes it: a blend there is crossed at a
      // few µm/s at best, and the corner quintic of a near-reversal degenerates into a cusp its
      // sampled curvature does not see (a fuzzer's line reversing onto a stub 1.3e-5 rad off it:
      // the quintic kept the axes' speed as its cap and was crossed at 0.45 mm/s, 10 % over Y's
      // acceleration).
      if (delta > config_.tangent_rad && delta < std::numbers::pi - 2e-3) {
        // Arc tangent to both lines whose midpoint lies `tol` from the corner:
        // tol = R·(1/cos h − 1), h = δ/2  →  R = tol·cos h / (1 − cos h); it touches the lines at
        // d = R·tan h from the corner. Each line gives at most half of its length to a blend, so
        // the blends at its two ends never overlap (then R shrinks and the deviation with it).
        const double h = delta / 2;
        const double one_minus_cos = 2 * std::sin(h / 2) * std::sin(h / 2);
        double r = tol * std::cos(h) / one_minus_cos;
        double d = r * std::tan(h);
        const double d_max = std::min(queue_.pending_full_length_ / 2, b.length / 2);
        if (d > d_max) {
          d = d_max;
          r = d / std::tan(h);
        }
        const bool jerk = !(std::isinf(a.j_mm_s3) && std::isinf(b.j_mm_s3));
        if (d > min_length_mm_ && r > min_length_mm_) {
          blend.is_blend = true;
          blend.blend = make_blend_arc(a.seg.end - a.seg.dir * d, a.seg.dir, b.seg.dir, r, delta);
          blend.length = r * delta;
          const auto bl = blend_limits(blend.blend, limits_, config_.centripetal_share);
          set_limits(blend, bl, jerk ? bl.j_max_mm_s3 : kInf);
          set_law(blend, [&] { return blend_law(blend.blend, limits_); });
        }
        if (jerk && delta >= config_.g2_blend_min_rad) {
          // Jerk mode: the arc's curvature steps at both ends limit it to the speed at which one
          // cycle's share of each axis's jerk takes the step (commit()); the curvature-continuous
          // quintic (make_corner_blend, its midpoint `tol` from the corner as the arc's, its shape
          // by the deflection) has no step but a higher peak curvature. It is taken
          // where its corner speed is well above the arc's (g2_blend_gain: a Poly piece keeps less of
          // the acceleration along the path than an arc, docs/planner.md, "Corner blends"); at most
          // half of each line, as the arc.
          const double v_arc =
              blend.length > 0
                  ? std::min(blend.v_cap_mm_s,
                             std::sqrt(curvature_step_v2(blend.blend.curvature(0), limits_, config_.curvature_step_share)))
                  : 0.0;
          double alpha = 0, beta = 0;
          corner_blend_shape(delta, alpha, beta);
          const double dq = std::min(tol / corner_blend_dev(chord, 1.0, alpha, beta), d_max);
          // Its cap never exceeds the target speed: where the arc is already that fast within the
          // gain, the quintic (tens of µs to build: its length table and sampled limits) is not.
          const double vq = target_speed(a.rapid && b.rapid, std::min(a.feed_mm_s, b.feed_mm_s));
          const bool worth = !(config_.g2_blend_gain * v_arc >= vq);
          const bool build = worth && dq > min_length_mm_;
          curves_tried_ += build ? 1 : 0;
          const SegmentResult q = build ? make_corner_blend(a.seg.end, a.seg.dir, b.seg.dir, dq, alpha, beta)
                                        : SegmentResult{CurveError::BadValue, {}};
          const SegmentLimits ql = q.ok() ? segment_limits(q.segment, limits_, config_.centripetal_share, vq, false) : SegmentLimits{};
          if (q.ok() && ql.v_max_mm_s > config_.g2_blend_gain * v_arc && ql.a_max_mm_s2 > 0 &&
              std::isfinite(ql.a_max_mm_s2)) {
            blend = Block{};
            blend.seg = q.segment;
            blend.length = q.segment.length;
            set_limits(blend, ql, ql.j_max_mm_s3, vq, false);
            set_law(blend, [&] { return segment_law(blend.seg, limits_); });
            d = dq;
          }
        }
        if (blend.length > 0) {
          // Blend or stop: a corner is crossed on its blend only where that is estimated quicker than
          // stopping on the corner and going on (kink() then makes it a stop). With a jerk limit a
          // sharp corner's blend is slow (a 90° quintic within P0.05 at 10 000 mm/s³: 3.7 mm/s),
          // and the path must slow down to it at the blend's lower jerk, then cross it and speed up
          // again: on zigzags of 1–10 mm lines a stop at each corner was up to 20 % quicker
          // (docs/planner.md, "Blend or stop"). Each side is timed from the corner to the middle of
          // its line (where the profiles of the corners at both ends meet) by side_time. The blend's
          // crossing speed: its cap, and an arc's curvature steps in jerk mode. With
          // corner_stop_when_quicker off, only a blend whose crossing lasts ten times a stop over its
          // own length is dropped, as before the choice (a return line almost onto its outgoing one:
          // 1e-8 mm/s over 2.6e-4 mm took hours of a review's fuzzing).
          double v_eff = blend.v_cap_mm_s;
          if (jerk && blend.is_blend)
            v_eff = std::min(v_eff, std::sqrt(curvature_step_v2(blend.blend.curvature(0), limits_,
                                                                config_.curvature_step_share)));
          const double acc = std::min(a.a_mm_s2, b.a_mm_s2), jk = std::min(a.j_mm_s3, b.j_mm_s3);
          const double jb = std::min(jk, blend.j_mm_s3);  // eased into the blend at its own jerk
          // The speed the lines run at: their feed at 100 % (the override is not known yet; rapids
          // carry an infinite feed, so their caps).
          const double vm = std::min({a.feed_mm_s, b.feed_mm_s, a.v_cap_mm_s, b.v_cap_mm_s});
          if (!config_.corner_stop_when_quicker) {
            const double t_stop = 2 * std::sqrt(blend.length / acc) + (std::isfinite(jk) ? 4 * std::cbrt(blend.length / jk) : 0.0);
            if (!(blend.length < 10 * t_stop * v_eff)) blend = Block{};
          } else if (!(v_eff >= vm)) {
            // A blend crossed at the lines' speed is always the quicker (and most are: CAM
            // polylines' slight turns, which cost no estimate then).
            const double la = queue_.pending_full_length_ / 2, lb = b.length / 2;
            const double t_stop = side_time(la, 0, vm, acc, jk, jk) + side_time(lb, 0, vm, acc, jk, jk);
            const double t_blend = v_eff > 0 ? side_time(la - d, v_eff, vm, acc, jb, jk) + side_time(lb - d, v_eff, vm, acc, jb, jk) +
                                                   blend.length / v_eff
                                             : kInf;
            if (!(t_blend < t_stop)) blend = Block{};
          }
        }
        if (blend.length > 0) {
          const Vec corner = a.seg.end;
          const Vec p1 = corner - a.seg.dir * d;
          const Vec p2 = corner + b.seg.dir * d;
          join_blend(blend, a, b);
          // Shorten both lines (same direction, so their limits stay).
          const Vec a_start = a.seg.start;
          a.seg = make_line(a_start, p1);
          a.length = a.seg.length;
          b.seg = make_line(p2, b.seg.end);
          b.length = b.seg.length;
          blended = true;
        }
      }
    }
    if (!blended && tol > 0 && (a.seg.kind == SegmentKind::Arc || b.seg.kind == SegmentKind::Arc))
      blended = blend_curves(a, b, tol, queue_.pending_full_length_ / 2, blend);
    // An unblended corner between two lines within P: where it turns out a stop, the interpolator
    // may start b while a still brakes, passing within tol of the corner.
    if (!blended && tol > 0 && !a.is_blend && a.seg.kind == SegmentKind::Line && b.seg.kind == SegmentKind::Line)
      b.overlap_mm = tol;
    if (!blended && p_mm > 0) kink(a, b);
    if (a.length > min_length_mm_) commit(a);
    if (blended) commit(blend);
  }
  queue_.pending_ = b;
  queue_.pending_full_length_ = full_length;
  queue_.has_pending_ = true;
}

void Planner::flush() {
  emit_stage();  // validated when pushed: the merged line is inside the hull of what was checked
  release_held();
  if (!queue_.has_pending_) {
    queue_.back_open_ = false;
    return;
  }
  queue_.has_pending_ = false;
  if (queue_.pending_.length > min_length_mm_) commit(queue_.pending_);
  queue_.back_open_ = false;  // nothing follows for now: the interpolator may plan with the back too
}

// rt-safe. Caps b where the kDenseBlocks blocks ending with it (it included) are shorter than a
// cycle's travel at its cap; fewer blocks since the window was last empty cannot fill a cycle.
void Planner::dense_cap(Block& b) {
  const std::size_t slot = dense_n_ % kDenseBlocks;
  if (slot == 0) {  // the running sum taken afresh once per round, so rounding cannot pile up
    dense_sum_mm_ = 0;
    for (std::size_t k = 0; k < kDenseBlocks && k < dense_n_; ++k) dense_sum_mm_ += dense_len_[k];
  }
  if (dense_n_ >= kDenseBlocks) dense_sum_mm_ -= dense_len_[slot];
  dense_len_[slot] = b.length;
  dense_sum_mm_ += b.length;
  if (++dense_n_ < kDenseBlocks) return;
  const double cap = std::max(0.0, dense_sum_mm_) / limits_.period_s;
  if (cap < b.v_cap_mm_s) {
    b.v_cap_mm_s = cap;
    b.v_split_mm_s = std::min(b.v_split_mm_s, cap);
  }
}

// rt-safe. Appends a block: its junction limit with the block before it, then the backward pass.
void Planner::commit(const Block& b) {
  auto& ring = queue_.ring_;
  // The block before b is final once the interpolator may plan with it (PlanQueue::visible: after
  // a flush), so the curvature step below must then leave its jerk alone.
  const bool prev_visible = !ring.empty() && !queue_.back_open_;
  ring.push(b);  // room was checked by push()
  queue_.back_open_ = true;
  ++blocks_committed_;
  Block& nb = ring.back();
  const bool from_rest = ring.size() == 1;
  if (from_rest) dense_n_ = 0;  // no block before it shares a cycle with it
  dense_cap(nb);
  if (from_rest) {
    nb.v2_junction = 0;  // the machine is at rest when the window is empty (its tail ends at rest)
  } else {
    Block& prev = ring.at(ring.size() - 2);
    // Tangent junctions keep the speed both neighbours allow; any other corner that was not blended
    // (G61, arcs, reversals) is an exact stop: a direction change at speed needs infinite acceleration.
    // |t_out − t_in| is the turning angle (chord of unit vectors), without acos's loss near 0.
    const double turn = core::norm(prev.tangent(prev.length) - nb.tangent(0));
    const double cap = std::min(plan_cap_mm_s(prev), plan_cap_mm_s(nb));
    nb.v2_junction = turn <= config_.tangent_rad ? cap * cap : std::min(cap * cap, nb.v2_kink);
    // A block without a jerk limit (axes with max_jerk 0, or a Trapezoid move) into one with a
    // limit: the trapezoid follower plans its exit with the backward pass's constant-deceleration
    // model, which knows nothing of the jerk follower's ramps, and handed it states it could not
    // brake from (a fuzzer's program on X, Y without jerk and Z with: X at 10× its acceleration where
    // the path reached the end of the program at 3 mm/s). The jerk follower starts from rest there.
    if (!std::isfinite(prev.j_mm_s3) && std::isfinite(nb.j_mm_s3)) nb.v2_junction = 0;
    // With jerk limits, a jump of the curvature vector (line into arc or blend) steps each axis's
    // acceleration by v²·Δκ_i within one cycle, on top of the path's own jerk in that cycle: the
    // step is kept within a share (curvature_step_share) of j_i·dt, and both neighbours give up the share the
    // step can actually take at the junction speed, so the two never add up past j_i.
    if (!std::isinf(nb.j_mm_s3) || !std::isinf(prev.j_mm_s3)) {
      const Vec dk = nb.curvature(0) - prev.curvature(prev.length);
      const double dt = limits_.period_s;
      nb.v2_junction = std::min(nb.v2_junction, curvature_step_v2(dk, limits_, config_.curvature_step_share));
      // The largest share of an axis's jerk budget the step takes, and what each neighbour keeps of
      // its path jerk; a junction that would leave a plane arc less than a quarter of what plain
      // shares keep (a stiff axis next to a soft one, a fast crossing onto a small radius) is crossed
      // slower instead.
      for (int halvings = 0;; ++halvings) {
        double used = 0;
        Vec step_j{};  // the jerk the step puts on each axis (mm/s³)
        for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
          const double d = std::abs(dk[i]);
          if (d < 1e-12 || !(limits_.axis[i].j_max_mm_s3 > 0)) continue;
          step_j[i] = nb.v2_junction * d / dt;
          used = std::max(used, step_j[i] / limits_.axis[i].j_max_mm_s3);
        }
        if (!(used > 0)) break;
        const double v = std::sqrt(nb.v2_junction);
        const double f_nb = jerk_left_by_step(step_j, nb, 0, v, limits_);
        const double f_prev = jerk_left_by_step(step_j, prev, prev.length, v, limits_);
        if (prev_visible && f_prev < 1) {  // (pushed after a flush before the path got there) a stop: the step at rest
          nb.v2_junction = 0;
          break;
        }
        if (std::min(f_nb, f_prev) < 0.25 * (1 - used)) {
          if (halvings == 40) {  // (never seen) a stop: the step then happens at rest
            nb.v2_junction = 0;
            break;
          }
          nb.v2_junction *= 0.5;
          continue;
        }
        nb.j_mm_s3 *= f_nb;
        prev.j_mm_s3 *= f_prev;
        break;
      }
    }
  }
  // An exact stop (or the window's start) before nb: the blocks on either side run from or to rest.
  if (config_.limit_to_reach) {
    // Past this reach from rest no block's cap can be met: the diagonal of every axis's speed.
    double v_top2 = 0;
    for (std::size_t i = 0; i < core::kMaxAxes; ++i)
      if (limits_.present(i)) v_top2 += limits_.axis[i].v_max_mm_s * limits_.axis[i].v_max_mm_s;
    const double v_top = std::sqrt(v_top2);
    // Forwards from the last rest point: nothing has planned into nb yet.
    if (nb.v2_junction == 0) reach_d_ = reach_a_ = reach_j_ = 0;
    if (reach_d_ >= 0) {
      if (limit_to_reach(nb, true, reach_d_, reach_a_, reach_j_)) nb.v2_junction = std::min(nb.v2_junction, nb.v_cap_mm_s * nb.v_cap_mm_s);
      reach_d_ += nb.length;
      reach_a_ = std::max(reach_a_, nb.a_mm_s2);
      reach_j_ = std::max(reach_j_, nb.j_mm_s3);
      if (!std::isfinite(reach_j_) || reach_from_rest(reach_d_, reach_a_, reach_j_) >= v_top) reach_d_ = -1;
    }
    // Backwards from a new stop, while a motion coming to rest there could still be below a cap.
    if (nb.v2_junction == 0 && !from_rest) {
      double d = 0, a_max = 0, j_max = 0;
      bool changed = false;
      for (std::size_t k = ring.size() - 1, walked = 0; k-- > 0 && walked++ < kReachBlocks;) {
        Block& pb = ring.at(k);
        if (limit_to_reach(pb, false, d, a_max, j_max)) {
          pb.v2_junction = std::min(pb.v2_junction, pb.v_cap_mm_s * pb.v_cap_mm_s);
          changed = true;
        }
        d += pb.length;
        a_max = std::max(a_max, pb.a_mm_s2);
        j_max = std::max(j_max, pb.j_mm_s3);
        if (pb.v2_junction == 0 || !std::isfinite(j_max) || reach_from_rest(d, a_max, j_max) >= v_top) break;
      }
      if (changed) ring.touch();  // readers that keep what they derived from the blocks begin again
    }
  }
  queue_.unsettled_ = std::min(queue_.unsettled_ + 1, ring.size());
}

}  // namespace softmc::motion
