// The cycle is sacred: planning pushes and interpolation steps allocate nothing once configured.
#include <gtest/gtest.h>

#include "alloc_counter.hpp"


#include "planner_run.hpp"


using namespace softmc;
using namespace softmc::motion;
using namespace softmc::motion::testing;

TEST(InterpAlloc, PushFlushAndStepAllocateNothing) {
  const auto lim = xyz_limits(200, 1000);
  std::vector<PathRequest> reqs;
  for (int k = 0; k < 3000; ++k) {
    const double a = k * 0.01;
    reqs.push_back(line_req(xyz(std::cos(a) * 10 - 10 * (k ? 1 : 1), std::sin(a) * 10),
                            xyz(std::cos(a + 0.01) * 10 - 10, std::sin(a + 0.01) * 10), 100,
                            static_cast<std::uint32_t>(k)));
  }
  for (std::size_t k = 1; k < reqs.size(); ++k) reqs[k].geom = make_line(reqs[k - 1].geom.end, reqs[k].geom.end);
  Planner planner(lim, 256);
  Interpolator in(planner.queue(), reqs.front().geom.start);
  const long before = softmc::testing::allocation_count();
  std::size_t next = 0;
  long cycles = 0;
  for (; cycles < 1'000'000; ++cycles) {
    while (next < reqs.size() && !planner.queue().full()) ASSERT_EQ(planner.push(reqs[next++]), PlanResult::Ok);
    if (next == reqs.size()) planner.flush();
    if (cycles == 100) in.set_feed_override(0.7);
    if (cycles == 200) in.set_feed_hold(true);
    if (cycles == 400) in.set_feed_hold(false);
    if (next == reqs.size() && in.idle()) break;
    in.step(0.001);
  }
  EXPECT_EQ(softmc::testing::allocation_count() - before, 0) << "allocations in " << cycles << " cycles";
  EXPECT_GT(cycles, 300);
}

// Under a jerk limit the planner builds Poly blends inside push (a quintic at each sharp line
// corner, a quintic where a line meets an arc at an angle or tangentially): their arc-length
// tables, limits and bounding boxes allocate nothing either (the bounding box's branch and bound
// once used a growing std::vector).
TEST(InterpAlloc, PushingCornersThatGetQuinticBlendsAllocatesNothing) {
  auto lim = xyz_limits(100, 1000);
  for (int i = 0; i < 3; ++i) lim.axis[i].j_max_mm_s3 = 10000;
  std::vector<PathRequest> reqs;
  core::Vec at = xyz(0, 0);
  for (int k = 0; k < 40; ++k) {
    const core::Vec a = at + xyz(5, 0), b = a + xyz(0, 5);  // 90° line corner: a quintic
    reqs.push_back(line_req(at, a, 100, static_cast<std::uint32_t>(3 * k), 0.05));
    reqs.push_back(line_req(a, b, 100, static_cast<std::uint32_t>(3 * k + 1), 0.05));
    // A line into a tangent R2 quarter arc and on along its end tangent: a fillet (one quintic
    // from line to line, Planner::fillet), the arc held until the next line arrives.
    PathRequest arc = arc_req(make_arc(b, b + xyz(2, 2), 0, 1, b[0] + 2, b[1], -1), 100, static_cast<std::uint32_t>(3 * k + 2));
    arc.tolerance_mm = 0.05;
    reqs.push_back(arc);
    at = arc.geom.end;
  }
  PlannerConfig pc;  // every corner blended (these would be stops: docs/planner.md, "Blend or stop")
  pc.corner_stop_when_quicker = false;
  Planner planner(lim, 512, pc);
  const long before = softmc::testing::allocation_count();
  for (const auto& r : reqs) ASSERT_EQ(planner.push(r), PlanResult::Ok);
  planner.flush();
  EXPECT_EQ(softmc::testing::allocation_count() - before, 0);
  std::size_t poly = 0, arcs = 0;
  for (std::size_t k = 0; k < planner.queue().ring().size(); ++k) {
    poly += planner.queue().ring().at(k).seg.kind == SegmentKind::Poly;
    arcs += planner.queue().ring().at(k).seg.kind == SegmentKind::Arc;
  }
  EXPECT_GT(poly, 60u);  // the blends this is about were built
  EXPECT_LE(arcs, 1u);   // and the fillets (the last arc has no line after it)
}
