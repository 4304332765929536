// core::ordered_parallel: jobs on several threads, their results handed over in order on the caller's.
#include "core/ordered_parallel.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace softmc;

// Every job is worked once and handed over once, in order, on the caller's thread; never more than
// `ahead` jobs are taken beyond the next one to hand over, however slow that one is.
TEST(OrderedParallel, EveryJobOnceHandedOverInOrderWithinAhead) {
  for (const std::size_t threads : {1u, 2u, 4u, 7u}) {
    SCOPED_TRACE(threads);
    constexpr std::size_t kJobs = 300, kAhead = 5;
    std::vector<std::atomic<int>> worked(kJobs);
    std::vector<int> given;
    std::atomic<std::size_t> taken_max{0};
    std::atomic<std::size_t> next_give{0};
    const auto caller = std::this_thread::get_id();
    core::ordered_parallel(
        kJobs, threads, kAhead,
        [&](std::size_t k) {
          ++worked[k];
          std::size_t seen = taken_max.load();
          while (k > seen && !taken_max.compare_exchange_weak(seen, k)) {
          }
          // taken only within max(ahead, threads) of the next to hand over (next_give here lags the
          // hand-over being made by one)
          EXPECT_LE(k, next_give.load() + std::max<std::size_t>(kAhead, 4 * threads));
          if (k % 37 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));  // a slow one
        },
        [&](std::size_t k) {
          EXPECT_EQ(std::this_thread::get_id(), caller);
          given.push_back(static_cast<int>(k));
          next_give = k + 1;
        });
    ASSERT_EQ(given.size(), kJobs);
    for (std::size_t k = 0; k < kJobs; ++k) {
      EXPECT_EQ(given[k], static_cast<int>(k));
      EXPECT_EQ(worked[k].load(), 1) << k;
    }
  }
}

// An exception from a job or from a hand-over reaches the caller once every thread has stopped, as
// on one thread: every job before the first failing one is handed over, none after it, and the
// error is the first failing job's even when a later one failed sooner.
TEST(OrderedParallel, AnErrorInAJobOrAHandOverReachesTheCaller) {
  for (const std::size_t threads : {1u, 3u}) {
    std::vector<int> given;
    EXPECT_THROW(core::ordered_parallel(
                     100, threads, 4,
                     [&](std::size_t k) {
                       if (k == 40) throw std::runtime_error("job 40");
                     },
                     [&](std::size_t k) { given.push_back(static_cast<int>(k)); }),
                 std::runtime_error);
    ASSERT_EQ(given.size(), 40u);  // 0 … 39, not the failed one nor any after it
    EXPECT_EQ(given.back(), 39);
    given.clear();
    try {
      core::ordered_parallel(
          100, threads, 30,
          [&](std::size_t k) {
            if (k == 20) {
              std::this_thread::sleep_for(std::chrono::milliseconds(20));
              throw std::runtime_error("job 20");
            }
            if (k == 25) throw std::runtime_error("job 25");
          },
          [&](std::size_t k) { given.push_back(static_cast<int>(k)); });
      ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "job 20");
    }
    EXPECT_EQ(given.size(), 20u);
    given.clear();
    EXPECT_THROW(core::ordered_parallel(
                     100, threads, 4, [](std::size_t) {},
                     [&](std::size_t k) {
                       if (k == 10) throw std::logic_error("hand-over 10");
                       given.push_back(static_cast<int>(k));
                     }),
                 std::logic_error);
    EXPECT_EQ(given.size(), 10u);
  }
  std::size_t n = 0;
  core::ordered_parallel(0, 4, 4, [](std::size_t) {}, [&](std::size_t) { ++n; });  // no jobs
  EXPECT_EQ(n, 0u);
}
