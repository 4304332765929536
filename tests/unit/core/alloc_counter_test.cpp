// The allocation counter the cycle tests rely on really counts (so those tests can fail).
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "alloc_counter.hpp"

TEST(AllocCounter, CountsEveryAllocation) {
  const long before = softmc::testing::allocation_count();
  auto p = std::make_unique<int>(3);
  std::vector<double> v(100);
  EXPECT_EQ(softmc::testing::allocation_count() - before, 2);
  EXPECT_EQ(*p + static_cast<int>(v.size()), 103);
}
