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
