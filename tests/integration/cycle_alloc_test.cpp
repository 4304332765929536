// The cycle is sacred: stepping a running simulation allocates nothing (DESIGN.md).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "machine/config.hpp"
#include "program/iso/parser.hpp"
#include "simulation.hpp"

namespace {
std::atomic<long> g_allocs{0};
}  // namespace

// Counts every allocation made in this test executable.
void* operator new(std::size_t n) {
  g_allocs.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

using namespace softmc;

TEST(Cycle, StepsAllocateNothing) {
  const auto cfg = machine::default_machine();
  auto parsed = program::iso::parse_file(std::string(SOFTMC_SOURCE_DIR) + "/examples/thesis/rounded_rectangle.ngc");
  ASSERT_TRUE(parsed.program);
  app::Simulation sim(*parsed.program, cfg);
  const long before = g_allocs.load();
  std::uint64_t cycles = 0;
  while (!sim.finished() && !sim.faulted() && cycles < 10'000'000) {
    sim.step();
    ++cycles;
  }
  const long during = g_allocs.load() - before;
  ASSERT_TRUE(sim.finished());
  EXPECT_GT(cycles, 1000u);
  EXPECT_EQ(during, 0) << "allocations inside " << cycles << " cycles";
}
