// Soft limits before motion (plc_interface.md P-9): the whole path, arcs included, named by line.
#include <gtest/gtest.h>

#include "control/travel_check.hpp"

using namespace softmc;

namespace {
motion::MachineLimits table() {
  motion::MachineLimits m;
  m.axis[0] = {100, 1000, 0, 0, 600};
  m.axis[1] = {100, 1000, 0, 0, 400};
  return m;
}
core::Vec xy(double x, double y) {
  core::Vec v;
  v[0] = x;
  v[1] = y;
  return v;
}
program::Program prog(std::vector<program::Op> ops) {
  program::Program p;
  p.files = {"part.ngc"};
  std::uint32_t line = 1;
  for (auto& o : ops) p.instructions.push_back({{0, line++, 3}, o});
  return p;
}
}  // namespace

TEST(TravelCheck, P9_InsidePathPasses) {
  EXPECT_TRUE(control::check_travel(prog({program::Rapid{xy(10, 10)}, program::Linear{xy(600, 400), 10}}), table())
                  .empty());
}

TEST(TravelCheck, P9_ArcBulgingOutIsRefusedWithItsLine) {
  // Both end points inside; the arc's top at y = 410 is not.
  program::Arc a;
  a.end = xy(300, 400);
  a.center0 = 305;
  a.center1 = 400;
  a.turns = 1;  // counter-clockwise from (310, 400) over the top to (300, 400)
  const auto d = control::check_travel(prog({program::Rapid{xy(310, 400)}, a}), table());
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].format(), "part.ngc:2:3: error: Y leaves the travel: 405.000 mm > max 400.000 mm");
}

TEST(TravelCheck, P9_EveryViolationIsReportedAndMissingAxesToo) {
  core::Vec z = xy(1, 1);
  z[2] = -5;  // the table has no Z
  auto p = prog({program::Linear{xy(-1, 5), 10}, program::Linear{xy(10, 5), 10}, program::Linear{xy(700, 5), 10},
                 program::Rapid{xy(5, 5)}, program::Rapid{z}});
  p.start = xy(5, 5);
  const auto d = control::check_travel(p, table());
  ASSERT_EQ(d.size(), 5u);
  EXPECT_EQ(d[0].message, "X leaves the travel: -1.000 mm < min 0.000 mm");
  EXPECT_EQ(d[1].line, 2u);  // it starts outside the travel, too
  EXPECT_EQ(d[2].message, "X leaves the travel: 700.000 mm > max 600.000 mm");
  EXPECT_EQ(d[3].line, 4u);
  EXPECT_EQ(d[4].message, "the machine has no Z axis");
}

// The travel check takes the program's pieces one by one as they are built (none kept): a curve
// that cannot be built is reported after every travel message, and the walk goes on past it from
// where the curve would have started (as the Channel does), so later motions are still checked.
TEST(TravelCheck, P9_ACurveThatCannotBeBuiltIsReportedAndTheRestStillChecked) {
  program::Nurbs bad;
  bad.ctrl = {xy(10, 10), xy(20, 20)};
  bad.weights = {1, -1};  // a weight must be positive
  bad.order = 2;
  auto p = prog({program::Rapid{xy(10, 10)}, bad, program::Linear{xy(650, 10), 10}});
  const auto d = control::check_travel(p, table());
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[0].format(), "part.ngc:3:3: error: X leaves the travel: 650.000 mm > max 600.000 mm");
  EXPECT_EQ(d[1].line, 2u);
  EXPECT_NE(d[1].message.find("the curve cannot be built"), std::string::npos) << d[1].message;
}
