// The planner's curves: kinks where a curve meets a corner, curve blends, and fillets of an arc
// between two lines (docs/planner.md, "Corner blends").
#include "motion/planner/planner.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "motion/geometry/bezier.hpp"
#include "motion/planner/planner_detail.hpp"

namespace softmc::motion {

using namespace planner_detail;

namespace {
// rt-safe. Largest curvature of a block (1/mm).
double max_curvature(const Block& b) {
  if (b.is_blend) return 1 / b.blend.radius;
  if (b.seg.kind == SegmentKind::Arc) return b.seg.arc_bounds().kappa;
  if (b.seg.kind == SegmentKind::Poly) return b.seg.max_curvature();
  return 0;
}
}  // namespace

// rt-safe. A corner that is not blended (one side an arc or a curve, or lines under G64 with P too
// small) is crossed at speed when that speed turns every axis within one cycle's share of its
// acceleration (and jerk): v·|t_out,i − t_in,i| ≤ share·a_i·dt, the discrete form of grbl's junction
// deviation. The setpoints stay on the programmed path (deviation 0). Both neighbours give up that
// share of their acceleration and jerk, so the kink's one-cycle impulse never adds up past a limit.
double Planner::kink_speed(const Block& a, const Block& b) const {
  const Vec dt_vec = b.tangent(0) - a.tangent(a.length);
  const double turn = core::norm(dt_vec);
  if (turn <= config_.tangent_rad || !(config_.kink_share > 0)) return 0;
  const double dt = limits_.period_s;
  double v = kInf;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    const double d = std::abs(dt_vec[i]);
    if (d < 1e-15 || !limits_.present(i)) continue;
    double room = limits_.axis[i].a_max_mm_s2 * dt;
    const bool jerk = limits_.axis[i].j_max_mm_s3 > 0 && !(std::isinf(a.j_mm_s3) && std::isinf(b.j_mm_s3));
    if (jerk) room = std::min(room, limits_.axis[i].j_max_mm_s3 * dt * dt);
    v = std::min(v, config_.kink_share * room / d);
  }
  const double keep = 1 - config_.kink_share;
  // The one-cycle impulse adds to the neighbours' centripetal acceleration too: within the cycle
  // that crosses the kink (speed ≤ v + that cycle's gain), v²κ may use at most `keep` of the axes.
  double a_min = kInf, a_path = 0;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (limits_.present(i)) a_min = std::min(a_min, limits_.axis[i].a_max_mm_s2);
  for (const Block* n : {&a, &b}) a_path = std::max({a_path, n->a_mm_s2, n->law.at(0)});
  for (const Block* n : {&a, &b}) {
    const double k = max_curvature(*n);
    if (k > 0 && std::isfinite(a_min)) v = std::min(v, std::sqrt(keep * a_min / k) - a_path * dt);
  }
  if (!(v >= config_.min_kink_speed_mm_s)) return 0;  // too slow to be worth the lost acceleration: stop
  return v;
}

// rt-safe. Applies kink_speed: both neighbours give up the kink's share.
void Planner::kink(Block& a, Block& b) const {
  const double v = kink_speed(a, b);
  if (!(v > 0)) return;
  const double keep = 1 - config_.kink_share;
  a.a_mm_s2 *= keep;
  a.law.scale *= keep;
  a.j_mm_s3 *= keep;
  b.a_mm_s2 *= keep;
  b.law.scale *= keep;
  b.j_mm_s3 *= keep;
  b.v2_kink = v * v;
}

// rt-safe. Corners and curvature steps where an arc meets a line or another arc (docs/planner.md,
// "Corner blends"):
//
//   a ────────────●╮ corner        a's end and b's start are cut back by the arc length d each and
//        p0 ╰───╮  │ b (an arc)    joined by the quintic of make_g2_blend, which continues each with
//               ╰──● p1            its tangent and curvature: no kink, no acceleration step.
//
// The corner's tangent lines from p0 and p1 give the control legs, the deflection between t0 and
// t1 the shape. d starts where the lines' quintic would put its midpoint P from the corner (or, on a
// tangent junction, at √(24·P/Δκ): a transition curve that long shifts the arc by about P), at most
// half of either piece and one radian of an arc, and shrinks until every sample of the quintic lies
// within 0.95·P of a or b. It is taken where its speed cap beats the junction's speed without it
// (a kink or exact stop; on a tangent curvature step, the step's speed by g2_blend_gain).
bool Planner::blend_curves(Block& a, Block& b, double tol, double da_half, Block& blend) const {
  const auto curve = [](const Block& k) {
    return !k.is_blend && (k.seg.kind == SegmentKind::Line || k.seg.kind == SegmentKind::Arc);
  };
  if (!curve(a) || !curve(b)) return false;
  const bool jerk = !(std::isinf(a.j_mm_s3) && std::isinf(b.j_mm_s3));
  const auto unit = [](const Vec& v) { return v * (1 / core::norm(v)); };  // a spiral's |tangent| ≠ 1
  const double turn = core::norm(unit(b.seg.tangent(0)) - unit(a.seg.tangent(a.length)));
  if (turn > 2 * std::cos(1e-3)) return false;  // a reversal: stop
  const bool tangent = turn <= config_.tangent_rad;
  double v_alt = 0, gain = 1;  // the junction's speed without a blend, and the margin a blend must beat it by
  const Vec dk = b.seg.curvature(0) - a.seg.curvature(a.length);
  if (tangent) {
    if (!jerk) return false;  // a curvature step costs trapezoids nothing
    v_alt = std::sqrt(curvature_step_v2(dk, limits_, config_.curvature_step_share));
    gain = config_.g2_blend_gain;
  } else {
    v_alt = kink_speed(a, b);
  }
  const double vq = target_speed(a.rapid && b.rapid, std::min(a.feed_mm_s, b.feed_mm_s));
  if (!(gain * v_alt < std::min({vq, a.v_cap_mm_s, b.v_cap_mm_s}))) return false;  // as fast without

  const double delta = 2 * std::asin(std::min(1.0, turn / 2));
  double alpha = 0, beta = 0;
  corner_blend_shape(delta, alpha, beta);
  const double dkn = core::norm(dk);
  const double d0 = tangent ? (dkn > 0 ? std::sqrt(24 * tol / dkn) : kInf) : tol / corner_blend_dev(turn, 1.0, alpha, beta);
  // Each side gives at most half of its length (the blend at its other end takes the other half)
  // and one radian of an arc.
  const auto side_max = [](const Block& k, double half) {
    return k.seg.kind == SegmentKind::Arc ? std::min(half, k.seg.radius) : half;
  };
  const double da_max = side_max(a, da_half), db_max = side_max(b, b.length / 2);
  double da = std::min(d0, da_max), db = std::min(d0, db_max);
  std::array<Vec, 6> ctrl{};
  // The quintic from a's point da before its end to b's point db after its start (in `out`) and its
  // largest distance from a and b (or the first found past `above`, where only that is asked).
  const auto fit = [&](double ea, double eb, std::array<Vec, 6>& out, double above = kInf) {
    const double sa = a.length - ea;
    const Vec p0 = a.seg.point(sa), p1 = b.seg.point(eb);
    const Vec t0 = unit(a.seg.tangent(sa)), t1 = unit(b.seg.tangent(eb));
    // Control legs: p0 + x0·t0 ≈ p1 − x1·t1 (least squares; the tangent lines meet in a plane).
    const Vec w = p1 - p0;
    const double c = core::dot(t0, t1), det = 1 - c * c, chord = core::norm(w);
    double x0 = chord / 2, x1 = chord / 2;
    if (det > 1e-6) {
      const double u0 = core::dot(t0, w), u1 = core::dot(t1, w);
      const double y0 = (u0 - c * u1) / det, y1 = (u1 - c * u0) / det;
      if (y0 > 0 && y1 > 0 && y0 < 2 * chord && y1 < 2 * chord) {
        x0 = y0;
        x1 = y1;
      }
    }
    double al = 0, be = 0;
    corner_blend_shape(2 * std::asin(std::min(1.0, core::norm(t1 - t0) / 2)), al, be);
    out = g2_blend_points(p0, t0, a.seg.curvature(sa), x0, p1, t1, b.seg.curvature(eb), x1, al, be);
    const BezierPower curve(out);
    return peak_distance([&](double u, double floor) {
      const Vec q = curve.at(u);
      const double e = a.seg.distance_to(q);
      return e <= floor ? e : std::min(e, b.seg.distance_to(q));
    }, above);
  };
  ++curves_tried_;  // the fit below is the costly part, taken or not
  bool fits = false;
  for (int it = 0; it < 16 && std::min(da, db) > min_length_mm_ && !fits; ++it) {
    const double dev = fit(da, db, ctrl);
    fits = dev <= 0.95 * tol;
    if (!fits) {
      const double f = std::clamp(0.95 * std::sqrt(tol / dev), 0.3, 0.9);
      da *= f;
      db *= f;
    }
  }
  // One side held to its half (a short arc between two corners) while the other had room: that side
  // grows while the quintic still fits; a longer transition bends less sharply.
  if (fits && (da >= da_max) != (db >= db_max)) {
    const bool grow_a = db >= db_max;
    for (int it = 0; it < 4; ++it) {
      double& e = grow_a ? da : db;
      const double e_max = grow_a ? da_max : db_max;
      const double next = std::min(1.5 * e, e_max);
      if (!(next > e * (1 + 1e-9))) break;
      std::array<Vec, 6> c2{};
      const double dev = grow_a ? fit(next, db, c2, 0.95 * tol) : fit(da, next, c2, 0.95 * tol);
      if (!(dev <= 0.95 * tol)) break;
      e = next;
      ctrl = c2;
    }
  }
  if (!fits) return false;
  const SegmentResult q = make_bezier(ctrl);
  if (!q.ok()) return false;
  const SegmentLimits ql = segment_limits(q.segment, limits_, config_.centripetal_share, vq, false);
  // Worth it only where it saves time. Each side of a corner crossed at v loses about T·(v_s − v)/2v_s
  // against going on at v_s (its speed: cap and feed; T the ramp's time from v_s to v with its
  // tangential acceleration at low speed, where the speed-dependent law of trapezoid blocks gives
  // most of the axes', and its jerk), and the blend's length len costs len/v − len/v_s; a stop is
  // v = 0. Slow blends of sharp corners, where a stop costs little more, are not taken (a margin of
  // a tenth there covers what the model leaves out: the quintic's own, lower acceleration).
  const auto side = [&](const Block& k, double v) {
    const double vs = std::min(vq, k.v_cap_mm_s), as = std::max(k.a_mm_s2, k.law.at(0)), js = k.j_mm_s3;
    const double dv = std::max(0.0, vs - v);
    const double t = !std::isfinite(js) ? dv / as : dv >= as * as / js ? dv / as + as / js : 2 * std::sqrt(dv / js);
    return t * dv / (2 * vs);
  };
  const double v_f = std::min({vq, a.v_cap_mm_s, b.v_cap_mm_s});
  const auto loss = [&](double v, double len) {
    return side(a, v) + side(b, v) + (v > 0 ? len / v - len / v_f : 0.0);
  };
  if (!(ql.v_max_mm_s > gain * v_alt) || !(loss(ql.v_max_mm_s, q.segment.length) < (tangent ? 1.0 : 0.9) * loss(v_alt, 0)) || !(ql.a_max_mm_s2 > 0) || !std::isfinite(ql.a_max_mm_s2)) return false;
  // The quintic may bulge past the corner (an arc's side): it must stay inside the travel too.
  if (!inside_travel(q.segment)) return false;
  blend = Block{};
  blend.seg = q.segment;
  blend.length = q.segment.length;
  set_limits(blend, ql, jerk ? ql.j_max_mm_s3 : kInf, vq, false);
  set_law(blend, [&] { return segment_law(blend.seg, limits_); });
  join_blend(blend, a, b);
  a.seg = trimmed(a.seg, 0, a.length - da);
  a.length = a.seg.length;
  b.seg = trimmed(b.seg, db, b.length);
  b.length = b.seg.length;
  // Where the quintic meets the arc their curvatures differ: a kink like any other.
  kink(a, blend);
  kink(blend, b);
  return true;
}

// rt-safe. An arc is held as a fillet candidate (jerk mode, docs/planner.md "Fillets") when it
// leaves the pending line at most kFilletMaxTurn off its direction, is no helix (a spiral's end off
// the circle is; fillet() checks the distance to it), turns at most kFilletMaxRad and is slower
// than its feed asks: the line after it may make it one quintic.
bool Planner::holds_fillet(const Block& b, double p_mm) const {
  if (!(config_.fillet_share > 0) || !(p_mm > 0) || !queue_.has_pending_) return false;
  const Block& a = queue_.pending_;
  if (a.is_blend || a.seg.kind != SegmentKind::Line || b.seg.kind != SegmentKind::Arc || a.rapid != b.rapid) return false;
  if (!std::isfinite(b.j_mm_s3) || !std::isfinite(a.j_mm_s3)) return false;  // trapezoids take the curvature step at speed
  if (is_helix(b.seg)) return false;  // its lines rarely share a plane
  if (!(std::abs(b.seg.sweep) <= kFilletMaxRad)) return false;
  if (core::norm(b.seg.tangent(0) - a.seg.dir) > kFilletMaxTurn) return false;
  return b.v_cap_mm_s < target_speed(b.rapid, b.feed_mm_s);
}

// rt-safe. The held arc h between the pending line a and the line c as one fillet:
//
//   a ─────────────●──╮ V        the quintic corner blend of the two lines' corner V
//            V−d·t0 ╰─╮ │ h       (make_corner_blend), d as large as keeps every point of it
//                    ╰─●│ c       within 0.95·P of a, h or c; it replaces the arc and both
//                       │         curvature steps, so nothing on the corner runs slower than
//                   V+d·t1        its own cap.
// Taken where that cap is at least fillet_share of the arc's own (the arc is entered through
// transitions slower than it). On success a and the quintic are committed and c is pending.
bool Planner::fillet(Block& c, double p_mm) {
  Block& a = queue_.pending_;
  const Block& h = queue_.held_;
  if (c.seg.kind != SegmentKind::Line || c.rapid != h.rapid || !std::isfinite(c.j_mm_s3)) return false;
  const double tol = std::min(p_mm, queue_.held_p_mm_) - std::max(a.merge_q_mm, c.merge_q_mm);
  if (!(tol > 0)) return false;
  const Vec t0 = a.seg.dir, t1 = c.seg.dir;
  if (core::norm(t1 - h.seg.tangent(h.length)) > kFilletMaxTurn) return false;
  const double chord = core::norm(t1 - t0);
  const double delta = 2 * std::asin(std::min(1.0, chord / 2));
  if (!(delta > config_.tangent_rad) || delta > kFilletMaxRad) return false;
  // V: a's end + x·t0 = c's start − y·t1 (the two lines meet: the arc lies in their plane).
  const Vec w = c.seg.start - a.seg.end;
  const double cc = core::dot(t0, t1), det = 1 - cc * cc;
  if (!(det > 1e-12)) return false;
  const double u0 = core::dot(t0, w), u1 = core::dot(t1, w);
  const double x = (u0 - cc * u1) / det, y = (u1 - cc * u0) / det;
  const Vec v = a.seg.end + t0 * x;
  // V lies ahead of a's end and before c's start (a corner the arc rounds, not one it overshoots),
  // and the arc turns the way the corner does: else the quintic would leave the arc's far side.
  if (!(x >= 0) || !(y >= 0) || core::distance(v, c.seg.start - t1 * y) > 1e-6) return false;
  const Vec turn_dir = t1 - t0;  // the corner bends towards it; so must the arc's curvature
  if (!(core::dot(h.seg.curvature(h.length / 2), turn_dir) > 0)) return false;
  double alpha = 0, beta = 0;
  corner_blend_shape(delta, alpha, beta);
  const double coef = corner_blend_dev(chord, 1.0, alpha, beta);
  // The quintic starts on a and ends on c (d ≥ x, d ≥ y), each line giving at most half of itself
  // as programmed; d from where its midpoint meets the arc's to where it lies 0.95·P past it.
  const double room = std::min(x + std::min(queue_.pending_full_length_ / 2, a.length), y + c.length / 2);
  const double mid = core::distance(h.seg.point(h.length / 2), v);
  const double d_lo = std::max({x, y, mid / coef}), d_hi = std::min(room, (mid + 0.95 * tol) / coef);
  if (!(d_lo <= d_hi)) return false;
  const auto off = [&](double d) {
    const std::array<Vec, 6> ctrl{v - t0 * d, v - t0 * (alpha * d), v - t0 * (beta * d),
                                  v + t1 * (beta * d), v + t1 * (alpha * d), v + t1 * d};
    const BezierPower curve(ctrl);
    return peak_distance([&](double u, double floor) {
      const Vec q = curve.at(u);
      const double e = std::min(a.seg.distance_to(q), c.seg.distance_to(q));  // the lines first: cheaper
      return e <= floor ? e : std::min(e, h.seg.distance_to(q));
    }, 0.95 * tol);  // only compared with it below
  };
  ++curves_tried_;  // the search below is the costly part, taken or not
  double d = d_hi;
  if (!(off(d) <= 0.95 * tol)) {
    if (!(off(d_lo) <= 0.95 * tol)) return false;
    double lo = d_lo, hi = d_hi;  // the largest d that fits, to 1/256 of the span
    for (int it = 0; it < 8; ++it) {
      const double m = 0.5 * (lo + hi);
      (off(m) <= 0.95 * tol ? lo : hi) = m;
    }
    d = lo;
  }
  const SegmentResult q = make_corner_blend(v, t0, t1, d, alpha, beta);
  if (!q.ok()) return false;
  // And the other way: the arc (its ends and 15 points between) lies within P of the quintic, so the
  // program is as near the path as the path is to the program.
  for (int i = 0; i <= 16; ++i)
    if (!(q.segment.distance_to(h.seg.point(h.length * i / 16), tol) <= tol)) return false;
  const double vq = target_speed(h.rapid, std::min({a.feed_mm_s, h.feed_mm_s, c.feed_mm_s}));
  const SegmentLimits ql = segment_limits(q.segment, limits_, config_.centripetal_share, vq, false);
  if (!(ql.v_max_mm_s >= config_.fillet_share * std::min(h.v_cap_mm_s, vq)) || !(ql.a_max_mm_s2 > 0) ||
      !std::isfinite(ql.a_max_mm_s2))
    return false;
  if (!inside_travel(q.segment)) return false;  // within P of the program, it may still pass a soft limit it touches
  Block blend;
  blend.seg = q.segment;
  blend.length = q.segment.length;
  set_limits(blend, ql, ql.j_max_mm_s3, vq, false);
  set_law(blend, [&] { return segment_law(blend.seg, limits_); });
  join_blend(blend, a, c);
  blend.feed_mm_s = std::min(blend.feed_mm_s, h.feed_mm_s);  // never faster than the arc it replaces
  const double full_c = c.length;
  a.seg = make_line(a.seg.start, v - t0 * d);
  a.length = a.seg.length;
  c.seg = make_line(v + t1 * d, c.seg.end);
  c.length = c.seg.length;
  queue_.has_held_ = false;
  if (a.length > min_length_mm_) commit(a);
  commit(blend);
  queue_.pending_ = c;
  queue_.pending_full_length_ = full_c;
  return true;
}
}  // namespace softmc::motion
