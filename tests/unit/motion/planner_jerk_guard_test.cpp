// PlannerJerk, the guard: its shortcuts, certificates and index, the fallback brakes, stop plans and brake distance.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "motion/geometry/bezier.hpp"
#include "motion/geometry/polyline_smoothing.hpp"
#include "motion/interp/jerk_follower.hpp"
#include "motion/interp/jerk_guard.hpp"
#include "planner_jerk_support.hpp"

using namespace softmc;
using namespace softmc::motion;
using namespace softmc::motion::testing;

namespace {
// Two runs of the same path that differ only in how the guard computes its verdicts: the setpoints
// must be bit-identical, and within every limit and P.
void expect_identical_runs(const MachineLimits& lim, const std::vector<PathRequest>& reqs, const InterpolatorConfig& ca,
                           const InterpolatorConfig& cb, std::uint64_t seed) {
  std::vector<core::Vec> a, b;
  const auto ra = run_path(lim, reqs, 256, {}, {}, 20'000'000, ca, &a);
  const auto rb = run_path(lim, reqs, 256, {}, {}, 20'000'000, cb, &b);
  ASSERT_TRUE(ra.finished && rb.finished) << "seed " << seed;
  ASSERT_EQ(a.size(), b.size()) << "seed " << seed;
  for (std::size_t k = 0; k < a.size(); ++k) ASSERT_EQ(a[k], b[k]) << "seed " << seed << " cycle " << k;
  expect_within(rb, 0.05, ("seed " + std::to_string(seed)).c_str());
}
}  // namespace

// The guard's two shortcuts change how it reaches its verdicts, never the verdicts: the closed-form
// tail (InterpolatorConfig::guard_closed_form: where the rest of the brake is one ramp that keeps
// every limit it stops simulating) and the index of the window (guard_index: the brake's "smallest
// jerk up to the stop point" without walking the blocks). On random paths with exact stops (G61
// corners), short blocks and varying limits, each must give setpoints bit-identical to the plain
// cycle-by-cycle simulation that walks every block.
TEST(PlannerJerk, GuardShortcutsGiveTheSameSetpoints) {
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const auto lim = jerk_limits(50 + 200 * u(rng), 300 + 3000 * u(rng), 5000 + 50000 * u(rng));
    std::vector<PathRequest> reqs;
    core::Vec at = xyz(0, 0, 0);
    const int n = 5 + static_cast<int>(rng() % 60);
    for (int k = 0; k < n; ++k) {
      core::Vec to = at;
      const double len = rng() % 3 ? 0.05 + 2 * u(rng) : 5 + 30 * u(rng);
      const double ang = (u(rng) - 0.5) * (rng() % 2 ? 0.3 : 3.0);
      to[0] += len * std::cos(ang + k * 0.2);
      to[1] += len * std::sin(ang + k * 0.2);
      to[2] += rng() % 2 ? 0.3 * (u(rng) - 0.5) : 0.0;
      reqs.push_back(line_req(at, to, 20 + 200 * u(rng), static_cast<std::uint32_t>(k), rng() % 4 ? 0.05 : 0.0));
      at = to;
    }
    // The shortcuts of the simulation of π: the certificate, which replaces that simulation where
    // it can (and so changes the setpoints), is off in all three.
    InterpolatorConfig plain, closed, index;
    plain.guard_closed_form = false;
    plain.guard_index = false;
    closed.guard_index = false;
    index.guard_closed_form = false;
    for (auto* c : {&plain, &closed, &index}) c->guard_certificate = false;
    expect_identical_runs(lim, reqs, plain, closed, seed);
    expect_identical_runs(lim, reqs, plain, index, seed);
  }
}

// 0.5 mm chords of a circle R 30 with Z swinging along, smoothed as the Channel does by default on
// a jerk-limited machine (one C² B-spline of Poly pieces, each with its own limits).
namespace {
std::vector<PathRequest> smoothed_circle(std::vector<core::Vec>& pts) {
  for (int k = 0; k <= 400; ++k) {
    const double a = 2 * std::numbers::pi * k / 376.99;
    pts.push_back(xyz(30 * std::sin(a), 30 - 30 * std::cos(a), 2 - 2 * std::cos(a)));
  }
  std::vector<std::vector<Segment>> out;
  smooth_polyline(pts, PolylineSmoothing{}, out);
  std::vector<PathRequest> reqs;
  for (const auto& line : out)
    for (const auto& seg : line) reqs.push_back({seg, 100, false, static_cast<std::uint32_t>(reqs.size())});
  return reqs;
}
}  // namespace

// The certificate takes a group of 8 blocks of its index at once wherever the walk block by block
// would end the same (GuardScratch); that must never change a verdict. On a smoothed
// flower (0.5 mm chords, the radius swinging 30 ± 12 mm three times a lap: the pieces' caps rise
// and fall, tens of them within the braking distance) the default run skips groups and gives
// setpoints bit-identical to the one taking every block one by one.
namespace {
Block guard_block(double len, double a, double j, double cap, double feed, double u2) {
  Block b;
  b.length = len;
  b.a_mm_s2 = a;
  b.j_mm_s3 = j;
  b.v_cap_mm_s = b.v_split_mm_s = cap;
  b.feed_mm_s = feed;
  b.v2_junction = u2;
  return b;
}
// The certificate's verdict (no simulation of π) on `step` over the window `blocks`, at v_now.
GuardVerdict certificate_verdict(const std::vector<Block>& blocks, double v_now, const PathStep& step, GuardScratch& scratch) {
  core::Ring<Block> ring(scratch.cap);
  for (const auto& x : blocks) ring.push(x);
  GuardMode mode;
  mode.certify = true;
  mode.simulate = false;
  return JerkGuard(ring, ring.size(), 0, v_now, 0.001, 1, false, 1, scratch).verify(step, mode);
}
// Every field of the verdicts, exactly (`near`: distances to the rounding of starts read as
// differences from an index's origin).
void expect_same_verdict(const GuardVerdict& a, const GuardVerdict& b, bool near, const std::string& what) {
  const auto close = [&](double x, double y) {
    return x == y || (std::isnan(x) && std::isnan(y)) || (near && std::abs(x - y) <= 1e-12 * (1 + std::abs(x)));
  };
  EXPECT_EQ(a.hard_ok, b.hard_ok) << what;
  EXPECT_EQ(a.soft_ok, b.soft_ok) << what;
  EXPECT_EQ(a.stop_binds, b.stop_binds) << what;
  EXPECT_TRUE(close(a.fail_at_mm, b.fail_at_mm)) << what << ": " << a.fail_at_mm << " vs " << b.fail_at_mm;
  EXPECT_EQ(a.fail_u_mm_s, b.fail_u_mm_s) << what;
  EXPECT_EQ(a.cert_a, b.cert_a) << what;
  EXPECT_EQ(a.cert_j, b.cert_j) << what;
  EXPECT_EQ(a.cert_w, b.cert_w) << what;
  EXPECT_TRUE(close(a.cert_gate_mm, b.cert_gate_mm)) << what;
  EXPECT_EQ(a.cert_a2, b.cert_a2) << what;
  EXPECT_EQ(a.cert_j2, b.cert_j2) << what;
  EXPECT_TRUE(close(a.brake_s, b.brake_s)) << what << ": " << a.brake_s << " vs " << b.brake_s;
}
// The verdict on `step` over `blocks` (the first `n` the window), block by block, with groups, with
// groups from an index kept through `origin` pops (the same blocks at other positions), and with
// groups and the ramp built at every refresh of its distance (GuardScratch::bracket = false).
void expect_group_verdicts(const std::vector<Block>& blocks, std::size_t n, double s_front, double v_now,
                           const PathStep& step, std::size_t origin, const std::string& what) {
  GuardMode mode;
  mode.certify = true;
  mode.simulate = false;
  GuardVerdict v[4];
  for (int variant = 0; variant < 4; ++variant) {
    core::Ring<Block> ring(256);
    GuardScratch scratch(256);
    scratch.groups = variant != 0;
    scratch.bracket = variant != 3;
    if (variant == 2) {
      for (std::size_t i = 0; i < origin; ++i) ring.push(blocks.front());
      for (const auto& b : blocks) ring.push(b);
      const JerkGuard g0(ring, ring.size(), 0, 0, 0.001, 1, false, 1, scratch);
      for (std::size_t k = 0; k < ring.size(); ++k) g0.acc(k);  // indexed at these positions
      for (std::size_t i = 0; i < origin; ++i) ring.pop();
    } else {
      for (const auto& b : blocks) ring.push(b);
    }
    const JerkGuard g(ring, n, s_front, v_now, 0.001, 1, false, 1, scratch);
    v[variant] = g.verify(step, mode);
  }
  expect_same_verdict(v[0], v[1], false, what + ", groups");
  expect_same_verdict(v[0], v[2], true, what + ", groups, index kept through pops");
  expect_same_verdict(v[1], v[3], false, what + ", ramp built at every refresh");
}
}  // namespace

// The certificate's walk takes a group of blocks whole only where block by block it would end the
// same: with no refresh of the ramp's distance on the way (with |a| above A being brought down, a
// lower J shortens the ramp) and no entry that narrows π's scan. Two cases a review's differential
// fuzzer found (660 M cases), where taking groups gave another verdict, then seeded random windows.
TEST(PlannerJerk, CertificateGroupsGiveTheBlockByBlockVerdict) {
  constexpr std::size_t G = GuardScratch::kGroup;
  const double inf = std::numeric_limits<double>::infinity();
  {  // A group that only lowers the jerk, taken while the entry cursor lagged behind a block of lower
     // acceleration: the jerk's refresh made the walk enter it and end its scan inside the group.
    std::vector<Block> b{guard_block(3.65, 2000, 10000, 100, 100, 1e4), guard_block(0.2, 1100, 10000, 100, 100, 1e4)};
    for (std::size_t i = 2; i < G; ++i) b.push_back(guard_block((9.95 - 3.85) / (G - 2), 2000, 10000, 100, 100, 1e4));
    for (std::size_t i = G; i < 2 * G; ++i)
      b.push_back(guard_block(3.5 / G, 2000, i == G ? 9000 : i == G + 4 ? 8000 : 10000, 100, 100, 1e4));
    for (std::size_t i = 0; i < 24; ++i) b.push_back(guard_block(0.5, 2000, 10000, 100, 100, 1e4));
    b.front().v2_junction = 0;
    expect_group_verdicts(b, b.size(), 0, 50, jerk_cycle({0, 50, 0, 0}, 0, 0.001), 5, "lagging entry");
  }
  {  // Braking harder than A (|a| above it is brought down at J first): refreshed at a group's start,
     // the lower J shortened the ramp, and the walk took other blocks (fuzzer seed 114338).
    const double rows[][6] = {
        {1.1088714472104717, 151.4844638028807, inf, 35.971321177384752, 27.517271185532703, 1293.9359472465687},
        {0.25719096936750047, 76.341797442090837, 1588.4848201071009, 26.72947023289764, 34.397599754245064, 283.74887974977548},
        {0.056512693764427892, 151.4844638028807, 2128.8778233005205, 24.770203691646667, 59.017745473485924, 613.56299092566621},
        {0.12039499194192818, 52.937313756117973, 2252.71551599134, 47.897019618983236, 20.146569501196222, 2294.1244883812651},
        {0.13657694697284534, 151.4844638028807, 2073.4582475296897, 47.897019618983236, 34.392639910390663, 2294.1244883812651},
        {0.34335212832738793, 57.778989180232813, 2073.4582475296897, 47.897019618983236, 53.862961795549005, 2294.1244883812651},
        {0.16770488628081676, 151.4844638028807, 1849.5134180023877, 47.897019618983236, 44.85563413011301, 2294.1244883812651},
        {0.012332113714627207, 103.64681265595485, 878.17408817859712, 50.343639330095861, 55.7400987199211, 136.62700337383973},
        {1.4554606652677, 207.69141697805173, 2128.8778233005205, 11.655499245241577, 24.971997067641038, 135.85066265582697},
        {0.073890436500821416, 151.4844638028807, 28.876713412192196, 47.897019618983236, inf, 2294.1244883812651},
        {1.0675441334974534, 151.4844638028807, 1842.8545415407459, 47.897019618983236, inf, 1454.9453222534921},
        {1.0929315008473262, 121.566107743088, 2087.2076041734349, 47.897019618983236, 35.545263373857289, 2294.1244883812651},
        {0.013910263054333901, 151.4844638028807, 1061.1032123107657, 10.878688904933428, 35.721854939012005, 118.34587229032167},
        {2.6467630057015148, 151.4844638028807, 69.845609415346232, 47.897019618983236, 27.561833759572608, 2294.1244883812651},
        {1.3960222632067201, 222.0478771831653, 2037.08560849728, 20.63230151549282, 46.913944360956641, 425.69186582620733},
        {1.2320289990992146, 53.169157556386267, 2120.484085004508, 47.897019618983236, 39.989820440148527, 2294.1244883812651}};
    std::vector<Block> b;
    for (const auto& r : rows) b.push_back(guard_block(r[0], r[1], r[2], r[3], r[4], r[5]));
    b[9].rapid = b[10].rapid = true;
    PathStep step = jerk_cycle({0, 16.384361981973971, 0, 0}, 0, 0.001);
    step.x = {0.016369870857921708, 16.340888609817178, -86.946744313588354, 0};
    expect_group_verdicts(b, b.size(), 0.24975768181161045, 16.384361981973971, step, 43, "braking harder than A");
  }
  {  // A block of lower acceleration starting on the ramp's reach, and a few ulps either side: the
     // closed-form distance's bracket holds it, so the walk builds the ramp to decide whether the
     // ramp enters it (GuardScratch::bracket), as it does at every refresh without the bracket.
    const PathStep step = jerk_cycle({0, 40, 100, 0}, 0, 0.001);
    const double reach = JerkGuard::brake_distance(step.x, 2000, 10000) * (1 + 1e-9) + 1e-9 + 1e-12;  // certify's reach(d)
    double first_a = 0;
    bool both = false;
    std::uint64_t sharpened = 0;
    double len = std::nextafter(reach + step.x.s, 0.0);
    for (int i = 0; i < 6; ++i) len = std::nextafter(len, 0.0);
    for (int i = 0; i < 14; ++i, len = std::nextafter(len, inf)) {
      std::vector<Block> b{guard_block(len, 2000, 10000, 100, 100, 1e4), guard_block(0.5, 1000, 10000, 100, 100, 1e4)};
      for (int k = 0; k < 40; ++k) b.push_back(guard_block(0.5, 2000, 10000, 100, 100, 1e4));
      expect_group_verdicts(b, b.size(), 0, 40, step, 0, "on the reach, " + std::to_string(i));
      GuardScratch scratch(256);
      const GuardVerdict v = certificate_verdict(b, 40, step, scratch);
      if (i == 0) first_a = v.cert_a;
      both = both || v.cert_a != first_a;
      sharpened += scratch.sharpened;
    }
    EXPECT_TRUE(both) << "the block's start never crossed the ramp's reach";
    EXPECT_GT(sharpened, 0u) << "no block fell inside the bracket: the built ramp never decided";
  }
  // Seeded random windows: a few values of acceleration and jerk (as smoothed paths have), short
  // and long blocks, exact stops, states accelerating or braking beyond A.
  std::mt19937_64 rng(20261202);
  std::uniform_real_distribution<double> u(0, 1);
  for (int c = 0; c < 3000 && !HasFailure(); ++c) {
    const double a0 = 200 + 2000 * u(rng), j0 = 2000 + 20000 * u(rng);
    std::vector<Block> b;
    const std::size_t n = 8 + rng() % 120;
    for (std::size_t k = 0; k < n; ++k) {
      const double a = rng() % 4 == 0 ? a0 * (0.05 + u(rng)) : a0, j = rng() % 4 == 0 ? j0 * (0.05 + u(rng)) : j0;
      const double cap = 20 + 80 * u(rng);
      const double len = rng() % 3 == 0 ? 0.01 + 0.1 * u(rng) : 0.1 + 2 * u(rng);
      b.push_back(guard_block(len, a, j, cap, 100, rng() % 40 == 0 ? 0.0 : cap * cap * (0.2 + u(rng))));
    }
    const double v = std::min(b.front().v_cap_mm_s, 60 * u(rng)), acc = a0 * (3 * u(rng) - 2);
    const PathStep step = jerk_cycle({0, v, acc, 0}, j0 * (2 * u(rng) - 1), 0.001);
    expect_group_verdicts(b, n, b.front().length * u(rng), v, step, rng() % 100, "random window " + std::to_string(c));
  }
}

// The gated certificate's first stage (a brake to the gate block's speed w on the limits before
// it) must never fall below w on the way: from a hard brake (25 mm/s at −700 mm/s², 10 000 mm/s³)
// the ramp to w = 1 mm/s eases a to 0 only at 0.5 mm/s and comes back up. Accepted, such a state
// let the follower ease at the corner's jerk one cycle and ride the dip to near rest the next
// (engraving.ngc 62.279 s instead of 60.991 when the jerk gate came without this condition). The
// corner's lower jerk (3 000) in π's scan makes the plain certificate refuse, so only the gate
// could accept the state: it must not.
TEST(PlannerJerk, GatedBrakeNeverDipsBelowTheGateSpeed) {
  const auto verdict = [](double a0) {
    const PathStep step = jerk_cycle({0, 25 - a0 * 0.001, a0, 0}, 0, 0.001);
    std::vector<Block> b{guard_block(1.0 + step.x.s, 1000, 10000, 100, 100, 1e4),  // the run, 1 mm left
                         guard_block(0.05, 10, 3000, 1, 100, 1),                    // the corner, w = 1
                         guard_block(5, 1000, 10000, 100, 100, 1)};
    for (int k = 0; k < 8; ++k) b.push_back(guard_block(5, 1000, 10000, 100, 100, 1e4));
    GuardScratch scratch(64);
    return certificate_verdict(b, step.x.v, step, scratch);
  };
  const GuardVerdict dips = verdict(-700);  // eased at 10 000: 25 − 700²/20 000 = 0.5 mm/s < w
  EXPECT_TRUE(dips.failed() || dips.cert_w == 0) << "accepted through the gate, w = " << dips.cert_w;
  const GuardVerdict keeps = verdict(-300);  // 25 − 4.5: never below w, the gate may take it
  EXPECT_FALSE(keeps.failed());
}

// A closed curve of 500 points (a three-lobed loop rising and falling in Z) smoothed as the Channel
// does on a jerk-limited machine, every piece at `feed_mm_s`.
static std::vector<PathRequest> smoothed_trefoil(double feed_mm_s) {
  std::vector<core::Vec> pts;
  for (int k = 0; k <= 500; ++k) {
    const double a = 2 * std::numbers::pi * k / 500, r = 30 + 12 * std::sin(3 * a);
    pts.push_back(xyz(r * std::cos(a), r * std::sin(a), 1 - std::cos(a)));
  }
  std::vector<std::vector<Segment>> out;
  smooth_polyline(pts, PolylineSmoothing{}, out);
  std::vector<PathRequest> reqs;
  for (const auto& line : out)
    for (const auto& seg : line) reqs.push_back({seg, feed_mm_s, false, static_cast<std::uint32_t>(reqs.size())});
  return reqs;
}

TEST(PlannerJerk, CertificateGroupSkipsGiveTheSameSetpoints) {
  const auto lim = jerk_limits(200, 2000, 10000);
  const auto reqs = smoothed_trefoil(150);
  InterpolatorConfig groups, one_by_one, built;
  one_by_one.guard_index = false;
  built.guard_distance_bracket = false;
  std::uint64_t skipped = 0, skipped_off = 0;
  run_path(lim, reqs, 256, {}, [&](std::uint64_t, Interpolator& in) { skipped = in.guard_groups_skipped(); },
           20'000'000, groups);
  run_path(lim, reqs, 256, {}, [&](std::uint64_t, Interpolator& in) { skipped_off = in.guard_groups_skipped(); },
           20'000'000, one_by_one);
  EXPECT_GT(skipped, 1000u);
  EXPECT_EQ(skipped_off, 0u);
  expect_identical_runs(lim, reqs, groups, one_by_one, 0);
  // The same with the certificate's ramp built at every refresh of its distance instead of taken
  // in closed form where that decides.
  expect_identical_runs(lim, reqs, groups, built, 0);
}

// The guard's certificate (jerk_guard.hpp): on a smoothed CAM curve (the Channel's default for a
// jerk-limited machine: every piece has its own limits, so π's closed-form tail rarely applies) the
// default guard settles every step without a long simulation of π, every limit and P still hold, and
// the run costs little time against simulating π wherever the certificate cannot decide (4.2 %
// on this short path when written; the price on real programs is in docs/planner.md). With simulation allowed,
// the certificate still settles most steps and the run is no slower than simulating alone.
TEST(PlannerJerk, CertificateSettlesStepsWithoutSimulatingTheBrake) {
  const auto lim = jerk_limits(200, 2000, 10000);
  std::vector<core::Vec> pts;
  const auto reqs = smoothed_circle(pts);
  ASSERT_GT(reqs.size(), 100u);
  struct Count {
    std::uint64_t cycles = 0, sims = 0;
  };
  const auto run = [&](const InterpolatorConfig& ic, Count& n) {
    const auto hook = [&n](std::uint64_t, Interpolator& in) {
      n.cycles = in.jerk_cycles();
      n.sims = in.guard_simulations();
    };
    return run_path(lim, reqs, 4096, {}, hook, 20'000'000, ic);
  };
  InterpolatorConfig cert_only, cert_sim, sim_only;
  cert_sim.guard_simulate = true;
  sim_only.guard_certificate = false;
  Count a, b, c;
  const auto ra = run(cert_only, a);
  const auto rb = run(cert_sim, b);
  const auto rc = run(sim_only, c);
  for (const auto* r : {&ra, &rb, &rc}) {
    expect_within(*r, 1e-9, "run");  // the path is the smoothed curve itself
    EXPECT_EQ(r->end, pts.back());
  }
  ASSERT_GT(a.cycles, 1000u);
  EXPECT_LT(static_cast<double>(a.sims), 0.05 * static_cast<double>(a.cycles)) << a.sims << " of " << a.cycles;
  EXPECT_LT(static_cast<double>(b.sims), 0.75 * static_cast<double>(c.sims)) << b.sims << " vs " << c.sims;
  EXPECT_GE(c.sims, c.cycles);  // every first candidate that passes its own check is simulated
  EXPECT_LE(static_cast<double>(ra.cycles), 1.05 * static_cast<double>(rc.cycles)) << ra.cycles << " vs " << rc.cycles;
  EXPECT_LE(static_cast<double>(rb.cycles), 1.01 * static_cast<double>(rc.cycles));
}

// The certificate on blocks of very different accelerations (fast X runs into legs that lean on a
// weak Y axis, blended): limits hold, and the run keeps up with simulating the brake (2.9 % slower
// when written).
TEST(PlannerJerk, CertificateKeepsUpWhereTheAccelerationChanges) {
  // A high jerk: the brake (v²/2A) reaches farther than the blocks whose acceleration the step
  // itself is held to (those reached before |a| can be brought to 0, about v·2A/J).
  auto lim = jerk_limits(200, 2000, 400000);
  lim.axis[1].a_max_mm_s2 = 300;
  const double c = std::cos(std::numbers::pi / 3), sn = std::sin(std::numbers::pi / 3);
  std::vector<PathRequest> reqs;
  core::Vec at = xyz(0, 0);
  for (int k = 0; k < 6; ++k) {  // zig-zag: X runs and Y-heavy legs, blended
    const core::Vec a = at, b = xyz(at[0] + 40, at[1]), e = xyz(b[0] + 8 * c, b[1] + (k % 2 ? -8 : 8) * sn);
    reqs.push_back(line_req(a, b, 200, static_cast<std::uint32_t>(2 * k), 0.05));
    reqs.push_back(line_req(b, e, 200, static_cast<std::uint32_t>(2 * k + 1), 0.05));
    at = e;
  }
  InterpolatorConfig cert_only, sim_only;
  sim_only.guard_certificate = false;
  const auto rc = run_path(lim, reqs, 256, {}, {}, 20'000'000, cert_only);
  const auto rs = run_path(lim, reqs, 256, {}, {}, 20'000'000, sim_only);
  expect_within(rc, 0.05, "certificate");
  expect_within(rs, 0.05, "simulation");
  EXPECT_EQ(rc.end, at);
  EXPECT_LE(static_cast<double>(rc.cycles), 1.05 * static_cast<double>(rs.cycles)) << rc.cycles << " vs " << rs.cycles;
}

// A block of 1.8 µm between two exact stops (as a CAM polyline's seam gave): at rest before it, the
// only way on is the position-mode stop onto its end, whose certified ramp ends exactly on that stop.
// Reaching a stop at rest is allowed (crossing it is not); before, the certificate refused it and
// the path stood still there for ever.
TEST(PlannerJerk, CertificateLetsTheBrakeEndExactlyOnAStop) {
  const auto lim = jerk_limits(100, 1000, 10000);
  const double h = 1.8e-6;
  std::vector<PathRequest> reqs{line_req(xyz(0, 0), xyz(10, 0), 100, 0, 0.0), line_req(xyz(10, 0), xyz(10, h), 100, 1, 0.0),
                                line_req(xyz(10, h), xyz(0, h), 100, 2, 0.0)};
  const auto res = run_path(lim, reqs, 16, {}, {}, 100'000);  // 20 mm of moves: a few seconds
  expect_within(res, 1e-9, "stops");
  EXPECT_EQ(res.end, xyz(0, h));
}

// The guard keeps its index of the window from cycle to cycle (GuardScratch) while the blocks stay
// where they are. It must follow every change a block can see: a commit lowers the jerk of the
// block before it where the curvature jumps (line into a tangent arc: Planner::commit), blocks are
// popped and cleared, the override and the stop scale change. After each, what the guard reads is
// what the blocks say.
TEST(PlannerJerk, GuardIndexFollowsTheWindow) {
  const auto lim = jerk_limits(100, 1000, 20000);
  Planner planner(lim, 64);
  auto& ring = planner.queue().ring();
  GuardScratch scratch(ring.capacity());
  const auto expect_reads_blocks = [&](double scale, double feed_override, const char* when) {
    if (ring.empty()) return;  // the first block is still pending
    const JerkGuard guard(ring, ring.size(), 0, 0, lim.period_s, scale, false, feed_override, scratch);
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const Block& b = ring.at(k);
      const double j = std::isfinite(b.j_mm_s3) ? b.j_mm_s3 : b.a_mm_s2 / lim.period_s;
      EXPECT_EQ(guard.jerk(k), j * scale) << when << ", block " << k;
      EXPECT_EQ(guard.acc(k), b.a_mm_s2 * scale) << when << ", block " << k;
      EXPECT_EQ(guard.soft(k), std::min(soft_speed(b, feed_override), b.v_split_mm_s)) << when << ", block " << k;
    }
    double a_min = 0, j_min = 0;
    guard.limits_until(1e9, a_min, j_min);  // reads every block (and their starts) to the first stop
    EXPECT_GT(j_min, 0) << when;
  };
  const std::vector<PathRequest> reqs{
      line_req(xyz(0, 0), xyz(30, 0), 80, 0, 0.0),
      // Tangent: the curvature jumps (a curve with plain jerk shares: the step's share comes off
      // its jerk when the line after it is committed).
      arc_req(make_cubic_bezier(xyz(30, 0), xyz(40, 0), xyz(50, 10), xyz(50, 20)), 80, 1),
      line_req(xyz(50, 20), xyz(50, 50), 80, 2, 0.0),
      arc_req(make_arc(xyz(50, 50), xyz(30, 70), 0, 1, 30, 50, 1), 80, 3),
      line_req(xyz(30, 70), xyz(0, 70), 80, 4, 0.0)};
  bool lowered = false;  // a commit lowered the jerk of a block the guard had indexed
  for (const auto& r : reqs) {
    std::vector<double> before;
    for (std::size_t k = 0; k < ring.size(); ++k) before.push_back(ring.at(k).j_mm_s3);
    ASSERT_EQ(planner.push(r), PlanResult::Ok);
    for (std::size_t k = 0; k < before.size(); ++k) lowered = lowered || ring.at(k).j_mm_s3 < before[k];
    expect_reads_blocks(1.0, 1.0, "after a push");
  }
  planner.flush();
  expect_reads_blocks(1.0, 1.0, "after the flush");
  EXPECT_TRUE(lowered);
  ring.pop();
  expect_reads_blocks(1.0, 1.0, "after a pop");
  ring.pop();
  ASSERT_EQ(planner.push(line_req(xyz(0, 70), xyz(0, 0), 60, 5, 0.0)), PlanResult::Ok);
  planner.flush();
  expect_reads_blocks(1.0, 1.0, "after a pop and a push (as many blocks as before)");
  expect_reads_blocks(0.5, 1.0, "with the emergency scale");
  expect_reads_blocks(0.5, 0.3, "with another override");
  const std::size_t size = ring.size();
  planner.queue().clear();
  for (std::uint32_t k = 0; ring.size() < size; ++k)  // another path, as many blocks
    ASSERT_EQ(planner.push(line_req(xyz(k, k), xyz(k + 1, k + 1 + k % 2), 50, k, 0.0)), PlanResult::Ok);
  expect_reads_blocks(1.0, 1.0, "after a clear and new pushes");
}

// The index is kept by position (GuardScratch::origin): a pop moves the front on in it and indexes
// nothing again, and what the guard reads stays what the blocks say through thousands of pushes and
// pops, across the index's new beginnings (its origin a window's length on, or the front 64 mm from
// it) and with exact stops in the window. Before, every pop indexed the whole reach again.
TEST(PlannerJerk, GuardIndexMovesOnWithThePops) {
  auto lim = jerk_limits(100, 1000, 20000);
  for (int i = 0; i < 3; ++i) lim.axis[i].min_mm = -1e6, lim.axis[i].max_mm = 1e6;
  Planner planner(lim, 32);
  auto& ring = planner.queue().ring();
  GuardScratch scratch(ring.capacity());
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> len(0.2, 3), turn(-0.8, 0.8), unit(0, 1);
  core::Vec at = xyz(0, 0);
  double heading = 0;
  std::uint32_t tag = 0;
  std::uint64_t pushes = 0, pop_only_checks = 0, begins = 0;
  for (int step = 0; step < 4000; ++step) {
    const bool push = !planner.queue().full() && (ring.size() < 2 || unit(rng) < 0.5);
    if (push) {
      heading += turn(rng);
      // One line in four is long: without a new beginning 64 mm on, the starts read as differences
      // from the origin would lose the picometres the guard's comparisons keep.
      const double l = unit(rng) < 0.25 ? 200 + 1800 * unit(rng) : len(rng);
      const core::Vec to = xyz(at[0] + l * std::cos(heading), at[1] + l * std::sin(heading));
      // One move in ten is an exact stop (G61): a stop in the index.
      ASSERT_EQ(planner.push(line_req(at, to, 60 + 40 * unit(rng), tag++, unit(rng) < 0.1 ? 0.0 : 0.05)), PlanResult::Ok);
      at = to;
      ++pushes;
    } else {
      ring.pop();
    }
    if (ring.empty()) continue;
    const std::uint64_t indexed = scratch.blocks_indexed;
    const double s_front = 0.5 * ring.front().length;
    const JerkGuard guard(ring, ring.size(), s_front, 0, lim.period_s, 1.0, false, 1.0, scratch);
    if (!push && scratch.origin > 0) {  // popped, the index kept: the blocks it had are read as they were
      const std::size_t had = scratch.built - scratch.origin;
      for (std::size_t k = 0; k < had; ++k) guard.acc(k);
      EXPECT_EQ(scratch.blocks_indexed, indexed) << "step " << step << ": a pop indexed blocks again";
      ++pop_only_checks;
    }
    begins += scratch.origin == 0 ? 1 : 0;
    double s = -s_front;
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const Block& b = ring.at(k);
      const double j = std::isfinite(b.j_mm_s3) ? b.j_mm_s3 : b.a_mm_s2 / lim.period_s;
      ASSERT_EQ(guard.jerk(k), j) << "step " << step << ", block " << k;
      ASSERT_EQ(guard.acc(k), b.a_mm_s2) << "step " << step << ", block " << k;
      ASSERT_EQ(guard.soft(k), k == 0 ? std::max(0.0, std::min(soft_speed(b, 1.0), b.v_split_mm_s))
                                      : std::min(soft_speed(b, 1.0), b.v_split_mm_s))
          << "step " << step << ", block " << k;
      // To the rounding of the start itself (and of the 64 mm the origin may lie behind the front).
      ASSERT_NEAR(guard.start_of(k), s, 1e-14 * (GuardScratch::kRebase_mm + s_front + std::abs(s)))
          << "step " << step << ", block " << k;
      s += b.length;
    }
    double a_min = 0, j_min = 0;
    guard.limits_until(1e9, a_min, j_min);  // the stops, through the index's stop list
    double a_ref = ring.at(0).a_mm_s2, j_ref = guard.jerk(0);
    for (std::size_t k = 1; k < ring.size() && ring.at(k).v2_junction > 0; ++k) {
      a_ref = std::min(a_ref, ring.at(k).a_mm_s2);
      j_ref = std::min(j_ref, guard.jerk(k));
    }
    ASSERT_EQ(a_min, a_ref) << "step " << step;
    ASSERT_EQ(j_min, j_ref) << "step " << step;
  }
  EXPECT_GT(pop_only_checks, 500u);
  EXPECT_GT(begins, 10u);  // the index began again many times (origin past the window, 64 mm on)
  EXPECT_GT(pop_only_checks, begins);  // and most pops kept it
  // Each block is indexed once, the old back once more after each push (its jerk may have been
  // lowered), and a window's worth at each new beginning; before, a window's worth after every pop.
  EXPECT_LE(scratch.blocks_indexed, 2 * pushes + begins * ring.capacity());
}

// Approaching an exact stop, the follower's position-mode stop (Otg1's peak-speed search) is solved
// once and sampled on while it is taken cycle after cycle (StopPlan: the rest of a time-optimal stop
// is the time-optimal stop from where it has got to): the setpoints are those of solving it every
// cycle to within the search's rounding, the stops land exactly on their points, and fewer than half
// as many plans are solved.
TEST(PlannerJerk, AStopPlanIsSampledOnWhileItIsTaken) {
  const auto lim = jerk_limits(100, 1000, 10'000);
  std::vector<PathRequest> reqs;
  const core::Vec pts[] = {xyz(0, 0), xyz(20, 0), xyz(20, 15), xyz(3, 15), xyz(3, 2), xyz(11, 7)};
  for (std::uint32_t k = 0; k + 1 < std::size(pts); ++k)
    reqs.push_back(line_req(pts[k], pts[k + 1], 60 + 10 * k, k, 0.0));  // G61: a stop at every corner
  std::uint64_t solves[2] = {0, 0}, reuses[2] = {0, 0};
  std::vector<core::Vec> trace[2];
  RunResult res[2];
  for (int keep = 0; keep < 2; ++keep) {
    InterpolatorConfig ic;
    ic.keep_stop_plan = keep == 1;
    const auto hook = [&](std::uint64_t, Interpolator& in) {
      solves[keep] = in.stop_plan().solves();
      reuses[keep] = in.stop_plan().reuses();
    };
    res[keep] = run_path(lim, reqs, 64, {}, hook, 20'000'000, ic, &trace[keep]);
    expect_within(res[keep], 0.0, keep ? "plans kept" : "plans solved every cycle");
    EXPECT_EQ(res[keep].end, reqs.back().geom.end);
  }
  EXPECT_EQ(reuses[0], 0u);
  EXPECT_GT(solves[0], 100u);
  // (Where the follower takes another candidate, the plan is dropped: about a third of the time here.)
  EXPECT_GT(reuses[1], solves[1]) << solves[1] << " solved, " << reuses[1] << " sampled on";
  EXPECT_LT(2 * solves[1], solves[0]) << solves[1] << " solved, against " << solves[0];
  ASSERT_EQ(trace[0].size(), trace[1].size());
  double worst = 0;
  for (std::size_t k = 0; k < trace[0].size(); ++k) worst = std::max(worst, core::norm(trace[0][k] - trace[1][k]));
  EXPECT_LT(worst, 1e-9);
}

// A run whose candidates were all refused from some cycle on (its fallback brake ran to rest): every
// axis within its speed, acceleration and jerk, every setpoint within P, and every block's own
// limits kept on the way.
static void expect_brake_run_within(const RunResult& res, double tol, const std::string& what) {
  ASSERT_EQ(res.error, PlanResult::Ok) << what;
  EXPECT_TRUE(res.fig.finite) << what;
  EXPECT_LE(res.fig.v_ratio, 1 + kRatioNoise) << what << ": " << res.fig.describe();
  EXPECT_LE(res.fig.a_ratio, 1 + kRatioNoise) << what << ": " << res.fig.describe();
  EXPECT_LE(res.fig.j_ratio, 1 + kRatioNoise) << what << ": " << res.fig.describe();
  EXPECT_LE(res.fig.deviation_mm, tol + 1e-9) << what << ": " << res.fig.describe();
  EXPECT_LE(res.block_v_ratio, 1 + 1e-9) << what;
  EXPECT_LE(res.block_a_ratio, 1 + 1e-6) << what;
  EXPECT_LE(res.block_j_ratio, 1 + 1e-4) << what;
}

// The fallback brake the interpolator keeps (the plain certificate's ramp to rest, or the gated
// one: ramp to a gate's speed, then to rest from past the gate) is only run for a cycle or two in
// normal runs. Refusing every candidate from a chosen cycle on (InterpolatorConfig::
// guard_refuse_from_cycle) makes it run to rest from wherever the follower was: every axis must stay
// within its speed, acceleration and jerk, and every setpoint within P, all the way.
TEST(PlannerJerk, TheKeptFallbackBrakeRunsToRestWithinEveryLimit) {
  std::uint64_t gated_runs = 0;
  for (std::uint64_t seed = 1; seed <= 120; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const MachineLimits lim = random_jerk_limits(rng, u);
    const double tol = std::array{0.01, 0.05, 0.2}[rng() % 3];
    const auto reqs = tangent_chain(rng, u, tol);
    InterpolatorConfig ic;
    ic.guard_refuse_from_cycle = static_cast<long long>(20 + rng() % 3000);
    bool gated = false;
    const auto hook = [&](std::uint64_t c, Interpolator& in) {
      if (static_cast<long long>(c) == ic.guard_refuse_from_cycle) gated = in.fallback().cert_a2 > 0;
    };
    const auto res = run_path(lim, reqs, 3 + rng() % 200, {}, hook, ic.guard_refuse_from_cycle + 8000, ic);
    expect_brake_run_within(res, tol, "seed " + std::to_string(seed));
    gated_runs += gated;
    if (HasFailure()) break;
  }
  EXPECT_GT(gated_runs, 5u);  // some of them ran a gated brake
}

// Refusing every candidate (InterpolatorConfig::guard_refuse_from_cycle) from cycles whose step a
// cruise certificate settled, on seeded tangent chains: the fallback brake then runs to rest from
// there, and must keep every limit (expect_brake_run_within). `varied`: periods of 0.25–2 ms,
// windows from 2 blocks, exact stops now and then, overrides, P-8 feed limits, holds and enable
// drops on the way, and half the refusals from the last cycle of a stretch. Returns the refusals
// that came within a certificate.
static std::uint64_t expect_cruise_fallbacks_within(std::uint64_t seeds, bool varied) {
  std::uint64_t within = 0;
  for (std::uint64_t seed = 1; seed <= seeds && !::testing::Test::HasFailure(); ++seed) {
    std::mt19937_64 rng(seed + (varied ? 9000 : 7000));
    std::uniform_real_distribution<double> u(0, 1);
    MachineLimits lim = random_jerk_limits(rng, u);
    if (varied) lim.period_s = std::array{0.00025, 0.0005, 0.001, 0.002}[rng() % 4];
    const double tol = std::array{0.01, 0.05, 0.2}[rng() % 3];
    auto reqs = tangent_chain(rng, u, tol);
    std::size_t window = 3 + rng() % 200;
    struct Event {
      std::uint64_t cycle;
      int kind;
      double value;  // 1: back to normal
    };
    std::vector<Event> events;
    if (varied) {
      for (auto& r : reqs)
        if (rng() % 6 == 0) r.tolerance_mm = 0;  // G61: an exact stop at its end
      window = std::array<std::size_t, 7>{2, 3, 4, 8, 16, 3 + rng() % 40, window}[rng() % 7];
      for (int e = 0; e < 4 && rng() % 2 == 0; ++e) {
        const auto c = static_cast<std::uint64_t>(u(rng) * 3000);
        events.push_back({c, e, std::array{0.0, 0.5, 1.2, 2.0}[rng() % 4]});
        events.push_back({c + 50 + rng() % 500, e, 1});
      }
    }
    const auto apply = [&](std::uint64_t c, Interpolator& in) {
      for (const auto& e : events) {
        if (e.cycle != c) continue;
        const bool back = e.value == 1;
        const double inf = std::numeric_limits<double>::infinity();
        if (e.kind == 0) in.set_feed_override(e.value);
        if (e.kind == 1) in.set_speed_limits(back ? inf : 5 + 100 * e.value, inf);
        if (e.kind == 2) in.set_feed_hold(!back);
        if (e.kind == 3) in.set_motion_enable(back);
      }
    };
    std::vector<std::uint64_t> settled, last;  // cycles a certificate settled, the last of each stretch
    std::uint64_t hits = 0;
    bool was = false;
    const auto find = [&](std::uint64_t c, Interpolator& in) {
      apply(c, in);
      const bool now = in.cruise_cycles_certified() != hits;  // the step of cycle c − 1
      if (now) settled.push_back(c);
      if (!now && was) last.push_back(c - 1);
      was = now;
      hits = in.cruise_cycles_certified();
    };
    run_path(lim, reqs, window, {}, find, 3'000'000);
    if (settled.empty()) continue;
    for (int pick = 0; pick < (varied ? 4 : 3); ++pick) {
      InterpolatorConfig ic;
      const auto& from = varied && pick % 2 == 1 && !last.empty() ? last : settled;
      ic.guard_refuse_from_cycle = static_cast<long long>(from[rng() % from.size()]);
      bool from_cruise = false;
      std::uint64_t seen = 0;
      const auto hook = [&](std::uint64_t c, Interpolator& in) {
        apply(c, in);
        if (static_cast<long long>(c) == ic.guard_refuse_from_cycle) from_cruise = in.cruise_cycles_certified() != seen;
        seen = in.cruise_cycles_certified();
      };
      const auto res = run_path(lim, reqs, window, {}, hook, ic.guard_refuse_from_cycle + 8000, ic);
      expect_brake_run_within(res, tol,
                              "seed " + std::to_string(seed) + ", refused from " + std::to_string(ic.guard_refuse_from_cycle));
      within += from_cruise;
    }
  }
  return within;
}

// A cruise certificate (InterpolatorConfig::guard_cruise_cycles) settles up to 16 cycles of cruise
// at once; the fallback brake it leaves (the ramp to rest with limits no higher than every block
// the cruise passes) must be safe from every cycle within it, as from any other accepted state.
TEST(PlannerJerk, TheFallbackBrakeOfACruiseCertificateRunsToRestWithinEveryLimit) {
  EXPECT_GT(expect_cruise_fallbacks_within(60, false), 60u);  // most refusals came within a certificate
}

// The same with other periods, short windows, exact stops and PLC events on the way (which begin the
// guard's index again: a certificate must not outlive them).
TEST(PlannerJerk, TheFallbackBrakeOfACruiseCertificateKeepsItsLimitsThroughEventsAndStops) {
  EXPECT_GT(expect_cruise_fallbacks_within(40, true), 60u);
}

// On a smoothed CAM curve at a feed below its caps most cycles cruise: with cruise certificates
// only about one cycle in 16 walks the blocks ahead, and the setpoints are the ones certifying
// every cycle gives, to the bit (the fallback brakes differ, but neither is run here).
TEST(PlannerJerk, CruiseCertificatesGiveTheSameSetpointsAsCertifyingEveryCycle) {
  const auto lim = jerk_limits(200, 2000, 10000);
  const auto reqs = smoothed_trefoil(40);
  InterpolatorConfig cruise, every;
  every.guard_cruise_cycles = 0;
  std::uint64_t cycles = 0, hits = 0, verifies = 0, verifies_every = 0;
  run_path(lim, reqs, 256, {}, [&](std::uint64_t c, Interpolator& in) {
    cycles = c;
    hits = in.cruise_cycles_certified();
    verifies = in.guard_verifies();
  }, 20'000'000, cruise);
  run_path(lim, reqs, 256, {}, [&](std::uint64_t, Interpolator& in) { verifies_every = in.guard_verifies(); },
           20'000'000, every);
  EXPECT_GT(hits, cycles / 2) << "cycles settled by a cruise certificate, of " << cycles;
  EXPECT_LT(verifies, verifies_every / 3);
  expect_identical_runs(lim, reqs, cruise, every, 0);
}

// JerkGuard::brake_distance advances plan_ramp's phases without building the whole ramp (its speeds
// and |a| bounds) where no phase 0 brings |a| down first: the same distance to the bit as the ramp
// built (brake_distance_built), accelerating and braking, |a| up to and beyond the limit, near rest,
// and braking so hard already that the ramp reverses.
TEST(PlannerJerk, BrakeDistanceIsTheBuiltRampsToTheBit) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(0, 1);
  int lean = 0;
  for (int i = 0; i < 20000; ++i) {
    const double a = 10 + 4000 * unit(rng), j = 100 + 50000 * unit(rng);
    const double v = i % 10 == 0 ? 1e-6 * unit(rng) : 200 * unit(rng);
    const double x_a = (2 * unit(rng) - 1) * a * (i % 7 == 0 ? 1.5 : 1.0);
    const ProfileState x{0, v, i % 11 == 0 ? (i % 2 ? a : -a) : x_a, 0};
    const double d = JerkGuard::brake_distance(x, a, j), e = JerkGuard::brake_distance_built(x, a, j);
    ASSERT_TRUE(d == e || (std::isnan(d) && std::isnan(e))) << i << ": v " << v << " a0 " << x.a << " A " << a << " J " << j;
    lean += std::abs(x.a) <= a;
  }
  EXPECT_GT(lean, 15000);
}
