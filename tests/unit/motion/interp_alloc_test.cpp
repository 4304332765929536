// The cycle is sacred: planning pushes and interpolation steps allocate nothing once configured.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "planner_run.hpp"

namespace {
std::atomic<long> g_allocs{0};
}  // namespace

// Counts every allocation made in this test executable (test_motion).
void* operator new(std::size_t n) {
  g_allocs.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

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
  const long before = g_allocs.load();
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
  EXPECT_EQ(g_allocs.load() - before, 0) << "allocations in " << cycles << " cycles";
  EXPECT_GT(cycles, 300);
}
