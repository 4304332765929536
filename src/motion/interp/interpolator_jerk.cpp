// Jerk mode of the interpolator: the online jerk-limited path speed over the look-ahead window.
#include <algorithm>
#include <cmath>

#include "motion/interp/interpolator.hpp"
#include "motion/interp/jerk_follower.hpp"
#include "motion/profile/jerk_ramp.hpp"

namespace softmc::motion {

bool jerk_mode(const MachineLimits& lim) {
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (lim.present(i) && lim.axis[i].j_max_mm_s3 > 0) return true;
  return false;
}

namespace {
constexpr double kEps_mm = 1e-9;
constexpr double kEps_mm_s = 1e-9;

// A block without a jerk limit (Trapezoid profile, axes with j = 0) reaches its acceleration in one cycle.
double jerk_of(const Block& b, double dt) { return std::isfinite(b.j_mm_s3) ? b.j_mm_s3 : b.a_mm_s2 / dt; }

struct Binding {
  bool ok = true;
  ProfileState act{};  // the strongest braking action among the violated limits
  bool has_act = false;
};
}  // namespace

// rt-safe. Entry speed limit of block b: its junction and its own hard cap. (Not the trapezoid backward
// pass: its envelope assumes instant changes of acceleration; the follower checks every point ahead.)
double Interpolator::hard_limit(const Block& b) const { return std::min(std::sqrt(b.v2_junction), b.v_cap_mm_s); }

// rt-safe
const Setpoint& Interpolator::step_jerk(double dt) {
  auto& ring = queue_.ring();
  const bool h = halt();
  const double scale = stop_ == StopKind::Emergency ? config_.emergency_accel_scale : 1.0;
  const Block& f = ring.front();
  const double vt = h ? 0.0 : soft_speed(f);
  const std::size_t n = std::min<std::size_t>(ring.size(), static_cast<std::size_t>(config_.max_horizon_blocks));

  // Limits for the next cycle's acceleration: every block reached before |a| can be brought to 0.
  double a_c = f.a_mm_s2, j_c = jerk_of(f, dt);
  double a_now = a_c, j_now = j_c;  // the blocks this cycle may pass through
  {
    const double vpk = std::max(v_, inflection_speed(v_, a_, j_c)) + a_c * dt;
    const double near = vpk * (2 * a_c / j_c + 3 * dt) + kEps_mm;
    const double reach = vpk * dt * 1.5 + kEps_mm;
    double d = f.length - s_;
    for (std::size_t k = 1; k < n && d < near; ++k) {
      const Block& b = ring.at(k);
      a_c = std::min(a_c, b.a_mm_s2);
      j_c = std::min(j_c, jerk_of(b, dt));
      if (d < reach) {
        a_now = std::min(a_now, b.a_mm_s2);
        j_now = std::min(j_now, jerk_of(b, dt));
      }
      d += b.length;
    }
  }
  a_c *= scale;
  j_c *= scale;
  a_now *= scale;
  j_now *= scale;
  const ProfileState now{0, v_, a_, 0};

  // Can every limit ahead still be met from state x, reached after moving ds? When not, `act` is the
  // strongest of the actions that would meet the violated ones (lowest speed after this cycle).
  const auto check = [&](const ProfileState& x, double ds, bool want_action) {
    Binding worst;
    double a_run = a_now, j_run = j_now;
    // Limits of just the blocks before k: a stop at the start of block k never enters k or beyond,
    // so their (possibly lower) limits must not weaken the brake that lands on it — that is what
    // missed a stop after a 0.015 mm block when a slower helix came within this cycle's reach.
    double a_blk = f.a_mm_s2 * scale, j_blk = jerk_of(f, dt) * scale;
    double d = f.length - s_;  // distance from now to the start of block k
    const auto take = [&](const ProfileState& y) {
      if (!worst.has_act || y.v < worst.act.v || (y.v == worst.act.v && y.a < worst.act.a)) worst.act = y;
      worst.has_act = true;
    };
    if (x.v < -kEps_mm_s || inflection_speed(x.v, x.a, j_now) < -kEps_mm_s) worst.ok = false;  // would reverse
    for (std::size_t k = 1; k <= n; ++k) {
      const bool tail = k == n;
      double u = 0, a_next = 0;
      if (!tail) {
        const Block& b = ring.at(k);
        u = hard_limit(b);
        a_next = b.a_mm_s2 * scale;
        if (!h) {
          const double soft = soft_speed(b);
          if (soft > 0) u = std::min(u, soft);
        }
      }
      const double left = d - ds;
      const double a_brk = u <= 0 ? a_blk : a_run, j_brk = u <= 0 ? j_blk : j_run;
      bool violated;
      if (left <= kEps_mm) {
        violated = std::max({v_, x.v, inflection_speed(x.v, x.a, j_brk)}) > u + kEps_mm_s;  // crossed now
      } else {
        violated = brake_distance(x.v, x.a, u, a_brk, j_brk, a_next) > left + kEps_mm;
      }
      if (violated) {
        worst.ok = false;
        if (want_action) {
          if (u <= 0) {
            ProfileState y = stop_step(now, d, std::max({v_, vt, 1e-6}), a_brk, j_brk, dt);
            if (y.s > d) y.s = d;
            take(y);
            break;  // stopping here: nothing beyond this point matters
          } else if (a_next < a_run) {
            take(ramp_step(now, u, a_run, j_run, dt));
          } else {
            ProfileState y = brake_step(now, a_run, j_run, dt);
            if (y.v < 0 || inflection_speed(y.v, y.a, j_run) < 0) y = ramp_step(now, 0, a_run, j_run, dt);
            take(y);
          }
        }
      }
      if (tail) break;
      // Beyond the distance a full stop needs (within the blocks passed so far), nothing binds.
      if (left > 0 && left > brake_distance(x.v, x.a, 0, a_run, j_run, 0) + kEps_mm) break;
      const Block& b = ring.at(k);
      a_run = std::min(a_run, b.a_mm_s2 * scale);
      j_run = std::min(j_run, jerk_of(b, dt) * scale);
      a_blk = std::min(a_blk, b.a_mm_s2 * scale);
      j_blk = std::min(j_blk, jerk_of(b, dt) * scale);
      d += b.length;
    }
    return worst;
  };

  // Accelerate (or cruise) when that stays safe; else the strongest action a violated limit asks for:
  // stop exactly on a point of speed 0, ramp to a lower limit, or brake as hard as the limits allow.
  ProfileState x = ramp_step(now, vt, a_c, j_c, dt);
  const Binding bind = check(x, x.s, true);
  if (!bind.ok) {
    if (bind.has_act) {
      x = bind.act;
    } else {  // only a reversal was in the way
      x = ramp_step(now, 0, a_now, j_now, dt);
    }
  }
  if (x.s < 0) x.s = 0;
  v_ = std::max(0.0, x.v);
  a_ = v_ == 0 && x.a < 0 ? 0.0 : x.a;
  s_ += x.s;

  // Pass the blocks the cycle finished.
  for (int m = 0; m < config_.max_blocks_per_cycle && !ring.empty(); ++m) {
    const Block& b = ring.front();
    if (s_ < b.length - 1e-12) break;
    s_ = std::max(0.0, s_ - b.length);
    sp_.pos = b.end();
    sp_.tag = b.tag;
    ring.pop();
    started_ = false;
    if (!ring.empty() && !std::isfinite(ring.front().j_mm_s3)) {
      s_ = 0;  // a trapezoid block plans from its start at v_ (mixed profiles: the rest of the cycle is dropped)
      a_ = 0;
      break;
    }
  }
  if (ring.empty()) {  // the tail ends at rest: exactly on the last programmed point
    if (stop_ != StopKind::None) {
      queue_.clear();
      stop_ = StopKind::None;
      stopped_ = true;
    }
    rest_at_end();
    return sp_;
  }
  const Block& b = ring.front();
  const double s = std::min(s_, b.length);
  const Vec tan = b.tangent(s);
  sp_.pos = b.point(s);
  sp_.vel = tan * v_;
  sp_.acc = tan * a_ + b.curvature(s) * (v_ * v_);
  sp_.path_v = v_;
  sp_.moving = true;
  sp_.rapid = b.rapid;
  sp_.tag = b.tag;
  if (stop_ != StopKind::None && v_ <= 0 && a_ == 0) {  // P-5: at rest on the path, the stop is done
    queue_.clear();
    stop_ = StopKind::None;
    stopped_ = true;
    rest_at_end();
  }
  return sp_;
}

}  // namespace softmc::motion
