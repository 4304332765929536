// S-10: the reference PLC client against the real controller, wired through the I/O image only:
// hundreds of orders without loss or duplication, and recovery from injected faults.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "control/spc/plc_client.hpp"
#include "spc_modes_rig.hpp"

namespace softmc::control::spc {
namespace {

using modes_testing::kDt;
using modes_testing::ModesRig;

double line_pos(int line) { return 10.0 + 20.0 * line; }

// P1: X to line_pos(n) for N000..N030, N031 = G61 X2 (RC only once X is really in its ±0.5 mm window).
// P2: Y to line_pos(n) for N000..N031.
void load_programs(ModesRig& r) {
  std::string a, b;
  for (int n = 0; n < 32; ++n) {
    char buf[64];
    if (n < 31) {
      std::snprintf(buf, sizeof buf, "N%03d G01 X%.1f FX0\n", n, line_pos(n));
      a += buf;
    }
    std::snprintf(buf, sizeof buf, "N%03d G01 Y%.1f FY0\n", n, line_pos(n));
    b += buf;
  }
  a += "N031 G61 X3\n";
  r.load(1, a, true);
  r.load(2, b, true);
}

struct PlcRig {
  ModesRig r;
  PlcClient plc;
  std::array<std::vector<int>, 2> ordered, executed;  // lines, PLC side and controller side
  std::array<std::uint64_t, 2> seen{};
  bool keep_faulting = false;

  explicit PlcRig(const PlcTiming& t = {}) : plc(t) {
    load_programs(r);
    ControllerConfig c;
    c.mode = SpcMode::RecordSelect;
    c.program_a = 1;
    c.program_b = 2;
    c.self_test_s = 0.1;
    r.power_up(c);
  }
  void order(TaskId t, int line) {
    ASSERT_TRUE(plc.order(t, line));
    ordered[static_cast<std::size_t>(t)].push_back(line);
  }
  // One scan of the PLC, then one controller cycle; the controller side's executed lines are logged.
  void cycle() {
    plc.cycle(kDt, r.wires());
    if (keep_faulting) r.ctl->raise_fault("drive fault (persistent)");
    r.cycle();
    const auto st = r.ctl->status();
    for (std::size_t i = 0; i < 2; ++i)
      while (seen[i] < st.records_executed[i]) {
        ++seen[i];
        executed[i].push_back(st.last_record_line[i]);
      }
  }
  long run_until(const std::function<bool()>& done, double max_s) {
    const long n = static_cast<long>(max_s / kDt);
    for (long i = 1; i <= n; ++i) {
      cycle();
      if (done()) return i;
    }
    return -1;
  }
  void run(double s) {
    for (long i = 0; i < static_cast<long>(s / kDt + 0.5); ++i) cycle();
  }
  const PlcCounters& count(TaskId t) const { return plc.counters(t); }
};

PlcTiming fast_timing() {
  PlcTiming t;
  t.motion_timeout_s = 2.0;
  return t;
}

TEST(Spc200, S10_HundredsOfOrdersNoneLost) {
  PlcRig k(fast_timing());
  std::mt19937 rng(20261122);
  std::uniform_int_distribution<int> line_a(0, 30), line_b(0, 31);
  constexpr int kOrders = 300;
  for (int i = 0; i < kOrders; ++i) {
    k.order(TaskId::A, line_a(rng));
    k.order(TaskId::B, line_b(rng));
  }
  ASSERT_GT(k.run_until([&] { return k.plc.idle(); }, 600.0), 0);
  for (auto t : {TaskId::A, TaskId::B}) {
    const auto i = static_cast<std::size_t>(t);
    const auto& c = k.count(t);
    EXPECT_EQ(c.accepted, static_cast<std::uint64_t>(kOrders));
    EXPECT_EQ(c.completed, static_cast<std::uint64_t>(kOrders));
    EXPECT_EQ(c.failed + c.interrupted + c.uncertain + c.order_errors + c.motion_errors, 0u);
    // Every order executed exactly once, in the order the PLC gave them.
    EXPECT_EQ(k.executed[i], k.ordered[i]);
  }
  EXPECT_FALSE(k.r.ctl->status().error);
  EXPECT_TRUE(k.r.out(sig::kReady));
  EXPECT_NEAR(k.r.x(), line_pos(k.ordered[0].back()), 1e-9);
  EXPECT_NEAR(k.r.y(), line_pos(k.ordered[1].back()), 1e-9);
}

TEST(Spc200, S10_OrderHandshakeTimingOnTheWires) {
  PlcRig k(fast_timing());
  k.run(0.12);
  k.order(TaskId::A, 21);
  // Step 2..4: the line bits stand 10 ms before CLK rises, and stay until ACK.
  ASSERT_GT(k.run_until([&] { return k.r.wires().line_bits() == 21; }, 0.1), 0);
  long settle = k.run_until([&] { return k.r.wires().get(sig::kClkA); }, 0.1);
  EXPECT_EQ(settle, 10);
  long to_ack = k.run_until([&] { return k.r.out(sig::kAckA); }, 0.1);
  EXPECT_EQ(to_ack, 4);  // the controller's 5 ms filter: the cycle CLK rose in plus 4
  EXPECT_EQ(k.r.wires().line_bits(), 21);
  // Step 5: ACK seen → CLK=0 on the next scan; step 6: ACK falls after the filter.
  k.cycle();
  EXPECT_FALSE(k.r.wires().get(sig::kClkA));
  EXPECT_EQ(k.plc.order_step(TaskId::A), PlcOrderStep::WaitAckFall);
  ASSERT_GT(k.run_until([&] { return k.plc.order_step(TaskId::A) == PlcOrderStep::WaitRc; }, 0.1), 0);
  ASSERT_GT(k.run_until([&] { return k.plc.idle(); }, 2.0), 0);
  EXPECT_EQ(k.count(TaskId::A).completed, 1u);
  EXPECT_NEAR(k.r.x(), line_pos(21), 1e-9);
}

TEST(Spc200, S10_RefusedOrderOrderErrorSequenceRecovers) {
  PlcRig k(fast_timing());
  k.r.ctl = nullptr;  // rebuild with task B unassigned: its orders are refused (no ACK)
  ControllerConfig c;
  c.mode = SpcMode::RecordSelect;
  c.program_a = 1;
  c.self_test_s = 0.1;
  k.r.power_up(c);
  k.order(TaskId::A, 4);
  ASSERT_GT(k.run_until([&] { return k.count(TaskId::A).completed == 1; }, 3.0), 0);
  ASSERT_TRUE(k.plc.order(TaskId::B, 6));  // refused by the controller
  // OrderError: CLK=0, STOP=0; 30 ms; RESET=1 for 10 ms; RESET=0, STOP=1.
  ASSERT_GT(k.run_until([&] { return k.plc.error_step() == PlcErrorStep::OrderStop; }, 1.0), 0);
  EXPECT_FALSE(k.r.out(sig::kReady));
  EXPECT_FALSE(k.r.wires().get(sig::kStop));
  EXPECT_FALSE(k.r.wires().get(sig::kClkB));
  EXPECT_EQ(k.run_until([&] { return k.r.wires().get(sig::kReset); }, 0.1), 30);
  EXPECT_EQ(k.run_until([&] { return !k.r.wires().get(sig::kReset); }, 0.1), 10);
  EXPECT_TRUE(k.r.wires().get(sig::kStop));
  ASSERT_GT(k.run_until([&] { return k.plc.error_step() == PlcErrorStep::None; }, 1.0), 0);
  EXPECT_TRUE(k.r.out(sig::kReady));  // the reset (STOP=0) cleared the controller's error
  EXPECT_EQ(k.count(TaskId::B).failed, 1u);
  EXPECT_EQ(k.count(TaskId::B).order_errors, 1u);
  // And the PLC goes on ordering.
  k.order(TaskId::A, 9);
  k.order(TaskId::A, 2);
  ASSERT_GT(k.run_until([&] { return k.plc.idle(); }, 3.0), 0);
  EXPECT_EQ(k.count(TaskId::A).completed, 3u);
  EXPECT_EQ(k.executed[0], k.ordered[0]);
  EXPECT_TRUE(k.executed[1].empty());
  EXPECT_NEAR(k.r.x(), line_pos(2), 1e-9);
}

TEST(Spc200, S10_BlockedAxisMotionTimerMotionErrorThenRecovery) {
  PlcTiming t = fast_timing();
  t.motion_timeout_s = 0.8;
  PlcRig k(t);
  k.order(TaskId::A, 31);  // G61 X3: RC only when X is really in its window
  k.order(TaskId::A, 5);
  ASSERT_GT(k.run_until([&] { return k.count(TaskId::A).completed == 2; }, 3.0), 0);
  k.order(TaskId::A, 25);
  ASSERT_GT(k.run_until([&] { return k.r.x() > 200.0; }, 2.0), 0);
  k.r.block(0);  // an obstruction: the setpoint goes on, the load does not
  ASSERT_GT(k.run_until([&] { return k.count(TaskId::A).motion_errors == 1; }, 3.0), 0);
  // MotionError: STOP=0; the controller stops every axis; READY stays 1 (no controller error).
  k.run(0.01);
  EXPECT_FALSE(k.r.wires().get(sig::kStop));
  EXPECT_FALSE(k.r.axes.moving(0));
  EXPECT_TRUE(k.plc.mem_stop(TaskId::A));
  ASSERT_GT(k.run_until([&] { return k.plc.error_step() == PlcErrorStep::None; }, 1.0), 0);
  EXPECT_TRUE(k.r.wires().get(sig::kStop));
  EXPECT_FALSE(k.r.out(sig::kRcA));  // S-9: RC stays 0 after the stop ...
  k.r.unblock(0);
  k.order(TaskId::A, 12);  // ... and MemStop lets the PLC order again
  k.order(TaskId::A, 3);
  ASSERT_GT(k.run_until([&] { return k.plc.idle(); }, 3.0), 0);
  const auto& c = k.count(TaskId::A);
  EXPECT_EQ(c.accepted, 5u);
  EXPECT_EQ(c.completed, 4u);
  EXPECT_EQ(c.interrupted, 1u);
  EXPECT_FALSE(k.plc.mem_stop(TaskId::A));
  EXPECT_EQ(k.executed[0], k.ordered[0]);
  EXPECT_NEAR(k.r.x(), line_pos(3), 1e-9);
  EXPECT_TRUE(k.r.out(sig::kReady));
}

TEST(Spc200, S10_StopDuringMotionThenOrdersGoOn) {
  PlcRig k(fast_timing());
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> line(0, 30);
  for (int i = 0; i < 40; ++i) {
    k.order(TaskId::A, line(rng));
    k.order(TaskId::B, line(rng));
  }
  int stops = 0;
  ASSERT_GT(k.run_until(
                [&] {
                  // A stop from the PLC's own logic (a light curtain) every ~0.7 s, mid-motion.
                  if (k.r.ctl->status().records_executed[0] > 0 && (k.r.cycles % 700) == 350 &&
                      k.r.axes.moving(0) && stops < 8) {
                    k.plc.request_stop();
                    ++stops;
                  }
                  return k.plc.idle();
                },
                120.0),
            0);
  EXPECT_GE(stops, 3);
  for (auto t : {TaskId::A, TaskId::B}) {
    const auto i = static_cast<std::size_t>(t);
    const auto& c = k.count(t);
    EXPECT_EQ(c.accepted, 40u);
    EXPECT_EQ(c.completed + c.interrupted, 40u);
    EXPECT_EQ(c.failed + c.uncertain + c.order_errors + c.motion_errors, 0u);
    EXPECT_EQ(k.executed[i], k.ordered[i]);  // none lost, none twice
  }
  EXPECT_GE(k.count(TaskId::A).interrupted, 1u);
  EXPECT_TRUE(k.r.out(sig::kReady));
}

TEST(Spc200, S10_PersistentFaultEndsInSystemError) {
  PlcTiming t = fast_timing();
  t.motion_timeout_s = 0.5;
  t.initial_signals_timeout_s = 0.3;
  PlcRig k(t);
  k.order(TaskId::A, 20);
  ASSERT_GT(k.run_until([&] { return k.r.axes.moving(0); }, 1.0), 0);
  k.keep_faulting = true;  // a drive that keeps failing: every reset is followed by a new fault
  // MotionError (motion timer) → STOP=0 → READY still 0 → reset → the fault is back → the
  // initial-signals timer runs out.
  std::vector<PlcErrorStep> steps{k.plc.error_step()};
  ASSERT_GT(k.run_until(
                [&] {
                  if (k.plc.error_step() != steps.back()) steps.push_back(k.plc.error_step());
                  return k.plc.system_error();
                },
                5.0),
            0);
  EXPECT_EQ(steps, (std::vector<PlcErrorStep>{PlcErrorStep::None, PlcErrorStep::MotionStop, PlcErrorStep::ResetHigh,
                                              PlcErrorStep::WaitInitial, PlcErrorStep::SystemError}));
  EXPECT_EQ(k.count(TaskId::A).motion_errors, 1u);
  EXPECT_FALSE(k.r.out(sig::kReady));
  // Not clearable by the PLC: it stays there.
  k.keep_faulting = false;
  k.run(1.0);
  EXPECT_TRUE(k.plc.system_error());
}

}  // namespace
}  // namespace softmc::control::spc
