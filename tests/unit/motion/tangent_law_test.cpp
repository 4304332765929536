// The speed-dependent tangential acceleration on curves (tangent_law.hpp): roots, bounds, and what
// it buys on whole paths (issue 4: per-axis limits given direction and curvature).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "motion/planner/planner.hpp"
#include "motion/planner/tangent_law.hpp"
#include "planner_run.hpp"

namespace softmc::motion {
namespace {

using testing::run_path;

MachineLimits xy(double v, double a) {
  MachineLimits lim;
  lim.axis[0] = {v, a, 0};
  lim.axis[1] = {v, a, 0};
  return lim;
}

PlannerConfig trapezoid_split() {
  PlannerConfig pc;
  pc.speed_dependent_tangential = false;
  return pc;
}

// Random laws of both kinds of term: the closed-form root solves w − x = k·g(w) (or lies at the cap,
// or at x where nothing is left), and nothing larger does.
TEST(TangentLaw, RootSolvesTheBrakingEquation) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int n = 0; n < 20000; ++n) {
    TangentLaw l;
    const int terms = 1 + static_cast<int>(rng() % 3);
    for (int t = 0; t < terms; ++t) {
      TangentTerm tt;
      if (rng() % 2) {
        tt.alpha = 100 + 5000 * u(rng);
        tt.beta = 10 * u(rng);
      }
      if (rng() % 2 || !std::isfinite(tt.alpha)) {
        tt.c = 100 + 5000 * u(rng);
        tt.d = rng() % 4 ? 10 * u(rng) : 0;
      }
      l.add(tt);
    }
    if (rng() % 3 == 0) l.a_const = 200 + 3000 * u(rng);
    if (rng() % 3 == 0) l.w_cap = 1e4 * u(rng);
    if (rng() % 4 == 0) l.scale = 0.75;
    const double x = 5000 * u(rng) * u(rng);
    const double k = 2 * std::pow(10, -3 + 4 * u(rng));  // 2 µm … 20 m of braking
    const double w = l.root(x, k);
    ASSERT_GE(w, x);
    const double lhs = w - x, rhs = k * l.at(w);
    // The root never asks for more than the law gives at it (it brakes at g(w), the least along it).
    EXPECT_LE(lhs, rhs * (1 + 1e-9) + 1e-9 * (1 + w)) << n;
    // Tight: a little above the root the law no longer covers it (unless the cap or x holds it).
    const double w2 = w * (1 + 1e-6) + 1e-6;
    if (w < l.w_cap * (1 - 1e-9) && l.at(x) > 0) {
      EXPECT_GT(w2 - x, k * l.at(w2)) << n;
    }
  }
}

// A circular arc in XY at speed² w with tangential acceleration law.at(w): every point of the circle
// keeps |a_x|, |a_y| ≤ A, and at w_cap the centripetal acceleration alone is A.
TEST(TangentLaw, ArcLawKeepsEveryAxisAtEverySpeed) {
  const MachineLimits lim = xy(1000, 1000);
  const Segment arc = make_arc({0, 0}, {0, 0}, 0, 1, 5, 0, 1);  // full circle, R = 5
  const CurveLaw c = segment_law(arc, lim);
  EXPECT_NEAR(c.v_max_mm_s, std::sqrt(1000.0 * 5), 1e-9);  // √(a·R): the whole centripetal limit
  for (double f = 0; f <= 1; f += 0.05) {
    const double w = f * c.v_max_mm_s * c.v_max_mm_s;
    const double at = c.law.at(w), an = w / 5;
    for (double ph = 0; ph < 2 * std::numbers::pi; ph += 0.01) {
      const double ax = -at * std::sin(ph) - an * std::cos(ph), ay = at * std::cos(ph) - an * std::sin(ph);
      EXPECT_LE(std::abs(ax), 1000 * (1 + 1e-12));
      EXPECT_LE(std::abs(ay), 1000 * (1 + 1e-12));
    }
  }
  EXPECT_NEAR(c.law.at(0), 1000, 1e-9);  // at rest the whole limit drives the path
}

// A shallow blend where X carries the tangent and Y the normal: both keep their limits while the
// law lets the path accelerate with nearly all of X's limit even close to the speed cap.
TEST(TangentLaw, BlendLawUsesTheAxesTheSweepLoads) {
  const MachineLimits lim = xy(1000, 1000);
  const Vec t1{1, 0}, t2{std::cos(0.02), std::sin(0.02)};
  const BlendArc b = make_blend_arc({0, 0}, t1, t2, 10, 0.02);
  const CurveLaw c = blend_law(b, lim);
  const double w_cap = c.v_max_mm_s * c.v_max_mm_s;
  EXPECT_NEAR(w_cap, 1000.0 * 10, 1e-6);  // Y takes the normal: v = √(A·R)
  for (double f = 0; f < 1; f += 0.1) {
    const double w = f * w_cap, at = c.law.at(w);
    for (double ph = 0; ph <= 0.02; ph += 0.001) {
      const Vec tan = b.tangent(ph * 10), kap = b.curvature(ph * 10);
      for (std::size_t i = 0; i < 2; ++i) EXPECT_LE(std::abs(at * tan[i] + w * kap[i]), 1000 * (1 + 1e-9));
    }
  }
  EXPECT_GT(c.law.at(0.9 * w_cap), 0.9 * 1000);  // the fixed split would give 0.6·A at a lower cap
}

// A half circle R = 5 between two tangent lines, at a feed above its cap: it is crossed faster than
// the split's cap √(0.8·a·R), never above √(a·R), and the trace keeps every axis's limits. (As one
// block, a lone circle from rest keeps one acceleration per ramp and cruises lower: the Channel
// cuts arcs into 45° pieces for that, docs/planner.md.)
TEST(TangentLaw, TangentArcRunsAboveTheSplitCap) {
  const MachineLimits lim = xy(1000, 1000);
  std::vector<PathRequest> reqs(3);
  reqs[0].geom = make_line({-50, 0}, {0, 0});
  reqs[1].geom = make_arc({0, 0}, {0, 10}, 0, 1, 0, 5, 1);
  reqs[2].geom = make_line({0, 10}, {-50, 10});
  for (auto& r : reqs) {
    r.feed_mm_s = 200;
    r.profile = ProfileKind::Trapezoid;
  }
  const auto law = run_path(lim, reqs, 64);
  const auto split = run_path(lim, reqs, 64, trapezoid_split());
  ASSERT_TRUE(law.finished);
  ASSERT_TRUE(split.finished);
  EXPECT_LE(law.fig.a_ratio, 1 + 1e-5) << law.fig.describe();
  EXPECT_LE(law.fig.v_ratio, 1 + 1e-5) << law.fig.describe();
  EXPECT_LT(law.cycles, split.cycles) << law.cycles << " vs " << split.cycles;
}

// CAM-like polylines on a curve (0.5 mm chords, blended): the law is never slower than the split,
// keeps every limit, and stays within P.
TEST(TangentLaw, BlendedPolylinesRunFasterThanTheSplitWithinEveryLimit) {
  const MachineLimits lim = xy(100, 1000);
  std::vector<PathRequest> reqs;
  Vec at{};
  for (int k = 0; k < 400; ++k) {
    const double x = 0.5 * (k + 1), y = 3 * std::sin(x / 4);
    PathRequest r;
    r.geom = make_line(at, {x, y});
    r.feed_mm_s = 100;
    r.tolerance_mm = 0.05;
    r.profile = ProfileKind::Trapezoid;
    reqs.push_back(r);
    at = r.geom.end;
  }
  const auto law = run_path(lim, reqs, 2048);
  const auto split = run_path(lim, reqs, 2048, trapezoid_split());
  ASSERT_TRUE(law.finished);
  EXPECT_LE(law.fig.a_ratio, 1 + 1e-5) << law.fig.describe();
  EXPECT_LE(law.fig.v_ratio, 1 + 1e-5) << law.fig.describe();
  EXPECT_LE(law.fig.deviation_mm, 0.05 + 1e-9);
  EXPECT_LT(law.cycles, split.cycles * 0.97) << law.cycles << " vs " << split.cycles;
}

// plasma.ngc's notch with an end further off the circle: the corner is an exact stop and the trace
// has no jump there (before the spiral the arc ended on its start circle, short of the end, and the
// setpoint jumped to it: 0.54 µm in plasma.ngc, 48 samples over the jerk limit).
TEST(TangentLaw, ArcWithAnEndOffTheCircleKeepsTheLimitsAtTheNextCorner) {
  const MachineLimits lim = xy(100, 1000);
  // The end 10 µm outside the start circle (the interpreter allows up to 28 µm on small arcs).
  const double ux = 3.54 / std::hypot(3.54, 1.86), uy = -1.86 / std::hypot(3.54, 1.86);
  const double r1 = std::hypot(31.62 - 35, 18.835 - 16.699) + 0.01;
  const Vec end{35 + r1 * ux, 16.699 + r1 * uy};
  std::vector<PathRequest> reqs(2);
  reqs[0].geom = make_arc({31.62, 18.835}, end, 0, 1, 35, 16.699, -1);
  reqs[1].geom = make_line(end, {56.004, 10.16});
  for (auto& r : reqs) {
    r.feed_mm_s = 100;
    r.profile = ProfileKind::Trapezoid;
  }
  const auto res = run_path(lim, reqs, 64);
  ASSERT_TRUE(res.finished);
  EXPECT_LE(res.fig.a_ratio, 1 + 1e-5) << res.fig.describe();
  EXPECT_EQ(res.end, reqs.back().geom.end);
}
// A blend that moves five axes needs five terms, more than a law holds: it keeps the fixed split
// (a correct, slower law) and the run keeps every limit.
TEST(TangentLaw, CurvesOnMoreAxesThanTheLawHoldsKeepTheSplit) {
  MachineLimits lim;
  for (int i = 0; i < 5; ++i) lim.axis[i] = {100, 1000, 0};
  Vec a{}, b{}, c{};
  for (int i = 0; i < 5; ++i) {
    b[i] = 10 + i;
    c[i] = b[i] + (i % 2 ? 8 : 3);
  }
  const Vec t1 = (b - a) * (1 / core::norm(b - a)), t2 = (c - b) * (1 / core::norm(c - b));
  const double delta = 2 * std::asin(core::norm(t2 - t1) / 2);
  const BlendArc arc = make_blend_arc(b - t1 * 1.0, t1, t2, 1.0 / std::tan(delta / 2), delta);
  EXPECT_TRUE(blend_law(arc, lim).law.full);
  std::vector<PathRequest> reqs(2);
  reqs[0].geom = make_line(a, b);
  reqs[1].geom = make_line(b, c);
  for (auto& r : reqs) {
    r.feed_mm_s = 100;
    r.tolerance_mm = 0.1;
    r.profile = ProfileKind::Trapezoid;
  }
  const auto res = run_path(lim, reqs, 16);
  ASSERT_TRUE(res.finished);
  EXPECT_LE(res.fig.a_ratio, 1 + 1e-5) << res.fig.describe();
  EXPECT_LE(res.fig.deviation_mm, 0.1 + 1e-9);
}
// Arc pieces of at most 45° (the Channel cuts arcs so without jerk limits) use their own sweep's
// tangent and normal shares: at every speed up to the piece's cap, every point of every random
// piece keeps both axes within their limits, and the pieces near an axis's direction allow more
// tangential acceleration than the whole circle does.
TEST(TangentLaw, ArcPieceLawKeepsEveryAxisOverItsSweep) {
  const MachineLimits lim = xy(1000, 1000);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  const double r = 4;
  const CurveLaw whole = segment_law(make_arc({r, 0}, {r, 0}, 0, 1, 0, 0, 1), lim);
  bool gained = false;
  for (int n = 0; n < 300; ++n) {
    const double a0 = 2 * std::numbers::pi * u(rng), sw = (0.05 + 0.735 * u(rng)) * (rng() % 2 ? 1 : -1);
    const Segment arc = make_arc({r * std::cos(a0), r * std::sin(a0)}, {r * std::cos(a0 + sw), r * std::sin(a0 + sw)}, 0, 1,
                                 0, 0, sw > 0 ? 1 : -1);
    const CurveLaw c = segment_law(arc, lim);
    const double w_cap = c.v_max_mm_s * c.v_max_mm_s;
    for (double f = 0; f <= 1; f += 0.05) {
      const double w = f * w_cap, at = c.law.at(w);
      if (at > whole.law.at(w) * 1.01) gained = true;
      for (int k = 0; k <= 20; ++k) {
        const double s = arc.length * k / 20;
        const Vec acc = arc.tangent(s) * at + arc.curvature(s) * w;
        for (std::size_t i = 0; i < 2; ++i) ASSERT_LE(std::abs(acc[i]), 1000 * (1 + 1e-9)) << n << " " << f;
      }
    }
  }
  EXPECT_TRUE(gained);
}
// A kink (a corner between two arcs, never blended) where both arcs cruise near their cap:
// the kink's one-cycle impulse comes on top of the arc's centripetal acceleration, so the kink
// speed leaves that room; and a hold on the arc brakes with at least the reserve (the cap keeps
// tangential_reserve of the law), re-planned as the speed falls.
TEST(TangentLaw, KinkAndHoldOnAnArcAtItsCapKeepTheLimits) {
  const MachineLimits lim = xy(1000, 1000);
  std::vector<PathRequest> reqs(3);
  reqs[0].geom = make_line({-50, 0}, {0, 0});
  reqs[1].geom = make_arc({0, 0}, {0, 10}, 0, 1, 0, 5, 1);  // half circle R5, ends heading −x
  const double off = 0.0036;  // rad: a corner between two arcs (never blended): a kink
  // A second half circle R5 on the same side, its start heading turned `off` towards the centre:
  // both neighbours of the kink carry their full centripetal acceleration on the same axis.
  const double cx = 5 * std::sin(off), cy = 10 - 5 * std::cos(off);
  reqs[2].geom = make_arc({0, 10}, {2 * cx, 2 * cy - 10}, 0, 1, cx, cy, 1);
  for (std::size_t k = 0; k < reqs.size(); ++k) {
    reqs[k].feed_mm_s = 200;
    reqs[k].profile = ProfileKind::Trapezoid;
    reqs[k].tolerance_mm = 0.001;  // arcs are never blended: the corner is a kink
    reqs[k].tag = static_cast<std::uint32_t>(k);
  }
  const auto res = run_path(lim, reqs, 64);
  ASSERT_TRUE(res.finished);
  EXPECT_LE(res.fig.a_ratio, 1 + 1e-5) << res.fig.describe();
  EXPECT_LE(res.fig.v_ratio, 1 + 1e-5) << res.fig.describe();
  // Hold at the middle of the half circle (about 10 ms after the line ends at the cap), release
  // 0.3 s later: the brake and the restart keep the limits, and the hold brakes promptly.
  std::uint64_t held_at = 0, rest_at = 0;
  const auto hold = run_path(lim, reqs, 64, {}, [&](std::uint64_t c, Interpolator& in) {
    const bool on_arc = in.setpoint().tag == 1;
    if (on_arc && held_at == 0) held_at = c + 100;
    in.set_feed_hold(held_at != 0 && c >= held_at && c < held_at + 300);
    if (held_at != 0 && c > held_at && rest_at == 0 && in.setpoint().path_v == 0) rest_at = c;
  });
  ASSERT_TRUE(hold.finished);
  EXPECT_LE(hold.fig.a_ratio, 1 + 1e-5) << hold.fig.describe();
  ASSERT_GT(rest_at, held_at);
  EXPECT_LT(rest_at - held_at, 400u);  // 70 mm/s at ≥ 250 mm/s² reserve: well under 0.4 s
}
// The cruise cap of a trapezoid curve keeps `tangential_reserve` of the law (a hold or stop always
// brakes with at least that): reserve_w is exactly where the law falls to that share.
TEST(TangentLaw, ReserveCapLeavesTheShareOfTheLaw) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int n = 0; n < 5000; ++n) {
    TangentLaw l;
    for (int t = 0; t < 1 + static_cast<int>(rng() % 3); ++t) {
      TangentTerm tt;
      tt.alpha = 100 + 5000 * u(rng);
      tt.beta = 0.01 + 10 * u(rng);
      tt.c = 100 + 5000 * u(rng);
      tt.d = 0.01 + 10 * u(rng);
      l.add(tt);
    }
    const double r = 0.05 + 0.9 * u(rng), g0 = l.at(0);
    const double w = l.reserve_w(r);
    ASSERT_GT(w, 0);
    EXPECT_GE(l.at(w), r * g0 * (1 - 1e-9)) << n;
    EXPECT_LT(l.at(w * (1 + 1e-6) + 1e-6), r * g0) << n;
  }
  // A circle R5 at 1000 mm/s²: the cap is √(1 − r²) of the centripetal limit in v².
  const auto c = segment_law(make_arc({5, 0}, {5, 0}, 0, 1, 0, 0, 1), xy(1000, 1000));
  EXPECT_NEAR(c.law.reserve_w(0.25), std::sqrt(1 - 0.25 * 0.25) * 5000, 1e-6);
}
}  // namespace
}  // namespace softmc::motion
