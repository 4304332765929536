// Execution of the look-ahead window: lazy forward pass, override, hold, stops.
#include "motion/interp/interpolator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "motion/interp/jerk_guard.hpp"

namespace softmc::motion {

// rt-safe
void Interpolator::set_feed_override(double factor) {
  rule_.feed_override = std::clamp(std::isfinite(factor) ? factor : 0.0, 0.0, config_.max_feed_override);
}

// rt-safe
void Interpolator::set_speed_limits(double feed_limit_mm_s, double rapid_limit_mm_s) {
  const auto cap = [](double v) { return v > 0 ? v : std::numeric_limits<double>::infinity(); };  // NaN too
  rule_.feed_limit_mm_s = cap(feed_limit_mm_s);
  rule_.rapid_limit_mm_s = cap(rapid_limit_mm_s);
}

// rt-safe
void Interpolator::request_stop(StopKind kind) {
  if (kind == StopKind::None || queue_.empty()) return;
  if (stop_ != StopKind::Emergency) stop_ = kind;  // an emergency stop is never weakened
}

// rt-safe. Path speed the feed and override ask for on `b`, under its hard cap.
double Interpolator::soft_speed(const Block& b) const { return motion::soft_speed(b, rule_); }

// rt-safe
Interpolator::Inputs Interpolator::inputs(const Block& b) const {
  const auto& ring = queue_.ring();
  Inputs in;
  const bool h = halt();
  in.vc = h ? 0.0 : soft_speed(b);
  in.acc_scale = stop_ == StopKind::Emergency ? config_.emergency_accel_scale : 1.0;
  if (ring.size() >= 2) {
    const Block& next = ring.at(1);
    in.v1_max = std::sqrt(next.v2_entry_max);
    in.v1_want = h ? 0.0 : std::min(in.vc, soft_speed(next));
  }
  return in;
}

// rt-safe. The acceleration of a ramp over `dist` from v0 (plan_ramp's cases): the law's value at the
// highest speed² the ramp reaches, so that every point of it keeps the law (tangent_law.hpp). A
// cruise at a curve's very cap leaves none: a floor far below any real axis keeps plan_ramp's
// divisions finite.
double Interpolator::ramp_acc(const TangentLaw& law, double dist, double v0, const Inputs& in) {
  const double w0 = v0 * v0;
  const double vc = std::max(0.0, in.vc);
  const double v1 = std::min({in.v1_want, in.v1_max, vc});
  const double w1 = v1 * v1;
  double w_top = w0;  // brakes from v0 (v0 above the cruise speed, or brakes all the way)
  if (v0 <= vc) {
    const double wp = law.root(0.5 * (w0 + w1), dist);  // where an accelerating and a braking ramp meet
    if (wp >= vc * vc) w_top = vc * vc;                 // they meet above the cruise speed: cruise
    else if (wp >= std::max(w0, w1)) w_top = wp;
    else if (w1 > w0) w_top = std::min(w1, law.root(w0, 2 * dist));  // accelerates all the way
  }
  return std::max(law.at(w_top), 1e-6);
}

// rt-safe. plan_ramp over the rest `dist` of `b` from v0 with the inputs `in`, its acceleration from the law.
VelocityRamp Interpolator::ramp_for(const Block& b, double dist, double v0, const Inputs& in) {
  return plan_ramp(dist, v0, in.vc, in.v1_want, in.v1_max, in.acc_scale * ramp_acc(b.law, dist, v0, in));
}

// rt-safe. A new plan for the rest of `b` from the state sampled now.
void Interpolator::replan(const Block& b, const Inputs& in) {
  double s = 0;
  if (started_) {
    const ProfileState st = ramp_.at(t_);
    s = st.s;
    v_ = st.v;
  }
  const double dist = b.length - s;
  ramp_ = ramp_for(b, dist, v_, in);
  if (b.law.n > 0 && !halt()) {
    // On a curve a lower cruise speed buys more tangential acceleration for the ramps to it (g falls
    // as the speed rises): a few cruise speeds between the fixed split's cap and the curve's own cap
    // are tried, and the quickest plan over the rest of the block wins.
    const double w_lo = b.v_split_mm_s * b.v_split_mm_s, w_hi = b.v_cap_mm_s * b.v_cap_mm_s;
    for (const double f : {0.0, 0.5, 0.75, 0.9}) {
      Inputs c = in;
      c.vc = std::sqrt(w_lo + f * (w_hi - w_lo));
      if (!(c.vc < in.vc) || !(c.vc > v_)) continue;
      c.v1_want = std::min(c.v1_want, c.vc);
      const VelocityRamp r = ramp_for(b, dist, v_, c);
      if (r.duration() < ramp_.duration()) ramp_ = r;
    }
  }
  ramp_.s0 = s;
  t_ = 0;
  in_ = in;
  started_ = true;
}

// rt-safe. At rest at the end of what there is to run (the window empty, or waiting for a block the
// planner may still change), or on the path where a stop has braked: a stop asked for (P-5) is done
// there, the window dropped and the stop reported.
const Setpoint& Interpolator::rest_at_window_end() {
  if (stop_ != StopKind::None) {
    queue_.clear();
    stop_ = StopKind::None;
    stopped_ = true;
  }
  rest_at_end();
  return sp_;
}

// rt-safe
void Interpolator::rest_at_end() {
  sp_.vel = Vec{};
  sp_.acc = Vec{};
  sp_.path_v = 0;
  sp_.moving = false;
  started_ = false;
  t_ = 0;
  v_ = 0;
  a_ = 0;
  s_ = 0;
  cert_ = GuardVerdict{};
}

// rt-safe
const Setpoint& Interpolator::step(double dt) {
  queue_.settle();  // the planner's backward pass over what was pushed since the last cycle
  if (tail_.active && queue_.ring().empty() && stop_ == StopKind::None && !stopped_) {
    // The window dropped from outside (a fault): the setpoint stays where it was, as the path's.
    sp_.pos = out_.pos;
    tail_.active = false;
  }
  if (tail_.active && stop_ == StopKind::Emergency && !tail_.emergency) {
    // P-5: the tail brakes onto the corner with the emergency ramp too.
    const double scale = config_.emergency_accel_scale;
    const ProfileState x = tail_.otg.at(tail_.t);
    Otg1 e;
    e.reset(x);
    if (e.update(0.0, {std::max(x.v, 1e-9), tail_.a1 * scale, tail_.j1 * scale}) != OtgResult::ErrorInvalidInput) {
      tail_.otg = e;
      tail_.t = 0;
    }
    tail_.emergency = true;
  }
  if (config_.corner_overlap && !tail_.active && v_ > 0) begin_overlap(dt);
  const Setpoint& p = step_path(dt);
  if (!tail_.active) return p;
  // The braking line's end beside the path (begin_overlap): its offset from the corner added.
  tail_.t += dt;
  const ProfileState x = tail_.otg.at(tail_.t);
  out_ = p;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    out_.pos[i] += tail_.dir[i] * x.s;
    out_.vel[i] += tail_.dir[i] * x.v;
    out_.acc[i] += tail_.dir[i] * x.a;
  }
  out_.moving = true;
  // The setpoint lies within the next line's progress of the braking line's point, and within what
  // the tail has left of the next line's point: it belongs to whichever is the nearer (the
  // instructions a setpoint is measured against, and the outputs the next line switches).
  if (-x.s > s_) {
    out_.tag = tail_.tag;
    out_.tag_last = tail_.tag_last;
    out_.rapid = tail_.rapid;
  }
  if (tail_.t >= tail_.otg.duration_s()) {
    // At rest on the corner: the next line gets its limits back, if it is still the front.
    tail_.active = false;
    auto& ring = queue_.ring();
    if (!ring.empty() && ring.pops() == tail_.pops) {
      Block& g = ring.front();
      g.a_mm_s2 = tail_.a;
      g.j_mm_s3 = tail_.j;
      g.v_cap_mm_s = tail_.v_cap;
      g.v_split_mm_s = tail_.v_split;
      ring.touch();
    }
  }
  return out_;  // (after the tail's last cycle its offset is 0: out_ is the path's own setpoint)
}

// rt-safe
const Setpoint& Interpolator::step_path(double dt) {
  auto& ring = queue_.ring();
  // Jerk mode at rest before a block the planner may still change (the only one, and more may
  // follow: PlanQueue::visible): it is not planned with yet, so the path waits for the next block
  // or the flush, as before an empty window.
  const bool waiting = !ring.empty() && queue_.visible() == 0 && std::isfinite(ring.front().j_mm_s3) &&
                       !started_ && s_ == 0 && v_ == 0 && a_ == 0;
  // (Stopped before anything was committed: the pending block is dropped.)
  if (ring.empty() || waiting) return rest_at_window_end();
  if (std::isfinite(ring.front().j_mm_s3) && !started_) return step_jerk(dt);
  return step_trapezoid(dt);
}

// rt-safe
const Setpoint& Interpolator::step_trapezoid(double dt) {
  auto& ring = queue_.ring();
  if (started_) {
    const Inputs in = inputs(ring.front());
    // Braking to a hold or a stop on a curve: the law allows more as the speed falls, so the brake
    // is planned again every cycle from where it is (one ramp each: bounded).
    if (!(in == in_) || (halt() && ring.front().law.n > 0)) replan(ring.front(), in);
  }
  double left = dt;
  for (int n = 0; n < config_.max_blocks_per_cycle; ++n) {
    const Block& b = ring.front();
    if (!started_) replan(b, inputs(b));
    const double rest = ramp_.duration() - t_;
    if (left < rest) {
      t_ += left;
      const ProfileState st = ramp_.at(t_);
      const CurveFrame fr = b.frame(st.s);
      sp_.pos = fr.point;
      sp_.vel = fr.tangent * st.v;
      sp_.acc = fr.tangent * st.a + fr.curvature * (st.v * st.v);
      sp_.path_v = st.v;
      sp_.moving = true;
      sp_.rapid = b.rapid;
      sp_.tag = b.tag;
      sp_.tag_last = b.tag_last;
      if (stop_ != StopKind::None && st.v <= 0) return rest_at_window_end();  // P-5: at rest on the path, done
      return sp_;
    }
    // The block ends within this cycle: its leftover time goes into the next one.
    left -= rest;
    v_ = ramp_.v1;
    sp_.pos = b.end();
    sp_.tag = b.tag;
    sp_.tag_last = b.tag_last;
    ring.pop();
    started_ = false;
    if (!ring.empty() && std::isfinite(ring.front().j_mm_s3)) {
      s_ = 0;
      a_ = 0;
      cert_ = GuardVerdict{};
      // An open back alone is not planned with (PlanQueue::visible): the path waits at rest on its
      // start, as step() does (it arrives at rest: the junction into a jerk block is a stop).
      if (queue_.visible() == 0 && v_ == 0) {
        rest_at_end();
        return sp_;
      }
      return step_jerk(left);
    }
    if (ring.empty()) return rest_at_window_end();  // the tail ends at rest: exactly on the last programmed point
  }
  // Budget spent: the rest of this cycle's time is dropped (the path runs slower, never faster).
  const Block& b = ring.front();
  sp_.pos = b.point(0);
  sp_.vel = b.tangent(0) * v_;
  sp_.path_v = v_;
  return sp_;
}

}  // namespace softmc::motion
