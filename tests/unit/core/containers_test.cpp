// Ring, SPSC queue, snapshot, diagnostics.
#include <gtest/gtest.h>

#include <thread>

#include "core/axes.hpp"
#include "core/diagnostic.hpp"
#include "core/ring.hpp"
#include "core/snapshot.hpp"
#include "core/spsc_queue.hpp"

using namespace softmc::core;

TEST(Ring, FifoWrapsAroundAndReportsFull) {
  Ring<int> r(3);
  EXPECT_TRUE(r.push(1));
  EXPECT_TRUE(r.push(2));
  EXPECT_TRUE(r.push(3));
  EXPECT_FALSE(r.push(4));
  EXPECT_EQ(r.front(), 1);
  r.pop();
  EXPECT_TRUE(r.push(4));
  EXPECT_EQ(r.at(2), 4);
  EXPECT_EQ(r.back(), 4);
  r.pop();
  r.pop();
  EXPECT_EQ(r.front(), 4);
  EXPECT_EQ(r.size(), 1u);
}

// changes() counts pops and clears, pops() pops alone: a reader that finds both moved by the same
// amount knows the elements were only popped, and where each one it had seen is now.
TEST(Ring, PopsAreCountedApartFromClears) {
  Ring<int> r(4);
  r.push(1);
  r.push(2);
  r.push(3);
  const auto c0 = r.changes(), p0 = r.pops();
  r.pop();
  r.pop();
  EXPECT_EQ(r.pops() - p0, 2u);
  EXPECT_EQ(r.changes() - c0, 2u);
  r.clear();
  EXPECT_EQ(r.pops() - p0, 2u);
  EXPECT_EQ(r.changes() - c0, 3u);
}

TEST(SpscQueue, TransfersInOrderAcrossThreads) {
  SpscQueue<int> q(16);
  constexpr int kN = 100000;
  std::thread producer([&] {
    for (int i = 0; i < kN;)
      if (q.push(i)) ++i;
  });
  int expected = 0;
  while (expected < kN)
    if (auto v = q.pop()) {
      ASSERT_EQ(*v, expected);
      ++expected;
    }
  producer.join();
  EXPECT_FALSE(q.pop());
}

TEST(Snapshot, ReaderNeverSeesATornValue) {
  struct Pair {
    long a, b;
  };
  Snapshot<Pair> s;
  std::atomic<bool> stop{false};
  std::thread writer([&] {
    for (long i = 0; !stop; ++i) s.publish({i, -i});
  });
  for (int i = 0; i < 200000; ++i) {
    const auto p = s.read();
    ASSERT_EQ(p.a, -p.b);
  }
  stop = true;
  writer.join();
}

TEST(Diagnostic, FormatsFileLineColumn) {
  Diagnostic d{"part.ngc", 12, 5, Severity::Error, "feed rate missing"};
  EXPECT_EQ(d.format(), "part.ngc:12:5: error: feed rate missing");
}

TEST(Axes, LettersMapToIndices) {
  EXPECT_EQ(axis_from_letter('x'), 0u);
  EXPECT_EQ(axis_from_letter('U'), 6u);
  EXPECT_FALSE(axis_from_letter('Q'));
  Vec a;
  a[0] = 3;
  a[1] = 4;
  EXPECT_DOUBLE_EQ(norm(a), 5);
}
