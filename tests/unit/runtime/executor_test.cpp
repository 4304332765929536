// The virtual-clock executor: fixed order, exact time, no drift.
#include <gtest/gtest.h>

#include "runtime/executor.hpp"

using namespace softmc::runtime;

TEST(VirtualExecutor, RunsFunctionsInOrderEachCycle) {
  VirtualExecutor ex(0.001);
  std::string log;
  ex.add("read", [&](const CycleClock&) { log += 'r'; });
  ex.add("update", [&](const CycleClock&) { log += 'u'; });
  ex.add("write", [&](const CycleClock&) { log += 'w'; });
  ex.step();
  ex.step();
  EXPECT_EQ(log, "ruwruw");
  EXPECT_EQ(ex.order(), (std::vector<std::string>{"read", "update", "write"}));
}

TEST(VirtualExecutor, TimeIsCycleTimesPeriodWithoutDrift) {
  VirtualExecutor ex(0.001);
  double last_t = -1;
  ex.add("probe", [&](const CycleClock& c) { last_t = c.t_s; });
  const auto n = ex.run_until([] { return false; }, 1000000);
  EXPECT_EQ(n, 1000000u);
  EXPECT_EQ(last_t, 999999 * 0.001);  // exact: computed, not accumulated
}

TEST(VirtualExecutor, RunUntilStopsWhenDone) {
  VirtualExecutor ex(0.01);
  int k = 0;
  ex.add("count", [&](const CycleClock&) { ++k; });
  EXPECT_EQ(ex.run_until([&] { return k == 7; }, 100), 7u);
  EXPECT_THROW(VirtualExecutor(0), std::invalid_argument);
}
