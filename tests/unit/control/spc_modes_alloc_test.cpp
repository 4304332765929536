// The cycle is sacred: the SPC controller (both modes, both tasks, the PLC client) allocates nothing per cycle.
#include <gtest/gtest.h>

#include "alloc_counter.hpp"

#include <string>

#include "control/spc/plc_client.hpp"
#include "spc_modes_rig.hpp"


namespace softmc::control::spc {
namespace {

using modes_testing::kDt;
using modes_testing::ModesRig;

TEST(SpcModesCycle, RecordSelectWithPlcAllocatesNothing) {
  ModesRig r;
  std::string a, b;
  for (int n = 0; n < 32; ++n) {
    a += "N" + std::to_string(100 + n).substr(1) + " G01 X" + std::to_string(10 + 20 * n) + " FX0\n";
    b += "N" + std::to_string(100 + n).substr(1) + " G02 Y" + std::to_string(10 + 20 * n) + " FY50\n";
  }
  r.load(1, a, true);
  r.load(2, b, true);
  ControllerConfig c;
  c.mode = SpcMode::RecordSelect;
  c.program_a = 1;
  c.program_b = 2;
  c.self_test_s = 0.05;
  r.power_up(c);
  PlcClient plc;
  for (int i = 0; i < 40; ++i) {
    plc.order(TaskId::A, (i * 7) % 32);
    plc.order(TaskId::B, (i * 11) % 32);
  }
  const long before = softmc::testing::allocation_count();
  long cycles = 0;
  while (!plc.idle() && cycles < 200000) {
    plc.cycle(kDt, r.wires());
    if (cycles == 3000) plc.request_stop();
    r.cycle();
    ++cycles;
  }
  const long during = softmc::testing::allocation_count() - before;
  ASSERT_TRUE(plc.idle());
  EXPECT_GT(plc.counters(TaskId::A).completed, 30u);
  EXPECT_EQ(during, 0) << "allocations inside " << cycles << " cycles";
}

TEST(SpcModesCycle, StartStopAllocatesNothing) {
  ModesRig r;
  r.load(1, "N000 M00\nN001 G01 X500 FX0\nN002 G04 10\nN003 G01 X0 FX50\nN004 E05 1\n", false);
  r.load(2, "N000 #TNI2.0 0\nN001 G02 Y300 FY0\nN002 G00 Y0\nN003 E05 0\n", false);
  ControllerConfig c;
  c.mode = SpcMode::StartStop;
  c.program_a = 1;
  c.program_b = 2;
  c.self_test_s = 0.05;
  r.power_up(c);
  r.run(0.06);
  const long before = softmc::testing::allocation_count();
  r.pulse(sig::kStart, 0.02);
  r.pulse(sig::kSyncIA, 0.02);
  r.set(sig::kStop, true);
  r.wires().set_input(2, 0, true);
  r.run(3.0);
  r.set(sig::kStop, false);
  r.run(0.05);
  r.pulse(sig::kStart, 0.02);  // reset
  const long during = softmc::testing::allocation_count() - before;
  EXPECT_GT(r.ctl->task(TaskId::A).instructions_executed(), 5u);
  EXPECT_EQ(during, 0);
}

}  // namespace
}  // namespace softmc::control::spc
