// Jerk mode of the interpolator: the online jerk-limited path speed over the look-ahead window.
#include <algorithm>
#include <array>
#include <cmath>

#include "motion/interp/interpolator.hpp"
#include "motion/interp/jerk_follower.hpp"
#include "motion/interp/jerk_guard.hpp"
#include "motion/profile/jerk_ramp.hpp"

namespace softmc::motion {

bool jerk_mode(const MachineLimits& lim) {
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (lim.present(i) && lim.axis[i].j_max_mm_s3 > 0) return true;
  return false;
}

namespace {
constexpr double kEps_mm = 1e-9;
constexpr double kSettle_mm = 1e-9;  // a hair short of a block's end at rest: settled, then snapped

// A block without a jerk limit (Trapezoid profile, axes with j = 0) reaches its acceleration in one cycle.
double jerk_of(const Block& b, double dt) { return std::isfinite(b.j_mm_s3) ? b.j_mm_s3 : b.a_mm_s2 / dt; }

}  // namespace


// rt-safe
const Setpoint& Interpolator::step_jerk(double dt) {
  auto& ring = queue_.ring();
  const bool h = halt();
  const double scale = stop_ == StopKind::Emergency ? config_.emergency_accel_scale : 1.0;
  const Block& f = ring.front();
  const double vt = h ? 0.0 : soft_speed(f);
  // The blocks it may plan with (an open back's jerk may still fall: PlanQueue::visible).
  // (None only while moving into an open back alone: never, step() and step_trapezoid() wait at
  // rest before it; taken as the front, as before the open back was held out.)
  const std::size_t n = std::min<std::size_t>(std::max<std::size_t>(1, queue_.visible()),
                                              static_cast<std::size_t>(config_.max_horizon_blocks));

  // Limits for the next cycle's acceleration: every block reached before |a| can be brought to 0.
  // Cruising at the speed asked for, the ramp holds that speed whatever they are, and a cycle a
  // cruise certificate settles uses nothing else: the walk (tens of blocks at speed, about 500
  // instructions a cycle on the smoothed benchmark) waits until a candidate needs them.
  double a_c = f.a_mm_s2 * scale, j_c = jerk_of(f, dt) * scale;
  double a_now = a_c, j_now = j_c;  // the blocks this cycle may pass through
  bool walked = false;
  const auto walk_limits = [&] {
    walked = true;
    a_c = f.a_mm_s2;
    j_c = jerk_of(f, dt);
    a_now = a_c;
    j_now = j_c;
    const double vpk = std::max(v_, inflection_speed(v_, a_, j_c)) + a_c * dt;
    const double near = vpk * (2 * a_c / j_c + 3 * dt) + kEps_mm;
    const double reach = vpk * dt * 1.5 + kEps_mm;
    double d = f.length - s_;
    for (std::size_t k = 1; k < n && d < near && ring.at(k).v2_junction > 0; ++k) {
      const Block& b = ring.at(k);
      j_c = std::min(j_c, jerk_of(b, dt));
      // A block d ahead is reached no sooner than d / vpk: |a| may be above its limit now by what
      // the jerk takes off in that time (the guard checks every block's limit on the brake).
      a_c = std::min(a_c, b.a_mm_s2 + j_c * std::max(0.0, d - reach) / vpk);
      if (d < reach) {
        a_now = std::min(a_now, b.a_mm_s2);
        j_now = std::min(j_now, jerk_of(b, dt));
      }
      d += b.length;
    }
    a_c = std::min(a_c, a_now);
    a_c *= scale;
    j_c *= scale;
    a_now *= scale;
    j_now *= scale;
  };
  const bool at_cruise = vt > 0 && v_ == vt && a_ == 0;
  // A step from rest is also a second difference of step/dt² (and −step/dt² after it): within half
  // the block's acceleration, where an axis without a jerk limit makes the path's J huge (a
  // fuzzer's stub moving X by 1e-5 of its length, X with a jerk limit and Y without: J 1.3e8 mm/s³,
  // J·dt³/8 = 16 µm, and a 8.3 µm stub taken in one step was 8.3× Y's acceleration).
  const auto rest_step = [dt](double j, double a) { return std::min(j * dt * dt * dt / 8, a * dt * dt / 2); };
  // A hair short of the front block's end: noise against one cycle's jerk step (snapped at once,
  // worked out only at rest), or up to kSettle_mm, where the follower settles before the snap (below).
  const auto noise = [&] { return 1e-6 * jerk_of(f, dt) * dt * dt * dt; };
  // The snap after three cycles at rest puts d, −2d, d in the third differences and d, −d in the
  // second: within the block's J and A for d ≤ J·dt³/2 and A·dt². A longer hair (only near the jerk
  // floor, where J·dt³/2 < kSettle_mm) is left to the position-mode stop, as any short move.
  const auto settle_band = [&] { return std::min({kSettle_mm, jerk_of(f, dt) * dt * dt * dt / 2, f.a_mm_s2 * dt * dt}); };
  // At rest in that band, waiting for the snap onto the block's end.
  const bool settling = v_ == 0 && a_ == 0 && f.length - s_ > noise() && f.length - s_ <= settle_band();
  if (!at_cruise) walk_limits();
  const ProfileState now{0, v_, a_, 0};

  // Candidates for this cycle, each taken only when a fallback brake from where it ends still meets
  // every limit ahead (JerkGuard: its certificate ramp, or π simulated): first the ramp towards the
  // cruise speed; when that is refused, a position-mode stop on the point it missed, a ramp to the
  // speed it missed, holding the acceleration, lowering it — the fastest accepted one wins. The
  // fallback certified when the present state was accepted is always safe from here (its rest is
  // what was checked), so one cycle of it is the last resort.
  scratch_.groups = config_.guard_index;
  scratch_.bracket = config_.guard_distance_bracket;
  const JerkGuard guard(ring, n, s_, v_, dt, scale, h, rule_, scratch_);
  GuardMode mode;
  mode.closed_form = config_.guard_closed_form;
  mode.certify = config_.guard_certificate;
  mode.simulate = config_.guard_simulate;
  mode.simulate_up_to_s = config_.guard_short_brake_cycles * dt;
  mode.gate = config_.guard_gate;
  mode.jerk_gate = config_.guard_jerk_gate;
  PathStep step = ramp_cycle(now, vt, a_c, j_c, dt);
  const bool refuse = config_.guard_refuse_from_cycle >= 0 &&
                      jerk_cycles_ >= static_cast<std::uint64_t>(config_.guard_refuse_from_cycle);
  // The guard's verdict on a candidate, counted (the benchmarks report verifies and simulations).
  const auto verify = [&](const PathStep& c) {
    const GuardVerdict v = guard.verify(c, mode);
    ++guard_verifies_;
    guard_simulations_ += v.simulated ? 1 : 0;
    return v;
  };
  // Cruising at the speed asked for: within a cruise certified ahead, only the step itself is
  // checked; where none covers the step, such a certificate is tried first (JerkGuard::
  // certify_cruise), and the step verified as any other where there is none.
  const bool cruise = mode.certify && !refuse && config_.guard_cruise_cycles > 1 && vt > 0 && now.v == vt &&
                      now.a == 0 && step.x.v == vt && step.x.a == 0;
  const auto covered = [&] {
    return cruise_.valid && cruise_.epoch == scratch_.epoch && cruise_.v == vt &&
           guard.window_end_in_index() >= cruise_.window_end && guard.now_in_index() + step.x.s <= cruise_.end;
  };
  if (cruise && !covered() && --cruise_.wait < 0) {
    if (cruise_.cycles < 2) cruise_.cycles = config_.guard_cruise_cycles;
    PathStep ahead;
    ahead.x = {static_cast<double>(cruise_.cycles) * vt * dt, vt, 0, 0};
    ahead.v_peak = ahead.v_min = vt;
    const GuardVerdict c = guard.certify_cruise(ahead);
    ++guard_verifies_;
    if (!c.failed() && c.cert_a > 0) {
      cruise_ = {true, scratch_.epoch, guard.window_end_in_index(), vt, guard.now_in_index() + ahead.x.s, c.cert_a,
                 c.cert_j, 0, config_.guard_cruise_cycles};
    } else if ((cruise_.cycles /= 2) < 2) {
      cruise_.wait = config_.guard_cruise_cycles / 2;
    }
  }
  GuardVerdict first;
  bool settled = false;
  if (cruise && covered()) {
    first = guard.check_step(step);
    settled = !first.failed();
    if (settled) {
      first.cert_a = cruise_.a;
      first.cert_j = cruise_.j;
      ++cruise_hits_;
    }
  }
  if (!settled) {
    cruise_.valid = false;
    if (!walked) {
      walk_limits();
      step = ramp_cycle(now, vt, a_c, j_c, dt);
    }
    first = verify(step);
  }
  if (refuse) first.hard_ok = false;
  ++jerk_cycles_;
  GuardVerdict taken = first;
  ProfileState stop_x{};  // the position-mode stop's end state, when it was a candidate
  bool asked_stop = false;
  const double stop_v = std::max({v_, vt, 1e-6});  // a position-mode stop's speed limit
  double stop_at = 0, stop_vmax = 0;  // its point (from now) and speed limit
  double ramp_u = 0;   // the speed of the ramp to a speed limit the first candidate missed, when it is one
  // A ramp to the speed limit u is a candidate down to it, or, from rest, up to it: a few nanometres
  // before a tiny block whose cap is far below what one cycle at full jerk reaches, no other
  // candidate moves at all. (Ramping up to it while moving was tried: greedy, surfacing.ngc 0.3 %
  // slower.)
  const auto ramp_to = [&](double u) { return u > 0 && (u < v_ || (v_ == 0 && a_ == 0)); };
  // A position-mode stop on the point `at` ahead, no faster than vmax (the stop plan kept while it is taken).
  const auto stop_step = [&](double at, double vmax) {
    double a_s = 0, j_s = 0;
    guard.limits_until(at, a_s, j_s);
    const ProfileState y = stop_plan_.step(now, at, vmax, a_s, j_s, dt);
    stop_x = y;
    asked_stop = true;
    stop_at = at;
    stop_vmax = vmax;
    PathStep st;
    st.x = y;
    st.gen = StepGen::Stop;
    st.j_abs = j_s;
    st.a_abs = std::max(std::abs(now.a), std::abs(y.a));
    st.v_peak = std::max({now.v, y.v, now.a > 0 ? inflection_speed(now.v, now.a, j_s) : now.v});
    st.v_min = std::min(now.v, y.v);
    return st;
  };
  if (first.failed()) {
    std::array<PathStep, 5> cand{};
    std::size_t m = 0;
    if (first.stop_binds && first.fail_at_mm > 0) {
      cand[m++] = stop_step(first.fail_at_mm, stop_v);
    } else if (ramp_to(first.fail_u_mm_s)) {
      ramp_u = first.fail_u_mm_s;
      cand[m++] = ramp_cycle(now, ramp_u, a_c, j_c, dt);
    }
    if (!asked_stop && v_ == 0 && a_ == 0 && rest_cycles_ >= 3 && !h && vt > 0 && f.length > s_) {
      // At rest for three cycles with every move refused: a position-mode stop on the front
      // block's end, no faster than its cap. Blocks of a few nanometres whose caps are 1e-4 mm/s
      // are passed so, a few cycles each, where a ramp that reaches their cap within a cycle would
      // still pass the slower jerk further on too fast (and the step onto them below is too long).
      // A hundredth below the cap: a plan that cruises on the cap exactly is refused for rounding.
      cand[m++] = stop_step(f.length - s_, 0.99 * std::min(vt, f.v_cap_mm_s));
    }
    cand[m++] = jerk_cycle(now, 0, dt);
    cand[m++] = jerk_cycle(now, -j_now, dt);
    if (refuse) m = 0;
    // Faster first; at equal speed, farther (a stop landing on its point beats staying short of it).
    const auto ahead = [](const PathStep& l, const PathStep& r) {
      return l.x.v > r.x.v || (l.x.v == r.x.v && l.x.s > r.x.s);
    };
    std::sort(cand.begin(), cand.begin() + static_cast<std::ptrdiff_t>(m), ahead);
    // The last resort: one cycle of the fallback brake certified when the present state was accepted.
    taken = cert_;
    taken.simulated = false;
    if (cert_.cert_a2 > 0) {
      step = guard.gated_brake(now, cert_);
      // Its distance to the gate shrinks with the step; past the gate the rest is the ramp to rest.
      taken.cert_gate_mm -= step.x.s;
      if (!(taken.cert_gate_mm > 0)) {
        taken.cert_a = cert_.cert_a2;
        taken.cert_j = cert_.cert_j2;
        taken.cert_a2 = taken.cert_j2 = taken.cert_w = taken.cert_gate_mm = 0;
      }
    } else {
      step = cert_.cert_a <= 0 ? guard.brake_now(now)
             : first.stop_binds  ? guard.anchored_brake(now, cert_.cert_a, cert_.cert_j, first.fail_at_mm)
                                 : guard.certified_brake(now, cert_.cert_a, cert_.cert_j);
    }
    int retries = 0;
    for (std::size_t i = 0; i < m; ++i) {
      // The position-mode stop also where it ties with the fallback to rounding: both land on the
      // same point (the fallback anchored on it), the stop's plan stretched onto it may be a few ulps
      // slower, and taking it keeps its plan for the next cycles (StopPlan) instead of solving again.
      const bool stop = asked_stop && cand[i].x.s == stop_x.s && cand[i].x.v == stop_x.v && cand[i].x.a == stop_x.a;
      if (!ahead(cand[i], step) && !(stop && cand[i].x.v >= step.x.v - 1e-12 * std::max(1.0, step.x.v))) continue;
      const GuardVerdict v = verify(cand[i]);
      if (!v.failed()) {
        step = cand[i];
        taken = v;
        break;
      }
      // A stop or a ramp to a speed limit, refused for a nearer point to stop at or a slower limit
      // on the way: the stop or the ramp for that one instead, or the same stop no faster than
      // that limit (at most four times). Tiny blocks
      // whose caps fall one after another within one cycle's distance, or an exact stop a few
      // nanometres behind a slow one (CAM zigzags), are otherwise never entered from rest: every
      // step of one cycle would pass one of them too fast, and no other candidate moves at all.
      const bool is_ramp = ramp_u > 0 && cand[i].x.v == ramp_u && cand[i].x.a == 0;
      if (!(stop || is_ramp) || retries >= 4) continue;
      if (v.stop_binds && v.fail_at_mm > 0 && (!asked_stop || v.fail_at_mm < stop_at)) {
        cand[i] = stop_step(v.fail_at_mm, stop ? stop_vmax : stop_v);
      } else if (stop && !v.stop_binds && v.fail_u_mm_s > 0 && v.fail_u_mm_s < stop_vmax) {
        cand[i] = stop_step(stop_at, v.fail_u_mm_s);  // the same stop, no faster than that limit
      } else if (!v.stop_binds && ramp_to(v.fail_u_mm_s) && (ramp_u == 0 || v.fail_u_mm_s < ramp_u)) {
        ramp_u = v.fail_u_mm_s;
        cand[i] = ramp_cycle(now, ramp_u, a_c, j_c, dt);
      } else {
        continue;
      }
      ++retries;
      --i;  // checked next (unsigned: ++i brings it back)
    }
  }
  // A further candidate, taken in place of the step so far when the guard accepts it.
  const auto take_if_safe = [&](const PathStep& c) {
    const GuardVerdict v = verify(c);
    if (v.failed()) return;
    step = c;
    taken = v;
  };
  // Asked to slow down (a hold, a stop, an override or limit below the speed) while still
  // accelerating: the ramp plans with the least jerk of every block it may reach, and so takes |a|
  // down no faster than that (3 000 mm/s³ ahead of a blend), where the block the path is in allows
  // j_now this cycle. Bringing a down at j_now is then the faster way to slow (a hold written while
  // accelerating towards a blend overshot the feed by 36 %: a fuzzer's case), taken when it is safe.
  if (!first.failed() && vt < v_ && a_ > 0 && j_now > j_c) {
    const PathStep down = jerk_cycle(now, -j_now, dt);
    if (down.x.a >= 0 && down.x.v < step.x.v) take_if_safe(down);
  }
  // Braking while a block ahead allows less jerk than the one the path is in (a short corner after
  // a line: 3 000 against 10 000 mm/s³): every candidate above eases the brake at that lower j_c,
  // slower than the path may, and from a hard brake the certificate refuses them (they would
  // reverse), so the follower rode its fallback brake to near rest before the corner and crept in
  // (surfacing.ngc: at every pass end). Easing at j_now, the jerk of the blocks this cycle can
  // reach, is a candidate too, taken when the guard accepts it and it is faster. Only where the
  // jerk ahead is far lower (below half, as the certificate's jerk gate): tried wherever it is
  // lower, the extra check cost 10.7 % more instructions per arc-blended cycle for 0.56 % on
  // pocket.ngc and 0.21 % on 3D_Chips (with stop 21's corner stops: +3.8 % per smoothed cycle,
  // pocket 0.57 % and 3D_Chips 0.17 % quicker).
  if (config_.ease_brake && a_ < 0 && j_now > 2 * j_c && !refuse) {
    const PathStep ease = ramp_cycle(now, vt, a_c, j_now, dt);
    if (ease.x.v > step.x.v) take_if_safe(ease);
  }
  // Settling onto a block's end (below): at rest, a hair short of it, every move is a zero step
  // until the three cycles of rest let the snap take that hair as the only motion in its third
  // differences.
  if (settling) {
    step = jerk_cycle(now, 0, dt);
    taken = GuardVerdict{};
  }
  cert_ = taken;
  // The stop plan is kept only while its steps are the ones taken.
  stop_plan_.taken(config_.keep_stop_plan && asked_stop && step.x.s == stop_x.s && step.x.v == stop_x.v &&
                   step.x.a == stop_x.a);
  ProfileState x = step.x;
  if (x.s < 0) x.s = 0;
  v_ = std::max(0.0, x.v);
  a_ = v_ == 0 && x.a < 0 ? 0.0 : x.a;
  // Rounding's rest is rest: a ramp from (0.5 mm/s, −1000 mm/s²) at 10⁶ mm/s³ ends a cycle at
  // 7·10⁻¹⁵ mm/s, a = 0 (a fuzzer's: a 3.6 µm line at F60 after a braking run). The rules for a
  // follower at rest (the ramp up from rest, the stop on the block's end after three cycles) ask
  // for v = a = 0 exactly, the ramp to the cap was refused for rounding at its peak, and the path
  // coasted at 7·10⁻¹⁵ mm/s for ever. Below 10⁻¹² mm/s (10⁻¹⁵ mm a cycle) it is rest.
  if (v_ <= 1e-12 && std::abs(a_) <= 1e-9) v_ = a_ = 0;
  s_ += x.s;
  // At rest on a point to stop at (the position-mode stop lands on it up to the rounding of the
  // distance from now): the block is done. Also at rest for three cycles or more just short of one,
  // by at most an eighth of the block's j·dt³: a fallback brake can end a few nanometres short (a
  // review's exploration found 4.4e-9 mm on a soft Z), where no position-mode stop fits in whole
  // cycles and every candidate is refused, so the follower would stay there for ever. The step is
  // then the only motion in its third differences on one side (three cycles of rest), and on the
  // other the next block starts from rest: per axis at most j_i·dt³·(1/8 + 5/6) (J·|t_i| ≤ j_i).
  rest_cycles_ = x.s == 0 && v_ == 0 && a_ == 0 ? rest_cycles_ + 1 : 0;
  const double left = f.length - s_;
  const bool at_stop = n < 2 || ring.at(1).v2_junction <= 0;
  // Only where the step ended on or before the block's end (to its rounding): a position-mode stop
  // that came to rest past it, inside the next block, was pulled back onto the junction (a fuzzer's
  // 0.1 µm last line: Y 1.09× its jerk where the path went on from there); the pass below carries
  // such a step into the next block instead.
  // A hair short of the end (up to kSettle_mm) is snapped onto it at once only where that hair is
  // noise against one cycle's jerk step (1e-6 of j·dt³); a longer one, after three cycles of rest
  // (`settling`): a brake to rest landed 2.5e-10 mm short of a program's end, and the snap in the
  // same cycle as the brake's last jerk phase added 2.5e-10/dt³ to it (a fuzzer's case: Y 1.0016×
  // its 10 000 mm/s³ at 0.25 ms). Snapping only the noise and letting the follower land the rest
  // crept there for 0.4 s at 1e-9 mm/s, neither moving nor at rest. After the rest the snap's
  // third differences are d, −2d, d alone (`settle_band`). Near the jerk floor a hair above the
  // band is not snapped at all: up to 1e-9 mm was, in the brake's last phase (a review's case: Y at
  // 1.285× its 400 mm/s³ at 0.1 ms).
  const bool resting = v_ <= 1e-9 && std::abs(a_) <= 1e-6 && left >= -1e-9;
  const double settle = resting ? settle_band() : 0.0;
  if (resting && (left <= noise() || (left <= settle && rest_cycles_ >= 3) ||
                  (at_stop && !h && rest_cycles_ >= 3 && left <= rest_step(jerk_of(f, dt), f.a_mm_s2)))) {
    s_ = f.length;
    v_ = 0;
    a_ = 0;
  } else if (resting && left > 0 && left <= settle) {
    v_ = 0;  // settling: the next cycles take zero steps (`settling`) until the snap above
    a_ = 0;
  } else if (rest_cycles_ >= 3 && !h && vt > 0 && std::isfinite(f.j_mm_s3)) {
    // At rest, and refused every move for three cycles, before blocks so short and slow that one
    // cycle from rest passes them too fast (a blend of 1e-6 mm at 1e-3 mm/s where a return line runs
    // back almost onto its outgoing one, CAM zigzags of a few nanometres): the end of the farthest
    // of them within J·dt³/8 of path, J the least path jerk on the way, is taken as one step, no
    // further than an exact stop. Per axis that is at most j_i·dt³/8 (J·|t_i| ≤ j_i on every block
    // kind and the chord is no longer than the path), as the rest onto a stop above; and no further
    // than A·dt²/2, A the least path acceleration on the way (rest_step).
    double d = left, jmin = f.j_mm_s3, amin = f.a_mm_s2, to = -1;
    for (std::size_t k = 1; d <= rest_step(jmin, amin); ++k) {
      to = d;
      if (k >= n || ring.at(k).v2_junction <= 0 || !std::isfinite(ring.at(k).j_mm_s3)) break;
      jmin = std::min(jmin, ring.at(k).j_mm_s3);
      amin = std::min(amin, ring.at(k).a_mm_s2);
      d += ring.at(k).length;
    }
    if (to > 0) s_ += to;
  }

  // Pass the blocks the cycle finished.
  for (int m = 0; m < config_.max_blocks_per_cycle && !ring.empty(); ++m) {
    const Block& b = ring.front();
    // Only once s reaches the block's length: passing it a picometre early dropped that distance
    // (s − length clamped to 0), a position step of up to 1e-12 mm, which is several times one
    // cycle's jerk where j·dt³ is near its floor (motion::kMinJerkStep_mm).
    if (s_ < b.length) break;
    // A point to stop at (an exact stop, the end of what is planned) is passed only at rest: a brake
    // whose last jerk phase ends a few µs into the next cycle reaches it with v ≈ 0 but |a| > 0, and
    // passing then would turn that acceleration with the path's direction (an axis acceleration
    // step). The next cycle ends the brake on the spot and the rest test above passes the block.
    if ((queue_.visible() < 2 || ring.at(1).v2_junction <= 0) && (v_ > 1e-9 || std::abs(a_) > 1e-6)) {
      s_ = b.length;
      break;
    }
    s_ = std::max(0.0, s_ - b.length);
    sp_.pos = b.end();
    sp_.tag = b.tag;
    sp_.tag_last = b.tag_last;
    ring.pop();
    started_ = false;
    if (!ring.empty() && !std::isfinite(ring.front().j_mm_s3)) {
      // A block without a jerk limit (a Trapezoid move, or one moving only axes with j = 0) plans
      // from its start at the speed the path crossed it with; the time this cycle ran past the end
      // is run on it, as step() passes a trapezoid block's leftover time to the jerk follower.
      // Dropping it dipped the speed for one cycle: 20–50 times the acceleration limit at speed (a
      // review's exploration). The crossing is found on the phases the cycle's step ran (step_at,
      // the stop plan's last_at), cut where they reach the block's end: taking the cycle's end speed
      // and s/v for the time lost a tenth of a micrometre at a blend into a line (0.7 % over the next
      // cycle's acceleration limit), and one cubic through the cycle's start and end, exact for one
      // jerk phase only, left 2e-3 mm/s where the ramp reached its acceleration within the cycle
      // (2e-4 over: fuzzers' cases).
      double left_s = 0;
      if (v_ > 0 && x.s > 0) {
        const double to_end = x.s - s_;
        // (A stop step is the stop plan's last one, unless a stop candidate planned earlier in the
        // cycle was taken (a review's reading: not seen to happen); then the cubic through the
        // cycle's start and end, exact for one jerk phase, as before.)
        const ProfileState plan_end = step.gen == StepGen::Stop ? stop_plan_.last_at(dt) : ProfileState{};
        const bool plan_is_step = plan_end.s == step.x.s && plan_end.v == step.x.v;
        const double c = (step.x.s - now.v * dt - 0.5 * now.a * dt * dt) / (dt * dt * dt);
        const auto at = [&](double t) {
          if (step.gen != StepGen::Stop) return step_at(now, step, t);
          if (plan_is_step) return stop_plan_.last_at(t);
          return ProfileState{now.v * t + 0.5 * now.a * t * t + c * t * t * t, now.v + now.a * t + 3 * c * t * t, 0, 0};
        };
        double lo = 0, hi = dt;
        for (int it = 0; it < 60 && lo < hi; ++it) {
          const double t = 0.5 * (lo + hi);
          (at(t).s < to_end ? lo : hi) = t;
        }
        const double t_x = 0.5 * (lo + hi);
        left_s = dt - t_x;
        v_ = std::clamp(at(t_x).v, std::max(0.0, step.v_min), std::max(step.v_peak, x.v));
      }
      s_ = 0;
      a_ = 0;
      cert_ = GuardVerdict{};
      if (left_s > 0) return step_trapezoid(left_s);
      break;
    }
  }
  if (ring.empty()) return rest_at_window_end();  // the tail ends at rest: exactly on the last programmed point
  const Block& b = ring.front();
  const double s = std::min(s_, b.length);
  const CurveFrame fr = b.frame(s);
  sp_.pos = fr.point;
  const double v2 = v_ * v_;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    sp_.vel[i] = fr.tangent[i] * v_;
    sp_.acc[i] = fr.tangent[i] * a_ + fr.curvature[i] * v2;
  }
  sp_.path_v = v_;
  sp_.moving = true;
  sp_.rapid = b.rapid;
  sp_.tag = b.tag;
  sp_.tag_last = b.tag_last;
  if (stop_ != StopKind::None && v_ <= 0 && a_ == 0) return rest_at_window_end();  // P-5: at rest on the path, done
  return sp_;
}

// rt-safe. The corner overlap (docs/planner.md, "Corner overlap"): braking onto a corner between two
// lines that the planner left a stop within a tolerance (the second's overlap_mm), the first line's
// end is run on beside the path as a position-mode stop from the present state (the tail) and the
// second line begins from rest at once, as soon as every setpoint that makes is within overlap_mm
// of the program (below). Each axis's speed, acceleration and jerk are the sums of both:
// the second line's limits are lowered, while the tail runs, to what each axis has left beside the
// tail's bounds (its speed now, its acceleration, the first line's jerk), with every axis's limit
// the machine's (InterpolatorConfig::axis_limits; unknown: the larger of what the two lines allow
// it, as both keep it). The second
// line must be long enough that nothing jerk-limited from rest leaves it before the tail ends.
void Interpolator::begin_overlap(double dt) {
  auto& ring = queue_.ring();
  if (ring.size() < 3) return;
  const Block& g = ring.at(1);
  if (!(g.overlap_mm > 0) || g.v2_junction > 0 || ring.pops() == overlap_refused_) return;
  if (halt() || started_ || queue_.visible() < 3) return;
  const Block& f = ring.front();
  const double left = f.length - s_;
  // Within reach of the deviation bound below only (each look costs a stop's solve).
  if (!(left > 0) || left > 4 * g.overlap_mm) return;
  if (f.is_blend || g.is_blend || f.seg.kind != SegmentKind::Line || g.seg.kind != SegmentKind::Line ||
      !std::isfinite(f.j_mm_s3) || !std::isfinite(g.j_mm_s3) || !(f.j_mm_s3 > 0) || !(g.j_mm_s3 > 0)) {
    overlap_refused_ = ring.pops();
    return;
  }
  // The second line's limits with each axis's share of the tail taken off: its speed v_t and
  // largest |a| a_t, and the first line's jerk (the tail's jerk phases use all of it).
  const Vec& u1 = f.seg.dir;
  const Vec& u2 = g.seg.dir;
  const auto lowered = [&](double v_t, double a_t, double& a2, double& j2, double& v2) {
    a2 = g.a_mm_s2;
    j2 = g.j_mm_s3;
    v2 = g.v_cap_mm_s;
    for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
      const double t1 = std::abs(u1[i]), t2 = std::abs(u2[i]);
      if (!(t2 > 1e-12)) continue;
      // The axis's own limits where known (each line keeps them, so at least what it allows it).
      const AxisLimits& al = config_.axis_limits.axis[i];
      const bool known = config_.axis_limits.present(i) && al.j_max_mm_s3 > 0;
      const double A = std::max({t1 * f.a_mm_s2, t2 * g.a_mm_s2, known ? al.a_max_mm_s2 : 0.0});
      const double J = std::max({t1 * f.j_mm_s3, t2 * g.j_mm_s3, known ? al.j_max_mm_s3 : 0.0});
      const double V = std::max({t1 * f.v_cap_mm_s, t2 * g.v_cap_mm_s, known ? al.v_max_mm_s : 0.0});
      a2 = std::min(a2, (A - t1 * a_t) / t2);
      j2 = std::min(j2, (J - t1 * f.j_mm_s3) / t2);
      v2 = std::min(v2, (V - t1 * v_t) / t2);
    }
  };
  // Where the tail leaves the second line less than half its acceleration or jerk, the corner
  // stays a stop: the line would start too gently to gain. The jerk's share does not depend on
  // where the tail begins: refused once, this corner is not looked at again.
  double a2 = 0, j2 = 0, v2 = 0;
  lowered(0, 0, a2, j2, v2);
  if (!(j2 >= 0.5 * g.j_mm_s3)) {
    overlap_refused_ = ring.pops();
    return;
  }
  // The tail: the time-optimal stop on the corner from here, within the first line's limits and
  // no faster than now. Taken only where it lands without passing the corner or reversing.
  Otg1 otg;
  otg.reset({-left, v_, a_, 0});
  if (otg.update(0.0, {v_, f.a_mm_s2, f.j_mm_s3}) == OtgResult::ErrorInvalidInput) return;
  const double T = otg.duration_s();
  if (!(T > 0) || T > 0.25) return;
  // Nothing from rest at jerk ≤ g's leaves g within T.
  if (!(g.length > 2 * g.j_mm_s3 * T * T * T / 6)) return;
  // The setpoint is the second line's point plus the tail's offset, whose length is what the tail
  // has left, d(t): at most d(t) from the first line's point there, and at most the second line's
  // progress from the corner's point on the second, which from rest at jerk ≤ j is j·t³/6. Both
  // are points of the program, so each cycle's setpoint lies within min(d, j·t³/6) of it: that
  // must stay within overlap_mm (the tail starts where the two cross below it, not only once d is).
  const double p_mm = g.overlap_mm;
  if (!(-otg.at(dt).s <= p_mm || g.j_mm_s3 * dt * dt * dt / 6 <= p_mm)) return;
  double v_t = v_, a_t = std::abs(a_);
  for (double t = dt; t < T + dt; t += dt) {
    const double tc = std::min(t, T);
    const ProfileState x = otg.at(tc);
    if (x.s > 1e-12 || x.v < -1e-12) return;
    if (std::min(-x.s, g.j_mm_s3 * t * t * t / 6) > p_mm) return;
    v_t = std::max(v_t, x.v);
    a_t = std::max(a_t, std::abs(x.a));
  }
  lowered(v_t, a_t, a2, j2, v2);
  if (!(a2 >= 0.5 * g.a_mm_s2) || !(j2 >= 0.5 * g.j_mm_s3) || !(v2 > 0)) return;

  // Begin: the first line is done for the path; the second starts from rest, the tail beside it.
  sp_.pos = f.end();
  tail_.tag = f.tag;
  tail_.tag_last = f.tag_last;
  tail_.rapid = f.rapid;
  tail_.a1 = f.a_mm_s2;
  tail_.j1 = f.j_mm_s3;
  tail_.emergency = false;
  ring.pop();
  Block& h = ring.front();
  tail_.active = true;
  tail_.otg = otg;
  tail_.dir = u1;
  tail_.t = 0;
  tail_.a = h.a_mm_s2;
  tail_.j = h.j_mm_s3;
  tail_.v_cap = h.v_cap_mm_s;
  tail_.v_split = h.v_split_mm_s;
  tail_.pops = ring.pops();
  h.a_mm_s2 = a2;
  h.j_mm_s3 = j2;
  h.v_cap_mm_s = std::min(h.v_cap_mm_s, v2);
  h.v_split_mm_s = std::min(h.v_split_mm_s, h.v_cap_mm_s);
  ring.touch();
  s_ = v_ = a_ = 0;
  cert_ = GuardVerdict{};
  stop_plan_.taken(false);
  cruise_.valid = false;
  rest_cycles_ = 0;
  ++overlaps_;
}

}  // namespace softmc::motion
