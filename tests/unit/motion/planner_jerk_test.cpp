// PlannerJerk (issue 4): S-curves across blocks, override/hold, profile per move, jerk on curves, random and soft paths.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "motion/profile/scurve.hpp"
#include "planner_jerk_support.hpp"

using namespace softmc;
using namespace softmc::motion;
using namespace softmc::motion::testing;

// A single line: the online follower is as fast as the closed-form S-curve for the whole line.
TEST(PlannerJerk, StraightLineMatchesTheClosedFormScurve) {
  const auto lim = jerk_limits(100, 1000, 20000);
  const auto res = run_path(lim, {line_req(xyz(0, 0), xyz(100, 0), 100, 0)}, 16);
  expect_within(res, 0, "line");
  EXPECT_GT(res.fig.j_ratio, 0.9);  // the jerk limit is used, not avoided
  const auto sc = plan_scurve(100, 0, 0, 100, 1000, 20000);
  ASSERT_TRUE(sc.has_value());
  const double t_s = static_cast<double>(res.cycles) * lim.period_s;
  EXPECT_LE(t_s, sc->duration() * 1.01 + 0.002) << t_s << " vs " << sc->duration();
  EXPECT_GE(t_s, sc->duration() - 0.002);
  EXPECT_EQ(res.end, xyz(100, 0));
}

// Many tiny colinear blocks: the S-curve spans block ends (acceleration is not forced to 0 at each).
TEST(PlannerJerk, TinyBlocksRampAcrossBlockEnds) {
  const auto lim = jerk_limits(200, 1000, 20000);
  std::vector<PathRequest> reqs;
  for (int k = 0; k < 4000; ++k)
    reqs.push_back(line_req(xyz(k * 0.01, 0), xyz((k + 1) * 0.01, 0), 100, static_cast<std::uint32_t>(k)));
  const auto res = run_path(lim, reqs, 4096);
  expect_within(res, 0, "tiny");
  const auto sc = plan_scurve(40, 0, 0, 100, 1000, 20000);
  const double t_s = static_cast<double>(res.cycles) * lim.period_s;
  EXPECT_LE(t_s, sc->duration() * 1.02 + 0.002) << t_s << " vs " << sc->duration();
  EXPECT_NEAR(res.max_path_v, 100, 1e-6);
}

TEST(PlannerJerk, CornersAndArcsKeepJerkAndTolerance) {
  const auto lim = jerk_limits(100, 1000, 20000);
  std::vector<PathRequest> reqs{line_req(xyz(0, 0), xyz(30, 0), 80, 0, 0.05), line_req(xyz(30, 0), xyz(30, 30), 80, 1, 0.05)};
  reqs.push_back(arc_req(make_arc(xyz(30, 30), xyz(10, 30), 0, 1, 20, 30, 1), 80, 2));
  reqs.push_back(line_req(xyz(10, 30), xyz(10, 0), 80, 3, 0.05));
  const auto res = run_path(lim, reqs, 64);
  expect_within(res, 0.05, "corners");
  EXPECT_EQ(res.end, xyz(10, 0));
}

// Seeded random paths (lines, arcs, helices, reversals, tiny pieces) with per-axis jerk limits:
// every setpoint within speed, acceleration and jerk of every axis, and within P of the program;
// the path speed within each block's own cap, acceleration and jerk (expect_random_jerk_paths).
// (Seed 2 once entered a 0.0045 mm line between two tiny blends faster than it could brake, 5.4x
// jerk; seed 2 also crossed a curvature jump at full path jerk, 1.27x: both fixed, see
// docs/planner.md "Jerk".)
TEST(PlannerJerk, RandomPathsKeepSpeedAccelerationJerkAndTolerance) {
  expect_random_jerk_paths(300, {0.0, 0.01, 0.1, 1.0}, [](std::mt19937_64& rng, std::uniform_real_distribution<double>& u, double tol) {
    const int n = 3 + static_cast<int>(rng() % 25);
    return chain(n, tol, [&](int k, const core::Vec& at, const std::vector<PathRequest>& reqs, PathRequest& r) {
      r.feed_mm_s = 1 + 300 * u(rng);
      r.rapid = rng() % 10 == 0;
      core::Vec to = at;
      switch (rng() % 5) {
        case 0:
          for (int i = 0; i < 3; ++i) to[i] += (u(rng) - 0.5) * 0.05;
          r.geom = make_line(at, to);
          break;
        case 1: {
          const double rad = 0.5 + 10 * u(rng), ang = 2 * std::numbers::pi * u(rng);
          const double c0 = at[0] - rad * std::cos(ang), c1 = at[1] - rad * std::sin(ang);
          const double a2 = ang + (u(rng) - 0.5) * 5;
          to[0] = c0 + rad * std::cos(a2);
          to[1] = c1 + rad * std::sin(a2);
          to[2] += (u(rng) - 0.5);
          r.geom = make_arc(at, to, 0, 1, c0, c1, rng() % 2 ? 1 : -1);
          break;
        }
        case 2:
          if (k > 0) to = reqs.back().geom.start;
          r.geom = make_line(at, to);
          break;
        default:
          for (int i = 0; i < 3; ++i) to[i] += (u(rng) - 0.5) * 40;
          r.geom = make_line(at, to);
          break;
      }
    });
  });
}

// Feed hold and override act in the cycle after the signal, with the jerk limit kept.
TEST(PlannerJerk, OverrideAndHoldActWithinOneCycleWithTheJerkKept) {
  const auto lim = jerk_limits(200, 1000, 20000);
  double v_before = 0, v_after = 0, a_after = 0;
  std::uint64_t held_at = 0;
  const auto hook = [&](std::uint64_t c, Interpolator& in) {
    if (c == 400) {
      v_before = in.setpoint().path_v;
      in.set_feed_override(0.5);
    }
    if (c == 401) {
      v_after = in.setpoint().path_v;
      a_after = in.setpoint().acc[0];
    }
    if (c == 800) in.set_feed_hold(true);
    if (c == 1200 && in.setpoint().path_v == 0) held_at = c;
    if (c == 1300) in.set_feed_hold(false);
  };
  const auto res = run_path(lim, {line_req(xyz(0, 0), xyz(150, 0), 100, 0)}, 16, {}, hook);
  expect_within(res, 0, "override/hold");
  EXPECT_NEAR(v_before, 100, 1e-6);
  EXPECT_LT(v_after, v_before);  // already slowing in the first cycle after the signal
  EXPECT_LT(a_after, 0);
  EXPECT_EQ(held_at, 1200u);
  EXPECT_EQ(res.end, xyz(150, 0));
}

TEST(PlannerJerk, ProfileSelectablePerMove) {
  const auto lim = jerk_limits(100, 1000, 20000);
  auto trap = line_req(xyz(0, 0), xyz(50, 0), 100, 0);
  trap.profile = ProfileKind::Trapezoid;
  const auto t = run_path(lim, {trap}, 16);
  const auto s = run_path(lim, {line_req(xyz(0, 0), xyz(50, 0), 100, 0)}, 16);
  EXPECT_GT(t.fig.j_ratio, 10);          // the trapezoid's acceleration jumps
  EXPECT_LE(s.fig.j_ratio, 1 + kRatioNoise);  // the S-curve keeps the limit...
  EXPECT_GT(s.cycles, t.cycles);          // ...and pays for it in time
  EXPECT_EQ(t.end, xyz(50, 0));
}

// cutting_table.md T-2 "tangent transitions crossed without stopping", on the part of
// examples/thesis/rounded_rectangle.ngc (its lines and quarter arcs, F480 = 8 mm/s), with the
// default table's limits, with and without jerk limits: the speed never dips between start and end.
TEST(PlannerJerk, T2_RoundedRectangleCrossesTangentJunctionsWithoutSlowing) {
  for (const double jerk : {0.0, 50000.0}) {
    MachineLimits lim = xyz_limits(250, 2000);
    for (int i = 0; i < 3; ++i) lim.axis[i].j_max_mm_s3 = jerk;
    std::vector<PathRequest> reqs;
    const auto line = [&](double x0, double y0, double x1, double y1) {
      reqs.push_back(line_req(xyz(x0, y0), xyz(x1, y1), 8, static_cast<std::uint32_t>(reqs.size())));
    };
    const auto arc = [&](double x0, double y0, double x1, double y1, double cx, double cy) {
      PathRequest r;
      r.geom = make_arc(xyz(x0, y0), xyz(x1, y1), 0, 1, cx, cy, 1);
      r.feed_mm_s = 8;
      r.tag = static_cast<std::uint32_t>(reqs.size());
      reqs.push_back(r);
    };
    line(20, 10, 40, 10);
    arc(40, 10, 50, 20, 40, 20);
    line(50, 20, 50, 40);
    arc(50, 40, 40, 50, 40, 40);
    line(40, 50, 20, 50);
    arc(20, 50, 10, 40, 20, 40);
    line(10, 40, 10, 20);
    arc(10, 20, 20, 10, 20, 20);
    double min_v = 1e9;
    bool cruising = false;
    std::uint64_t first_cruise = 0, last_cruise = 0;
    const auto hook = [&](std::uint64_t c, Interpolator& in) {
      const double v = in.setpoint().path_v;
      if (v >= 8 - 1e-9) {
        if (!cruising) first_cruise = c;
        cruising = true;
        last_cruise = c;
      }
      if (cruising && in.setpoint().tag >= 1 && in.setpoint().tag <= 6) min_v = std::min(min_v, v);
    };
    const auto res = run_path(lim, reqs, 256, {}, hook);
    expect_within(res, 0, jerk > 0 ? "jerk" : "trapezoid");
    EXPECT_NEAR(min_v, 8, 1e-9) << "jerk " << jerk;  // the whole perimeter between ramps at 8 mm/s
    const double perimeter_mm = 80 + 20 * std::numbers::pi;
    EXPECT_GT(static_cast<double>(last_cruise - first_cruise) * lim.period_s, perimeter_mm / 8 - 0.2);
    EXPECT_EQ(res.end, xyz(20, 10));
  }
}

// A centre-format arc whose end point is off the circle through its start (G2/G3 allow that, within
// LinuxCNC's radius allowance, docs/gcode.md) must still end exactly on its end point: the geometry
// is continuous there, so the setpoints never jump. Before, the arc kept the start radius and only
// its last point was the end point: on plasma.ngc (outline arcs with end radii 5.4e-4 mm off) every
// exact stop at their ends showed a one-sample jump of the radius difference, ~50× the jerk limit
// (0.025 mm, near the allowance on small arcs, breaks the acceleration limit too, with or without
// jerk limits). Cases: the plasma outline's G3 (R 50, end 5.4e-4 mm outside) into its sharp corner;
// a small arc (R 1.5 → 1.475) into a corner; a spiral crossed at speed (below).
TEST(PlannerJerk, ArcWithItsEndOffTheStartCircleReachesItsEndWithoutAJump) {
  {
    const auto lim = jerk_limits(100, 1000, 10000);
    std::vector<PathRequest> reqs{line_req(xyz(114.84, 63.996), xyz(109.84, 63.996), 100, 0, 0.05)};
    reqs.push_back(arc_req(make_arc(xyz(109.84, 63.996), xyz(105.161, 81.46), 0, 1, 60, 60, 1), 100, 1));
    reqs.push_back(line_req(xyz(105.161, 81.46), xyz(100, 90), 100, 2, 0.05));
    const auto res = run_path(lim, reqs, 64);
    expect_within(res, 0.05, "R50 arc into a corner");
    EXPECT_EQ(res.end, xyz(100, 90));
  }
  for (const double jerk : {0.0, 10000.0}) {  // jerk 0: trapezoids
    const auto lim = jerk_limits(100, 1000, jerk);
    // Centre (10, 1.5): starts on R 1.5, ends at R 1.475 after a quarter turn, then a line on at
    // about 1° to the arc's end tangent (too sharp for a kink speed: blended within P).
    std::vector<PathRequest> reqs{line_req(xyz(0, 0), xyz(10, 0), 50, 0, 0.05)};
    reqs.push_back(arc_req(make_arc(xyz(10, 0), xyz(11.475, 1.5), 0, 1, 10, 1.5, 1), 50, 1));
    reqs.push_back(line_req(xyz(11.475, 1.5), xyz(11.475, 10), 50, 2, 0.05));
    const auto res = run_path(lim, reqs, 64);
    const std::string what = "R1.5 arc into a corner, jerk " + std::to_string(jerk);
    expect_within(res, 0.05, what.c_str());
    EXPECT_EQ(res.end, xyz(11.475, 10)) << what;
  }
  // Crossed at speed, and planned with the spiral's own shares: R 50 → 50.05 (the allowance),
  // cruising at the X axis's speed limit where the tangent is +X (the spiral's in-plane tangent is
  // longer than r0·sweep/length by about Δr/2r: 5e-4 over the limit if planned as the start circle),
  // into a line along its end tangent.
  for (const double jerk : {0.0, 10000.0}) {
    const auto lim = jerk_limits(100, 1000, jerk);
    const double q = std::numbers::pi / 4;
    const core::Vec a0 = xyz(-50 * std::cos(q), 50 - 50 * std::sin(q));
    const core::Vec a1 = xyz(50.05 * std::cos(q), 50 - 50.05 * std::sin(q));
    PathRequest arc;
    arc.geom = make_arc(a0, a1, 0, 1, 0, 50, 1);
    arc.feed_mm_s = 200;
    arc.tag = 1;
    const core::Vec t0 = arc.geom.tangent(0), t1 = arc.geom.tangent(arc.geom.length);
    std::vector<PathRequest> reqs{line_req(a0 - t0 * 60.0, a0, 200, 0)};
    reqs.push_back(arc);
    reqs.push_back(line_req(a1, a1 + t1 * 60.0, 200, 2));
    const auto res = run_path(lim, reqs, 64);
    const std::string what = "R50 spiral at the speed limit, jerk " + std::to_string(jerk);
    expect_within(res, 0.05, what.c_str());  // jerk: its curvature steps are blended within P
    EXPECT_GT(res.fig.v_ratio, 0.999) << what;  // the limit is reached, not avoided
  }
}

// On a circle in its plane each axis sees the path's tangential jerk (less v³κ²) and 3·v·a_t·κ one
// phase apart, so its jerk is their Euclidean sum, not the plain one: the arc's shares of j_max
// (⅖ tangential, ⅕ v³κ², ⅖ 3·v·a_t·κ) are scaled by 1/√(0.6² + 0.4²) = 1.387 (segment_limits.cpp
// curve_jerk). An R5 circle at 10 000 mm/s³ runs at 41.1 mm/s instead of 36.8, every axis within its
// jerk in the trace; a helix (the tangent leaves the plane) and a spiral keep the plain sum.
TEST(PlannerJerk, PlaneCirclesUseTheWholeJerkBudget) {
  const double j = 10'000, r = 5, kappa = 1 / r;
  const auto lim = jerk_limits(100, 1000, j);
  const double scale = 1 / std::sqrt(0.6 * 0.6 + 0.4 * 0.4);
  const Segment half = make_arc(xyz(r, 0), xyz(-r, 0), 0, 1, 0, 0, 1);
  const SegmentLimits sl = segment_limits(half, lim);
  const double cap = std::cbrt(scale * 0.2 * j / (kappa * kappa));
  EXPECT_NEAR(sl.v_max_mm_s, cap, 1e-9);
  EXPECT_NEAR(sl.j_max_mm_s3, scale * 0.4 * j, 1e-9);
  EXPECT_NEAR(sl.a_max_mm_s2, scale * 0.4 * j / (3 * cap * kappa), 1e-9);
  EXPECT_GT(sl.v_max_mm_s, 1.1 * std::cbrt(0.2 * j / (kappa * kappa)));  // 41.1 against 36.8 mm/s

  const Segment helix = make_arc(xyz(r, 0, 0), xyz(-r, 0, 2), 0, 1, 0, 0, 1);
  const double kh = helix.arc_bounds().kappa, ks = helix.arc_bounds().k_speed;  // ks = kh²/inplane
  EXPECT_NEAR(ks, kh * kh / helix.arc_bounds().inplane, 1e-12);
  EXPECT_NEAR(segment_limits(helix, lim).v_max_mm_s, std::cbrt(0.2 * j / ks), 1e-9);

  // Four turns of half circles: the path speed reaches the new cap, every axis within its limits.
  std::vector<PathRequest> reqs;
  for (std::uint32_t k = 0; k < 8; ++k) {
    const double sgn = k % 2 ? -1 : 1;
    reqs.push_back(arc_req(make_arc(xyz(sgn * r, 0), xyz(-sgn * r, 0), 0, 1, 0, 0, 1), 100, k));
  }
  const auto res = run_path(lim, reqs, 64);
  expect_within(res, 0.05, "four turns of an R5 circle");
  EXPECT_GT(res.max_path_v, 0.99 * cap);
  EXPECT_LE(res.max_path_v, cap * (1 + 1e-9));
}

// A steep helix: its in-plane axes run a circle of radius R at the path speed times inplane = R·ω
// (ω the turn per mm of path), so their speed jerk is v³·R·ω³ = v³·κ²/inplane, not v³·κ² (κ = R·ω²,
// the helix's curvature). The cap must take the larger term, or a helix of pitch well above its
// radius overruns the in-plane axes' jerk by 1/inplane times the term's share (a 30 mm half turn of
// R1 gave about twice j_max). The linear axis sees only the tangential jerk times its share.
TEST(PlannerJerk, SteepHelicesKeepTheInPlaneAxesJerk) {
  const double j = 10'000, r = 1;
  auto lim = jerk_limits(400, 1000, j);
  lim.axis[2].a_max_mm_s2 = 5000;  // a stiff Z: the path reaches the cap within the first half turn
  lim.axis[2].j_max_mm_s3 = 100'000;
  std::vector<PathRequest> reqs;
  double z = 0;
  for (std::uint32_t k = 0; k < 6; ++k) {
    const double sgn = k % 2 ? -1 : 1, rise = k < 3 ? 30 : 5;
    reqs.push_back(arc_req(make_arc(xyz(sgn * r, 0, z), xyz(-sgn * r, 0, z + rise), 0, 1, 0, 0, 1), 400, k));
    z += rise;
  }
  const Segment steep = reqs[0].geom;
  const auto ab = steep.arc_bounds();
  ASSERT_LT(ab.inplane, 0.11);
  const SegmentLimits sl = segment_limits(steep, lim);
  const double w = std::numbers::pi / steep.length;  // the turn per mm
  EXPECT_LE(sl.v_max_mm_s * sl.v_max_mm_s * sl.v_max_mm_s * r * w * w * w, 0.2 * j * (1 + 1e-12));
  const auto res = run_path(lim, reqs, 64);
  expect_within(res, 0.05, "steep helix");
  EXPECT_GT(res.fig.j_ratio, 0.5);  // the jerk limit is used, not avoided
}

// A blend's speed term v³κ² runs along its tangent (j = (j_t − v³κ²)·T + 3·v·a_t·κ·N on a circle),
// so each axis caps it by its own tangent share: X, carrying the tangent of a shallow corner with a
// soft jerk (2 000 mm/s³ against Y's 100 000), keeps v³κ²·|T_x| within its fifth of j_x. Capped by
// its normal share instead (until 2026-12-03), X's share was 1/sin(sweep) times too large: 10×.
TEST(PlannerJerk, BlendsCapTheirSpeedTermByTheTangentShare) {
  auto lim = jerk_limits(200, 1000, 2000);
  lim.axis[1].j_max_mm_s3 = 100'000;
  lim.axis[1].a_max_mm_s2 = 5000;
  for (const double sweep : {0.02, 0.1, 0.5}) {
    for (const double r : {0.2, 1.0, 5.0}) {
      const BlendArc b = make_blend_arc(xyz(0, 0), xyz(1, 0), xyz(std::cos(sweep), std::sin(sweep)), r, sweep);
      const SegmentLimits sl = blend_limits(b, lim);
      const double v = sl.v_max_mm_s, k = 1 / r;
      EXPECT_LE(v * v * v * k * k, 0.2 * 2000 * (1 + 1e-12)) << sweep << " " << r;  // |T_x| ≥ cos(sweep) ≈ 1
      EXPECT_GE(v * v * v * k * k, 0.2 * 2000 * (1 - 1e-9) * std::cos(sweep) * std::cos(sweep))
          << sweep << " " << r;  // and is the binding cap
    }
  }
}

// A curvature step at a plane circle's end (jerk_left_by_step): the circle's shares are scaled to
// the Euclidean bound, so the step's share comes off its tangential jerk by the crossing's own
// speed and curvature, axis by axis. At a slow crossing (the speed a step of ¼ allows) nothing need
// come off; at the circle's cap speed with its full acceleration the factor is lower and the worst
// axis jerk, √((f·j + v³κ²)² + (3·v·a·κ)²) + step_j[i], is exactly j_i; plain shares keep 1 − used.
TEST(PlannerJerk, CurvatureStepsNextToPlaneCirclesKeepTheEuclideanBound) {
  const double j = 10'000, r = 5;
  auto lim = jerk_limits(100, 1000, j);
  Block circle;
  circle.seg = make_arc(xyz(r, 0), xyz(-r, 0), 0, 1, 0, 0, 1);
  circle.length = circle.seg.length;
  const SegmentLimits sl = segment_limits(circle.seg, lim);
  ASSERT_GT(sl.jerk_scale, 1.38);
  circle.a_mm_s2 = sl.a_max_mm_s2;
  circle.j_mm_s3 = sl.j_max_mm_s3;
  circle.v_cap_mm_s = sl.v_max_mm_s;
  const double k = 1 / r;
  const auto worst = [&](double f, double v, const core::Vec& step) {
    double w = 0;
    for (std::size_t i = 0; i < 2; ++i)
      w = std::max(w, std::hypot(f * circle.j_mm_s3 + v * v * v * k * k, 3 * v * circle.a_mm_s2 * k) + step[i]);
    return w;
  };
  // The step a line into this circle takes at its junction speed (curvature_step_share ¼, 1 ms), on
  // the y axis.
  const double used = 0.25, v_step = std::sqrt(used * j * lim.period_s / k);
  const core::Vec step = xyz(0, used * j);
  const double f_slow = jerk_left_by_step(step, circle, 0, v_step, lim);
  EXPECT_GE(f_slow, 1 - used);
  const double v_slow = std::min(v_step + 3 * circle.a_mm_s2 * lim.period_s, circle.v_cap_mm_s);
  EXPECT_LE(worst(f_slow, v_slow, step), j * (1 + 1e-12));
  // At the cap speed (no real step allows it): the bound binds, on the axis that takes the step.
  const double v = sl.v_max_mm_s;
  const double f = jerk_left_by_step(step, circle, 0, v, lim);
  EXPECT_LT(f, 0.9 * (1 - used));
  EXPECT_GT(f, 0.25);
  EXPECT_NEAR(worst(f, v, step), j, 1e-9 * j);
  // Plain shares (a helix, a line): 1 − used.
  Block line;
  line.seg = make_line(xyz(0, 0), xyz(10, 0));
  line.j_mm_s3 = j;
  EXPECT_DOUBLE_EQ(jerk_left_by_step(step, line, 0, v, lim), 1 - used);
}

// An arc that will never be asked to run as fast as its curvature allows (its feed at the highest
// override, v_target) keeps of the centripetal share and of the v³κ² jerk share only what that speed
// needs and gives the rest to its tangential acceleration and jerk, as Poly pieces do: an R20 arc at
// F1200 (40 mm/s at 200 %) on 100 mm/s, 1 000 mm/s², 10 000 mm/s³ axes may accelerate at 997 mm/s²
// instead of 378 with a tangential jerk of 6 970 mm/s³ instead of 5 550, within every limit.
TEST(PlannerJerk, AnArcSlowerThanItsCurvatureAllowsGivesTheRestToItsTangentialAcceleration) {
  const auto lim = jerk_limits(100, 1000, 10'000);
  const Segment arc = make_arc(xyz(20, 0), xyz(-20, 0), 0, 1, 0, 0, 1);  // R20 half circle
  const SegmentLimits fast = segment_limits(arc, lim, 0.8), slow = segment_limits(arc, lim, 0.8, 40);
  EXPECT_GE(slow.v_max_mm_s, 40);  // never below what it is asked for
  EXPECT_LT(slow.v_max_mm_s, 45);
  EXPECT_GT(fast.v_max_mm_s, 95);
  EXPECT_GT(slow.a_max_mm_s2, 2.5 * fast.a_max_mm_s2);
  EXPECT_GT(slow.j_max_mm_s3, 1.2 * fast.j_max_mm_s3);
  // From rest at its start (an exact stop after a line along Y) to its feed.
  PathRequest r = arc_req(arc, 20, 1);
  r.tolerance_mm = 0;
  const std::vector<PathRequest> reqs{line_req(xyz(20, -10), xyz(20, 0), 20, 0, 0), r};
  std::vector<core::Vec> trace;
  const auto res = run_path(lim, reqs, 64, {}, {}, 20'000'000, {}, &trace);
  ASSERT_TRUE(res.finished);
  EXPECT_LE(res.fig.v_ratio, 1 + 1e-9) << res.fig.describe();
  EXPECT_LE(res.fig.a_ratio, 1 + 1e-6) << res.fig.describe();
  EXPECT_LE(res.fig.j_ratio, 1 + 1e-3) << res.fig.describe();
  EXPECT_LE(res.block_v_ratio, 1 + 1e-9);
  EXPECT_LE(res.block_a_ratio, 1 + 1e-6);
  // From rest to 20 mm/s the ramp is all jerk phases: the path jerk on the arc (y > 0) is the larger.
  double j_path = 0;
  const auto v_at = [&](std::size_t k) { return core::norm(trace[k] - trace[k - 1]) / lim.period_s; };
  for (std::size_t k = 4; k < trace.size(); ++k) {
    if (trace[k - 4][1] <= 1e-9) continue;
    const double a1 = (v_at(k) - v_at(k - 1)) / lim.period_s, a0 = (v_at(k - 1) - v_at(k - 2)) / lim.period_s;
    j_path = std::max(j_path, std::abs(a1 - a0) / lim.period_s);
  }
  EXPECT_GT(j_path, 1.15 * fast.j_max_mm_s3) << j_path << " mm/s³ against " << fast.j_max_mm_s3;
}

// A G-code arc whose end is off its circle by the program's rounding (a slight spiral, Segment::
// dradius) keeps the Euclidean bound of its jerk shares, less the spiral's own term v³·|κ'|:
// plane_arc_spiral bounds |κ'|/κ² at twice |dradius|/length (measured here on the segment's own
// curvature), and the scale drops from 1.387 only by that. Helices and arcs opening by more than 1 %
// keep the plain sum.
TEST(PlannerJerk, GcodeArcsOffTheirCircleKeepTheEuclideanJerkBound) {
  const auto lim = jerk_limits(100, 1000, 10'000);
  const double r = 5;
  const Segment circle = make_arc(xyz(r, 0), xyz(0, r), 0, 1, 0, 0, 1);
  EXPECT_EQ(plane_arc_spiral(circle), 0.0);
  for (const double off : {5e-5, -5e-5, 1e-3, -0.04}) {
    const Segment g = make_arc(xyz(r, 0), xyz(0, r + off), 0, 1, 0, 0, 1);
    const double rho = plane_arc_spiral(g);
    ASSERT_TRUE(std::isfinite(rho)) << off;
    double worst = 0;  // |κ'|/κ² from the curvature at 400 points
    const double ds = g.length / 400;
    for (int i = 1; i < 400; ++i) {
      const double s = i * ds;
      const double k0 = core::norm(g.curvature(s - 1e-4)), k1 = core::norm(g.curvature(s + 1e-4)), k = core::norm(g.curvature(s));
      worst = std::max(worst, std::abs(k1 - k0) / 2e-4 / (k * k));
    }
    EXPECT_GT(worst, 0.3 * rho) << off;  // the bound is tight to its factor 2
    EXPECT_LE(worst, rho) << off;
    const SegmentLimits sl = segment_limits(g, lim);
    EXPECT_LT(sl.jerk_scale, 1.3868) << off;
    EXPECT_GT(sl.jerk_scale, std::abs(off) < 1e-3 ? 1.3865 : 1.3) << off;
  }
  EXPECT_FALSE(std::isfinite(plane_arc_spiral(make_arc(xyz(r, 0), xyz(0, 1.02 * r), 0, 1, 0, 0, 1))));
  EXPECT_FALSE(std::isfinite(plane_arc_spiral(make_arc(xyz(r, 0), xyz(0, r, 1), 0, 1, 0, 0, 1))));
  EXPECT_EQ(segment_limits(make_arc(xyz(r, 0), xyz(0, r, 1), 0, 1, 0, 0, 1), lim).jerk_scale, 1.0);
}

// tangent_chain's draws in a coordinate plane (axes p0, p1: xy, xz or yz), full circles now and then.
static std::vector<PathRequest> plane_chain(std::mt19937_64& rng, std::uniform_real_distribution<double>& u, double tol,
                                            std::uint8_t p0, std::uint8_t p1) {
  std::vector<PathRequest> reqs;
  core::Vec at{};
  double h = 2 * std::numbers::pi * u(rng);
  const auto in_plane = [&](double x, double y) {
    core::Vec v{};
    v[p0] = x;
    v[p1] = y;
    return v;
  };
  const int n = 3 + static_cast<int>(rng() % 20);
  for (int k = 0; k < n; ++k) {
    PathRequest r;
    r.feed_mm_s = 5 + 200 * u(rng);
    r.tag = static_cast<std::uint32_t>(k);
    r.tolerance_mm = tol;
    if (rng() % 8 == 0) h += (u(rng) < 0.5 ? -1 : 1) * (0.05 + 2.5 * u(rng));  // a corner
    if (rng() % 3 == 0) {
      const double len = 0.5 + 20 * u(rng);
      r.geom = make_line(at, at + in_plane(std::cos(h), std::sin(h)) * len);
    } else {
      const double rad = rng() % 4 == 0 ? 0.2 + 0.8 * u(rng) : 1 + 30 * u(rng);
      const double dir = rng() % 2 ? 1.0 : -1.0, sweep = rng() % 4 == 0 ? 2 * std::numbers::pi : 0.1 + 3 * u(rng);
      const double c0 = at[p0] - dir * rad * std::sin(h), c1 = at[p1] + dir * rad * std::cos(h);
      const double a0 = std::atan2(at[p1] - c1, at[p0] - c0), a1 = a0 + dir * sweep;
      core::Vec to = at;
      to[p0] = c0 + rad * std::cos(a1);
      to[p1] = c1 + rad * std::sin(a1);
      if (sweep == 2 * std::numbers::pi) to = at;  // a full circle
      r.geom = make_arc(at, to, p0, p1, c0, c1, dir > 0 ? 1 : -1);
      h += dir * sweep;
    }
    reqs.push_back(r);
    at = r.geom.end;
  }
  return reqs;
}

// Plane circles take their jerk shares scaled to the Euclidean bound (1.387, segment_limits.cpp
// curve_jerk), and a curvature step at their ends takes its share off their tangential jerk by
// jerk_left_by_step: chains of lines, arcs and full circles in the xy, xz and yz planes, at 1 ms and
// 0.25 ms cycles, with the override changed now and then, keep every axis within its speed,
// acceleration and jerk, and every setpoint within P.
TEST(PlannerJerk, RandomPlaneChainsAtEveryCycleKeepTheLimits) {
  constexpr std::uint8_t kPlanes[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (std::uint64_t seed = 1; seed <= 150; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    MachineLimits lim = random_jerk_limits(rng, u);
    lim.period_s = rng() % 2 ? 0.001 : 0.00025;
    const double tol = std::array{0.0, 0.01, 0.05, 0.2}[rng() % 4];
    const auto& pl = kPlanes[rng() % 3];
    const auto reqs = plane_chain(rng, u, tol, pl[0], pl[1]);
    const std::uint64_t every = 200 + rng() % 3000;
    const auto hook = [&](std::uint64_t c, Interpolator& in) {
      if (c > 0 && c % every == 0) in.set_feed_override(0.3 + 1.2 * static_cast<double>((c / every * 7919) % 100) / 100);
    };
    const auto res = run_path(lim, reqs, 3 + rng() % 200, {}, hook);
    expect_within(res, tol, ("seed " + std::to_string(seed)).c_str());
    EXPECT_EQ(res.end, reqs.back().geom.end) << "seed " << seed;
    if (HasFailure()) break;
  }
}

// Seeded chains of lines and arcs joined tangentially (CAM contours: every junction a curvature
// step, S-bends where arcs turn opposite ways, tiny arcs and lines) with a corner now and then:
// the blends at arcs (Planner::blend_curves) and the gated certificate must keep every axis within
// speed, acceleration and jerk, and every setpoint within P of the program.
TEST(PlannerJerk, RandomTangentChainsOfLinesAndArcsKeepTheLimits) {
  expect_random_jerk_paths(300, {0.0, 0.01, 0.05, 0.2}, tangent_chain);
}

// Seeded chains of helices in the xy, xz and yz planes, steep ones (a rise of up to eight radii per
// turn, inplane down to 0.12) among shallow ones, joined by lines and corners, on axes with uneven
// jerks: every axis within its speed, acceleration and jerk (the in-plane speed term v³κ²/inplane,
// SteepHelicesKeepTheInPlaneAxesJerk), every setpoint within P.
TEST(PlannerJerk, RandomHelixChainsInEveryPlaneKeepTheLimits) {
  constexpr std::uint8_t kPlanes[3][3] = {{0, 1, 2}, {2, 0, 1}, {1, 2, 0}};
  expect_random_jerk_paths(200, {0.0, 0.01, 0.05, 0.2}, [&](std::mt19937_64& rng, std::uniform_real_distribution<double>& u, double tol) {
    const int n = 3 + static_cast<int>(rng() % 12);
    return chain(n, tol, [&](int, const core::Vec& at, const std::vector<PathRequest>&, PathRequest& r) {
      r.feed_mm_s = 5 + 400 * u(rng);
      if (rng() % 3 == 0) {
        core::Vec to = at;
        for (int i = 0; i < 3; ++i) to[i] += (u(rng) - 0.5) * (rng() % 3 == 0 ? 0.1 : 20);
        r.geom = make_line(at, to);
      } else {
        const auto& pl = kPlanes[rng() % 3];
        const double rad = 0.3 + 8 * u(rng), ang = 2 * std::numbers::pi * u(rng);
        const double c0 = at[pl[0]] - rad * std::cos(ang), c1 = at[pl[1]] - rad * std::sin(ang);
        const double sweep = 0.3 + 6 * u(rng), dir = rng() % 2 ? 1.0 : -1.0;
        core::Vec to = at;
        to[pl[0]] = c0 + rad * std::cos(ang + dir * sweep);
        to[pl[1]] = c1 + rad * std::sin(ang + dir * sweep);
        const double pitch = rng() % 2 ? 8 * u(rng) : 0.3 * u(rng);  // rise per radian, in radii
        to[pl[2]] += (u(rng) < 0.5 ? -1 : 1) * pitch * rad * sweep;
        r.geom = make_arc(at, to, pl[0], pl[1], c0, c1, dir > 0 ? 1 : -1);
      }
    });
  });
}

// A review's exploration (2026-12-03) found runs that came to rest a few nanometres short of an
// exact stop and never moved again: three xz arcs on a soft Z (j 235 mm/s³) at 1 ms, P 0.01.
TEST(PlannerJerk, RestJustShortOfAStopMovesOnToIt) {
  const MachineLimits lim = limits_vaj({{{94.938398689346215, 5044.821742683017, 97940.832588854915},
                                         {220.92991096911626, 2140.4241800586415, 98412.312630735789},
                                         {216.75416046650008, 40.807252091490462, 234.65166787838152}}},
                                       0.001);
  const core::Vec p1 = xyz(-0.1542524456310872, 0, 0.14196536564845641), p2 = xyz(-5.6657818944876919, 0, 3.8839253791524868);
  std::vector<PathRequest> reqs{
      arc_req(make_arc(xyz(0, 0, 0), p1, 0, 2, 0.86854244990662011, 1.0984988298633216, -1), 37.496440696477727, 0),
      arc_req(make_arc(p1, p2, 0, 2, -11.182934909921737, -10.172227528076979, 1), 50.208423097069236, 1),
      arc_req(make_arc(p2, xyz(-11.428825326992172, 0, 5.3016686440107357), 0, 2, -13.853167002940967, -16.975227280353536, 1),
              91.318777068499557, 2)};
  for (auto& r : reqs) r.tolerance_mm = 0.01;
  const auto res = run_path(lim, reqs, 3, {}, {}, 200'000);
  expect_within(res, 0.01, "three xz arcs");
  EXPECT_EQ(res.end, reqs.back().geom.end);
}

// One axis 50 to 200 times softer than the others in jerk and acceleration (a torch or a Z on a
// lead screw), at 1 ms and 0.25 ms: chains of lines, arcs and full circles in a random plane and
// tangent chains, queues of 3 to 200 blocks. Every axis within its speed, acceleration and jerk,
// every setpoint within P, and every run finishes. (The hang a review's exploration of such axes
// found is RestJustShortOfAStopMovesOnToIt; these 150 seeds do not meet it.)
TEST(PlannerJerk, RandomChainsOnAVerySoftAxisKeepTheLimits) {
  constexpr std::uint8_t kPlanes[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (std::uint64_t seed = 1; seed <= 150; ++seed) {
    std::mt19937_64 rng(seed * 104729);
    std::uniform_real_distribution<double> u(0, 1);
    MachineLimits lim = random_jerk_limits(rng, u);
    lim.period_s = rng() % 2 ? 0.001 : 0.00025;
    auto& soft = lim.axis[rng() % 3];
    // j·dt³ at least 1e-8 mm, five times the floor the configuration allows: nearer the floor a
    // position-mode stop's landing tolerance (1e-13 of its distance) and the rounding of positions
    // are a few 1e-4 of a cycle's jerk (docs/planner.md, "Jerk": stop 17).
    const double dt3 = lim.period_s * lim.period_s * lim.period_s;
    soft.j_max_mm_s3 = std::max(soft.j_max_mm_s3 / (50 + 150 * u(rng)), 1e-8 / dt3);
    soft.a_max_mm_s2 /= 50 + 150 * u(rng);
    const double tol = std::array{0.0, 0.01, 0.05, 0.2}[rng() % 4];
    const auto& pl = kPlanes[rng() % 3];
    const auto reqs = rng() % 2 ? plane_chain(rng, u, tol, pl[0], pl[1]) : tangent_chain(rng, u, tol);
    const auto res = run_path(lim, reqs, 3 + rng() % 200, {}, {}, 4'000'000);
    expect_within(res, tol, ("seed " + std::to_string(seed)).c_str());
    EXPECT_EQ(res.end, reqs.back().geom.end) << "seed " << seed;
    if (HasFailure()) break;
  }
}

// A helix whose linear Y runs 262 mm on a very soft Y (31 mm/s³ at 0.25 ms: j·dt³ = 4.9e-10 mm), then
// an exact stop (the corner cannot be blended on Y): the stop lands 8.4e-12 mm short, about 150 ulps
// of 260 mm: the kept fallback brake, solved again from each cycle's rounded state for 13 s, had
// drifted past the point, and its last cycle's landing on it took the drift as a jerk step: 1.05×
// Y's jerk (a review's exploration). JerkGuard::anchored_brake raises its jerk within the guard's
// relative slack where it would end past the point.
TEST(PlannerJerk, StopLandingOnALongHelixKeepsTheJerkOfASoftAxis) {
  const MachineLimits lim = limits_vaj({{{208.25513182745198, 1536.9568684266212, 85937.481757523012},
                                         {98.967262924224968, 8.9673252299048034, 31.220345748303313},
                                         {302.74499233469965, 979.30572435586816, 7539.9092801219313}}},
                                       0.00025);
  const core::Vec a = xyz(-0.12114780833303908, -2.1373613723737077, 63.820642455092411);
  const core::Vec b = xyz(2.0661548750440382, 259.83109941131579, 68.568881226660196);
  std::vector<PathRequest> reqs{arc_req(make_arc(a, b, 0, 2, -6.1402873335943884, 69.471308640236714, -1), 120.33847357692871, 0),
                                line_req(b, xyz(-5.1889295966178342, 259.87765449428628, 63.000344157043884), 354.51131560236229, 1)};
  for (auto& r : reqs) r.tolerance_mm = 0.01;
  const auto res = run_path(lim, reqs, 3);
  ASSERT_TRUE(res.finished);
  // Y near 260 mm: a third difference of positions is good to 8 ulps, 4.5e-13 mm, which is 9e-4 of
  // this j·dt³ (the suite's 1e-4 assumes positions nearer the origin).
  const double noise = 8 * 260 * std::numeric_limits<double>::epsilon() / (lim.axis[1].j_max_mm_s3 * std::pow(lim.period_s, 3));
  EXPECT_LT(noise, 1e-3);
  EXPECT_LE(res.fig.j_ratio, 1 + noise) << res.fig.describe();
  EXPECT_LE(res.fig.a_ratio, 1 + kRatioNoise) << res.fig.describe();
  EXPECT_LE(res.fig.v_ratio, 1 + kRatioNoise) << res.fig.describe();
  EXPECT_LE(res.fig.deviation_mm, 0.01 + 1e-9);
  EXPECT_EQ(res.end, reqs.back().geom.end);
}

// Axes whose jerk is so low that one cycle of it moves a few nanometres: j·dt³ from the floor the
// configuration allows (motion::kMinJerkStep_mm, 2e-9 mm) to ten times it, at 0.1, 0.25 and 0.5 ms
// cycles (2 000–20 000 mm/s³ at 0.1 ms), on short lines with exact stops now and then; and from the
// old floor, 2e-10 mm (200–2 000 mm/s³ at 0.1 ms), where the roundings below were found and mended.
struct TinyJerkCase {
  MachineLimits lim;
  double tol = 0;
  std::vector<PathRequest> reqs;
  std::size_t capacity = 0;
};
static TinyJerkCase tiny_jerk_case(std::uint64_t seed, double floor_mm = kMinJerkStep_mm) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  TinyJerkCase c;
  c.lim.period_s = std::array{0.0001, 0.00025, 0.0005}[rng() % 3];
  const double dt3 = c.lim.period_s * c.lim.period_s * c.lim.period_s;
  for (int i = 0; i < 3; ++i)  // j·dt³ from the floor to ten times it
    c.lim.axis[i] = {2 + 20 * u(rng), 5 + 60 * u(rng), floor_mm * (1 + 9 * u(rng)) / dt3, -1000, 1000};
  c.tol = std::array{0.0, 0.01, 0.05}[rng() % 3];
  core::Vec at = xyz(0, 0, 0);
  const int n = 2 + static_cast<int>(rng() % 5);
  for (int k = 0; k < n; ++k) {
    PathRequest r;
    r.feed_mm_s = 1 + 20 * u(rng);
    r.tag = static_cast<std::uint32_t>(k);
    r.tolerance_mm = rng() % 3 == 0 ? 0.0 : c.tol;  // some exact stops
    core::Vec to = at;
    for (int i = 0; i < 3; ++i) to[i] += (u(rng) - 0.5) * (rng() % 3 == 0 ? 0.02 : 3.0);
    r.geom = make_line(at, to);
    c.reqs.push_back(r);
    at = to;
  }
  c.capacity = 3 + rng() % 50;
  return c;
}

// Every distance the follower rounds must stay well below one cycle of jerk there: a position step
// δ shows as a jerk of up to 2·δ/dt³. A review found 1.3–2.7 times the limit at the ends of stops:
// the certificate let a brake run up to 1e-9 mm past a stop, blocks were passed 1e-12 mm early
// (that distance dropped), and Otg1 landed a stop within 1e-13 mm (then snapped). 108 of 400 seeds
// broke the jerk limit before those three were fixed, none after.
TEST(PlannerJerk, AxesWithATinyJerkPerCycleKeepItAtRestOnAPoint) {
  // Seeds 1–60, two a review found (10 000 seeds), 1096 and 9879, where the certificate's slack of 1e-9 of the
  // distance to a stop let the fallback brake, run for 750 cycles, end 6e-11 mm past it (1.075×),
  // and 2079, where Otg1 landing a stop within a fixed 1e-13 mm broke it 1.0001×.
  // All were drawn from the floor of 2e-10 mm the roundings were mended at, and still are; seeds
  // 1–60 also from the configuration's floor since it was raised, motion::kMinJerkStep_mm (2e-9 mm).
  std::vector<std::pair<std::uint64_t, double>> cases{{1096, 2e-10}, {9879, 2e-10}, {2079, 2e-10}};
  for (std::uint64_t seed = 1; seed <= 60; ++seed) cases.insert(cases.end(), {{seed, 2e-10}, {seed, kMinJerkStep_mm}});
  for (const auto& [seed, floor_mm] : cases) {
    const TinyJerkCase c = tiny_jerk_case(seed, floor_mm);
    const auto res = run_path(c.lim, c.reqs, c.capacity);
    const std::string what = "seed " + std::to_string(seed) + (floor_mm == kMinJerkStep_mm ? " at the floor" : " at 2e-10 mm");
    expect_within(res, c.tol, what.c_str());
    EXPECT_EQ(res.end, c.reqs.back().geom.end) << what;
    if (HasFailure()) break;
  }
}

// A move shorter than a nanometre between two exact stops, on axes whose jerk per cycle, j·dt³, is
// at or near the floor (motion::kMinJerkStep_mm): the planner used to leave out pieces up to 1e-9 mm
// (their length became a step in the setpoints, 10 times the jerk limit at the floor), and the
// follower snapped onto a stop from up to 1e-9 mm short. Now both stay within a twentieth of j·dt³
// and the stop plan covers the rest.
TEST(PlannerJerk, SubNanometreMovesBetweenExactStopsKeepTheJerk) {
  for (const double d : {1e-12, 1e-11, 5e-11, 1e-10, 5e-10, 1e-9, 1.5e-9, 3e-9, 1e-8, 1e-7}) {
    // The floor and above it, and the old floor's 2e-10 to 1e-9 mm where these moves were mended.
    for (const double jdt3 : {2e-10, 5e-10, 1e-9, kMinJerkStep_mm, 5e-9, 1e-8}) {
      MachineLimits lim;
      lim.period_s = 0.00025;
      const double dt3 = lim.period_s * lim.period_s * lim.period_s;
      for (int i = 0; i < 3; ++i) lim.axis[i] = {10, 20, jdt3 / dt3, -1000, 1000};
      const std::vector<PathRequest> reqs{line_req(xyz(0, 0), xyz(0.01, 0), 10, 0, 0),
                                          line_req(xyz(0.01, 0), xyz(0.01, d), 10, 1, 0),
                                          line_req(xyz(0.01, d), xyz(0.02, 0.001), 10, 2, 0)};
      const auto res = run_path(lim, reqs, 16);
      const std::string what = "d " + std::to_string(d) + " j·dt³ " + std::to_string(jdt3);
      expect_within(res, 0, what.c_str());
      EXPECT_EQ(res.end, reqs.back().geom.end) << what;
    }
  }
}
