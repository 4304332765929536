// The cycle is sacred: stepping a running simulation allocates nothing (DESIGN.md).
#include <gtest/gtest.h>

#include "alloc_counter.hpp"
#include "control/spc/registers.hpp"
#include "machine/config.hpp"
#include "program/iso/parser.hpp"
#include "program/spc/store.hpp"
#include "simulation.hpp"
#include "spc_simulation.hpp"

using namespace softmc;

TEST(Cycle, StepsAllocateNothing) {
  const auto cfg = machine::default_machine();
  auto parsed = program::iso::parse_file(std::string(SOFTMC_SOURCE_DIR) + "/examples/thesis/rounded_rectangle.ngc");
  ASSERT_TRUE(parsed.program);
  app::Simulation sim(*parsed.program, cfg);
  const long before = softmc::testing::allocation_count();
  std::uint64_t cycles = 0;
  while (!sim.finished() && !sim.faulted() && cycles < 10'000'000) {
    sim.step();
    ++cycles;
  }
  const long during = softmc::testing::allocation_count() - before;
  ASSERT_TRUE(sim.finished());
  EXPECT_GT(cycles, 1000u);
  EXPECT_EQ(during, 0) << "allocations inside " << cycles << " cycles";
}

// The PLC's motion signals played into the cycle (override, hold, enable, a stop) allocate nothing either.
TEST(Cycle, StepsWithMotionSignalsAllocateNothing) {
  const auto cfg = machine::default_machine();
  auto parsed = program::iso::parse_file(std::string(SOFTMC_SOURCE_DIR) + "/examples/thesis/rounded_rectangle.ngc");
  ASSERT_TRUE(parsed.program);
  const auto st = control::parse_channel_stimulus(
      "0.3 feed_override_permille 1500\n0.6 feed_hold 1\n0.9 feed_hold 0\n1.2 axis_enable[Y] 0\n"
      "1.5 axis_enable[Y] 1\n1.8 feed_override_multiplier_permille 500\n2.5 stop_request 1\n",
      "alloc.stim", cfg.axis_mask());
  ASSERT_TRUE(st.stimulus);
  app::Simulation sim(*parsed.program, cfg, &*st.stimulus);
  const long before = softmc::testing::allocation_count();
  std::uint64_t cycles = 0;
  while (!sim.finished() && !sim.stopped() && !sim.faulted() && cycles < 10'000'000) {
    sim.step();
    ++cycles;
  }
  const long during = softmc::testing::allocation_count() - before;
  ASSERT_TRUE(sim.stopped());
  EXPECT_GT(cycles, 2000u);
  EXPECT_EQ(during, 0) << "allocations inside " << cycles << " cycles";
}

TEST(Cycle, SpcRecordSelectWithPlcStepsAllocateNothing) {
  // Both tasks in Record Select, driven by the reference PLC (S-10) through the whole composition root.
  auto cfg = machine::load_machine(std::string(SOFTMC_SOURCE_DIR) + "/examples/machines/spc_positioning.toml");
  cfg.spc.self_test_s = 0.2;
  program::spc::ProgramStore store;
  ASSERT_TRUE(store.load_folder(std::string(SOFTMC_SOURCE_DIR) + "/examples/spc/two_axes_independent", {true, -1}).empty());
  app::SpcRunConfig rc;
  rc.controller = control::spc::controller_config_from(cfg.spc);
  rc.controller.mode = control::spc::SpcMode::RecordSelect;
  rc.controller.program_a = 1;
  rc.controller.program_b = 10;
  auto script = control::spc::parse_plc_script("0.3 A 31\n0.3 B 31\n1.5 A 0\n1.5 B 0\n", "orders.plc");
  ASSERT_TRUE(script.script);
  rc.plc = *script.script;
  control::spc::Registers regs;
  app::SpcSimulation sim(store, cfg, rc, regs);
  for (int i = 0; i < 100; ++i) sim.step();  // settle any first-use work before counting
  const long before = softmc::testing::allocation_count();
  for (int i = 0; i < 4000; ++i) sim.step();
  EXPECT_EQ(softmc::testing::allocation_count() - before, 0);
  ASSERT_NE(sim.plc(), nullptr);
}
