// Online trajectory generation for one axis: candidate peak speeds, the fastest valid one laid out on a JerkPath.
#include "motion/profile/otg1.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "motion/profile/jerk_ramp.hpp"

namespace softmc::motion {

namespace {

bool finite(const ProfileState& x) {
  return std::isfinite(x.s) && std::isfinite(x.v) && std::isfinite(x.a);
}

// Validates and normalises the limits (an infinite jerk is no jerk limit).
bool normalise(OtgLimits& l) {
  if (!(l.v_max_mm_s > 0) || !std::isfinite(l.v_max_mm_s)) return false;
  if (!(l.a_max_mm_s2 > 0) || !std::isfinite(l.a_max_mm_s2)) return false;
  if (std::isnan(l.j_max_mm_s3) || l.j_max_mm_s3 < 0) return false;
  if (std::isinf(l.j_max_mm_s3)) l.j_max_mm_s3 = 0;
  return true;
}

struct Candidate {
  double vp = 0;
  double t_cruise = 0;
  double duration = INFINITY;
};

}  // namespace

const char* to_string(OtgResult r) {
  switch (r) {
    case OtgResult::Working: return "working";
    case OtgResult::Finished: return "finished";
    case OtgResult::ErrorInvalidInput: return "invalid input";
  }
  return "?";
}

// rt-safe
PeakTrial otg_peak_trial(const ProfileState& x, double vp, const OtgLimits& lim) {
  const Ramp r1 = plan_ramp(x.v, x.a, vp, lim.a_max_mm_s2, lim.j_max_mm_s3);
  const Ramp r2 = plan_ramp(vp, 0, 0, lim.a_max_mm_s2, lim.j_max_mm_s3);
  const ProfileState e = ramp_end({0, x.v, x.a, 0}, r1);
  // The second ramp starts and ends with a = 0: its length is its mean speed times its duration.
  return {e.s + 0.5 * vp * r2.duration(), r1.duration() + r2.duration()};
}

void Otg1::reset(const ProfileState& x) {
  now_ = x;
  now_.j = 0;
  t_ = 0;
  path_.reset(now_);
  mode_ = now_.v == 0 ? OtgMode::Position : OtgMode::Velocity;
  target_mm_ = now_.s;
  target_v_ = now_.v;
}

ProfileState Otg1::begin(const OtgLimits& lim) {
  path_.reset(now_);
  t_ = 0;
  const double j = lim.j_max_mm_s3, am = lim.a_max_mm_s2;
  if (j > 0 && std::abs(now_.a) > am) path_.push((std::abs(now_.a) - am) / j, now_.a > 0 ? -j : j);
  ProfileState b = path_.end();
  if (j > 0) b.a = std::clamp(b.a, -am, am);  // exactly on the limit after the brake
  return b;
}

// rt-safe: at most kGrid + 7 trials to bracket, then ≤ 100 root-finding steps per bracket.
OtgResult Otg1::update(double target_mm, const OtgLimits& limits) {
  OtgLimits lim = limits;
  if (!normalise(lim) || !std::isfinite(target_mm) || !finite(now_)) return OtgResult::ErrorInvalidInput;
  const ProfileState b = begin(lim);
  const double vm = lim.v_max_mm_s, am = lim.a_max_mm_s2, j = lim.j_max_mm_s3;
  const double dp = target_mm - b.s;

  Candidate best;
  // A cruise only for the ±v_max candidates: a root's leftover is rounding, snapped at the end (a cruise at a
  // near-zero root speed would be long).
  auto consider = [&](double vp, double length, double dur, bool cruise) {
    const double tc = cruise ? std::max(0.0, (dp - length) / vp) : 0.0;
    if (dur + tc < best.duration) best = {vp, tc, dur + tc};
  };
  // Cruise at ±v_max when the no-cruise length falls short of the distance.
  const PeakTrial up = otg_peak_trial(b, vm, lim), down = otg_peak_trial(b, -vm, lim);
  if (dp >= up.length_mm) consider(vm, up.length_mm, up.duration_s, true);
  if (dp <= down.length_mm) consider(-vm, down.length_mm, down.duration_s, true);

  // No cruise: roots of length(vp) = dp, bracketed on the speeds where the length function has kinks (the
  // ramps' direction changes, where they start to saturate a_max) plus a coarse grid as insurance: the kinks
  // alone already match a 20000-point brute-force scan (test Otg.NoBetterPeakSpeedExists).
  constexpr int kGrid = 8;
  std::array<double, kGrid + 7> vs{};
  int n = 0;
  for (int i = 0; i < kGrid; ++i) vs[n++] = -vm + 2 * vm * i / (kGrid - 1);
  auto add = [&](double v) {
    if (v > -vm && v < vm) vs[n++] = v;
  };
  add(0);
  add(b.v);
  if (j > 0) {
    add(inflection_speed(b.v, b.a, j));
    add(b.v + (2 * am * am - b.a * b.a) / (2 * j));
    add(b.v - (2 * am * am - b.a * b.a) / (2 * j));
    add(am * am / j);
    add(-am * am / j);
  }
  std::sort(vs.begin(), vs.begin() + n);  // ≤ 15 doubles, in place

  std::array<double, kGrid + 7> f{};
  std::array<PeakTrial, kGrid + 7> trial{};
  for (int i = 0; i < n; ++i) {
    const PeakTrial tr = trial[i] = otg_peak_trial(b, vs[i], lim);
    f[i] = tr.length_mm - dp;
    if (f[i] == 0) consider(vs[i], tr.length_mm, tr.duration_s, false);
  }
  // Each bracket holds one root of the length (smooth between the kinks): the Illinois form of
  // regula falsi, with a bisection step whenever it does not halve the bracket, until the length is
  // within 1e-13 of the distance (down to 1e-14 mm: a stop a few nanometres long lands within a
  // small part of one cycle's jerk, j·dt³ ≥ motion::kMinJerkStep_mm) or the bracket is down to
  // rounding (about ten trials a bracket instead of fifty for bisection alone). A floor of 1e-16 mm
  // was tried first: rounding never reaches it, so it took all 100 trials, 5.4 µs an update; a
  // floor of 1e-13 mm broke the jerk 1.0001× at one of 4 000 seeds of the tiny-jerk test (2079).
  const double tol_mm = std::max(1e-13 * std::abs(dp), 1e-14);
  for (int i = 0; i + 1 < n; ++i) {
    if (f[i] == 0 || f[i + 1] == 0 || (f[i] < 0) == (f[i + 1] < 0)) continue;
    double lo = vs[i], hi = vs[i + 1], flo = f[i], fhi = f[i + 1];
    const bool low_end = std::abs(flo) <= std::abs(fhi);  // the bracket's end nearer the root
    double best_v = low_end ? lo : hi;
    PeakTrial best_t = trial[low_end ? i : i + 1];
    double best_f = std::abs(best_t.length_mm - dp);
    int side = 0;  // the end kept in the last step (Illinois: halve its value when kept twice)
    double width = hi - lo;  // at the last check (every third step)
    for (int k = 0; k < 100 && hi - lo > 1e-15 * vm && best_f > tol_mm; ++k) {
      bool bisect = false;
      if (k % 3 == 2) {
        bisect = hi - lo > 0.5 * width;
        width = hi - lo;
      }
      double mid = bisect ? 0.5 * (lo + hi) : (lo * fhi - hi * flo) / (fhi - flo);
      if (!(mid > lo && mid < hi)) mid = 0.5 * (lo + hi);
      const PeakTrial tr = otg_peak_trial(b, mid, lim);
      const double fm = tr.length_mm - dp;
      if (std::abs(fm) < best_f) best_v = mid, best_t = tr, best_f = std::abs(fm);
      if (fm == 0) break;
      if ((fm < 0) == (flo < 0)) {
        lo = mid, flo = fm;
        if (side == -1) fhi *= 0.5;
        side = -1;
      } else {
        hi = mid, fhi = fm;
        if (side == 1) flo *= 0.5;
        side = 1;
      }
    }
    consider(best_v, best_t.length_mm, best_t.duration_s, false);
  }

  // Lay the winner out (there always is one: the length function is continuous between the ±v_max trials).
  const Ramp r1 = plan_ramp(b.v, b.a, best.vp, am, j);
  const Ramp r2 = plan_ramp(best.vp, 0, 0, am, j);
  push_ramp(path_, r1);
  path_.push(best.t_cruise, 0);
  push_ramp(path_, r2);
  path_.snap_end({target_mm, 0, 0, 0});
  mode_ = OtgMode::Position;
  target_mm_ = target_mm;
  target_v_ = 0;
  now_ = path_.at(0);
  return finished() ? OtgResult::Finished : OtgResult::Working;
}

// rt-safe
OtgResult Otg1::update_velocity(double v_mm_s, const OtgLimits& limits) {
  OtgLimits lim = limits;
  if (!normalise(lim) || !std::isfinite(v_mm_s) || std::abs(v_mm_s) > lim.v_max_mm_s || !finite(now_))
    return OtgResult::ErrorInvalidInput;
  const ProfileState b = begin(lim);
  push_ramp(path_, plan_ramp(b.v, b.a, v_mm_s, lim.a_max_mm_s2, lim.j_max_mm_s3));
  ProfileState e = path_.end();
  e.v = v_mm_s;
  path_.snap_end(e);
  mode_ = OtgMode::Velocity;
  target_v_ = v_mm_s;
  target_mm_ = e.s;
  now_ = path_.at(0);
  return finished() ? OtgResult::Finished : OtgResult::Working;
}

// rt-safe
ProfileState Otg1::at(double t) const {
  ProfileState x = path_.at(t);
  if (t > path_.duration()) x.s += x.v * (t - path_.duration());  // held speed (0 in position mode)
  return x;
}

// rt-safe
OtgResult Otg1::step(double dt_s) {
  if (!(dt_s >= 0) || !std::isfinite(dt_s)) return OtgResult::ErrorInvalidInput;
  t_ += dt_s;
  now_ = at(t_);
  return finished() ? OtgResult::Finished : OtgResult::Working;
}

}  // namespace softmc::motion
