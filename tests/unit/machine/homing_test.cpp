// Homing (cutting_table.md T-4, plc_interface.md P-9): one axis's reference cycle on a simulated drive.
#include "machine/homing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "machine/config.hpp"
#include "machine/sim_drive.hpp"

using namespace softmc;
using namespace softmc::machine;

namespace {

AxisConfig table_x() { return *default_machine().axis(0); }

// The cycle on one drive whose reading starts at 0 while its load stands at `power_up`; the
// commands' finite differences within the axis's limits, checked on the way.
struct Homed {
  AxisHoming h;
  SimDrive d;
  double max_v = 0, max_a = 0, max_j = 0, max_search_v = 0;
  int cycles = 0;
  Homed(const AxisConfig& a, double power_up) : h(a), d(a, 0.0, power_up) {
    h.start(0.0);
    const double dt = 0.001;
    double c[3] = {0, 0, 0};  // the last three commands, in the coordinates of the newest
    for (; cycles < 200000 && !h.done() && !h.failed(); ++cycles) {
      const bool sw = a.home_side == HomeSide::Negative ? d.limit_negative() : d.limit_positive();
      const auto cmd = h.step(sw, d.measured_mm(), dt);
      if (cmd.shift_mm != 0) {
        d.shift_reference(cmd.shift_mm);
        for (double& x : c) x += cmd.shift_mm;
      }
      d.update(cmd.pos_mm, cmd.vel_mm_s, dt);
      if (cycles >= 1) max_v = std::max(max_v, std::abs(cmd.pos_mm - c[0]) / dt);
      if (cycles >= 2) max_a = std::max(max_a, std::abs(cmd.pos_mm - 2 * c[0] + c[1]) / (dt * dt));
      if (cycles >= 3) max_j = std::max(max_j, std::abs(cmd.pos_mm - 3 * c[0] + 3 * c[1] - c[2]) / (dt * dt * dt));
      if (h.phase() == HomingPhase::Search) max_search_v = std::max(max_search_v, std::abs(cmd.vel_mm_s));
      c[2] = c[1];
      c[1] = c[0];
      c[0] = cmd.pos_mm;
    }
  }
};

}  // namespace

TEST(Homing, T4_FindsTheSwitchGivesItsCoordinateAndBacksOff) {
  const auto a = table_x();
  Homed r(a, 300.0);
  ASSERT_TRUE(r.h.done()) << r.h.error();
  // The switch sits overtravel beyond the travel's start; the axis ends the back-off away from it.
  EXPECT_DOUBLE_EQ(home_switch_mm(a), a.min_mm - a.switch_overtravel_mm);
  EXPECT_DOUBLE_EQ(homed_mm(a), home_switch_mm(a) + a.home_backoff_mm);
  EXPECT_DOUBLE_EQ(r.d.last_setpoint(), homed_mm(a));
  // The reading's frame against the real one: within one encoder count and one cycle at the search speed.
  EXPECT_LE(std::abs(r.d.reference_offset_mm()), a.mm_per_count() + home_speed_mm_s(a) * 0.001);
  // The search ran at the homing speed (a tenth of the axis's by default), every move within the limits.
  EXPECT_DOUBLE_EQ(home_speed_mm_s(a), a.max_vel_mm_s / 10);
  EXPECT_NEAR(r.max_search_v, home_speed_mm_s(a), 1e-9);
  EXPECT_LE(r.max_v, a.max_vel_mm_s * (1 + 1e-9));
  EXPECT_LE(r.max_a, a.max_acc_mm_s2 * (1 + 1e-6));
  EXPECT_LE(r.max_j, a.max_jerk_mm_s3 * (1 + 1e-6));
  // Settled, the load is where the reading says within a count and the reference's error: the switch
  // really is 2 mm before the travel.
  for (int k = 0; k < 500; ++k) r.d.update(homed_mm(a), 0, 0.001);
  EXPECT_NEAR(r.d.true_mm(), homed_mm(a), a.mm_per_count() + home_speed_mm_s(a) * 0.001 + 1e-9);
}

TEST(Homing, T4_AnAxisStandingOnItsSwitchMovesOffItFirst) {
  const auto a = table_x();
  Homed r(a, a.min_mm - a.switch_overtravel_mm - 1.0);  // 1 mm past the switch's point
  ASSERT_TRUE(r.h.done()) << r.h.error();
  EXPECT_LE(std::abs(r.d.reference_offset_mm()), a.mm_per_count() + home_speed_mm_s(a) * 0.001);
  EXPECT_LE(r.max_a, a.max_acc_mm_s2 * (1 + 1e-6));
  EXPECT_LE(r.max_j, a.max_jerk_mm_s3 * (1 + 1e-6));
}

TEST(Homing, P9_TowardsThePositiveSwitchAtItsOwnSpeed) {
  auto a = table_x();
  a.home_side = HomeSide::Positive;
  a.home_vel_mm_s = 40;
  Homed r(a, 120.0);
  ASSERT_TRUE(r.h.done()) << r.h.error();
  EXPECT_DOUBLE_EQ(home_switch_mm(a), a.max_mm + a.switch_overtravel_mm);
  EXPECT_DOUBLE_EQ(r.d.last_setpoint(), a.max_mm + a.switch_overtravel_mm - a.home_backoff_mm);
  EXPECT_NEAR(r.max_search_v, 40.0, 1e-9);
  EXPECT_LE(std::abs(r.d.reference_offset_mm()), a.mm_per_count() + 40 * 0.001);
}

TEST(Homing, T4_AnAxisWithoutLimitSwitchesCannotHome) {
  auto a = table_x();
  a.limit_switches = false;
  AxisHoming h(a);
  h.start(0);
  EXPECT_TRUE(h.failed());
  EXPECT_NE(std::string(h.error()).find("no limit switch"), std::string::npos);
}

TEST(Homing, T4_NoSwitchWithinTheTravelFails) {
  // A switch that never closes (the drive's switches off while the homing thinks they are there).
  auto a = table_x();
  AxisHoming h(a);
  auto b = a;
  b.limit_switches = false;
  SimDrive d(b, 0.0, 300.0);
  h.start(0);
  int n = 0;
  for (; n < 400000 && !h.failed() && !h.done(); ++n) {
    const auto c = h.step(d.limit_negative(), d.measured_mm(), 0.001);
    d.update(c.pos_mm, c.vel_mm_s, 0.001);
  }
  EXPECT_TRUE(h.failed());
  EXPECT_NE(std::string(h.error()).find("no home switch"), std::string::npos);
  // It gave up after the travel and its margins, not at once.
  EXPECT_GT(n * 0.001 * home_speed_mm_s(a), a.max_mm - a.min_mm);
}

TEST(Homing, T4_TheLatchIsTheReadingWhereTheSwitchClosedNotTheCommand) {
  // At 100 mm/s the load lags its command by v·τ = 0.5 mm (5 ms motor): a reference taken from the
  // command would be 0.5 mm off; from the reading it is within a count and one cycle's travel.
  auto a = table_x();
  a.home_vel_mm_s = 100;
  Homed r(a, 300.0);
  ASSERT_TRUE(r.h.done()) << r.h.error();
  EXPECT_LE(std::abs(r.d.reference_offset_mm()), a.mm_per_count() + 100 * 0.001);
}
