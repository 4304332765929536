// G74/G84 tapping, G86/G87/G88 boring: moves and spindle events as LinuxCNC 2.9 (plus G88's retract).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "iso_test_util.hpp"

namespace softmc::program::iso {
namespace {

using test::parse_errors;
using test::parse_ok;
using test::xyz;

// One short word per instruction: "rapid 10,10,2", "feed 10,10,-5 @5", "M5", "tool off", "dwell 0.5", "pause".
std::vector<std::string> events(const Program& p) {
  std::vector<std::string> out;
  auto pt = [](const core::Vec& v) { return fmt::format("{:g},{:g},{:g}", v[0], v[1], v[2]); };
  for (const auto& ins : p.instructions) {
    const auto& op = ins.op;
    if (const auto* r = std::get_if<Rapid>(&op)) out.push_back("rapid " + pt(r->end));
    else if (const auto* l = std::get_if<Linear>(&op)) out.push_back(fmt::format("feed {} @{:g}", pt(l->end), l->feed_mm_s));
    else if (const auto* m = std::get_if<MFunction>(&op)) out.push_back(fmt::format("M{}", m->number));
    else if (const auto* t = std::get_if<ToolSwitch>(&op)) out.push_back(t->on ? "tool on" : "tool off");
    else if (const auto* d = std::get_if<Dwell>(&op)) out.push_back(fmt::format("dwell {:g}", d->seconds));
    else if (std::holds_alternative<Pause>(op)) out.push_back("pause");
  }
  return out;
}

// The events of the program after its preamble line (S… M3 F… G0 …).
std::vector<std::string> cycle_events(const std::string& preamble, const std::string& cycle) {
  const auto before = events(parse_ok(preamble));
  auto all = events(parse_ok(preamble + cycle));
  EXPECT_GE(all.size(), before.size());
  return {all.begin() + static_cast<std::ptrdiff_t>(before.size()), all.end()};
}

const std::string kSpindleCw = "G21 G90 G17 G98\nS400 M3 F600\nG0 X0 Y0 Z10\n";

TEST(IsoCanned, G84TapsAtTheProgrammedFeedAndReversesTheSpindle) {
  // LinuxCNC 2.9's G84: overrides off, feed down, stop, reverse, dwell P, feed out, stop, forward.
  const std::vector<std::string> want = {
      "rapid 10,10,10", "rapid 10,10,2", "M49", "feed 10,10,-5 @10", "M5", "tool off", "M4", "tool on", "dwell 0.5",
      "feed 10,10,10 @10", "M5", "tool off", "M3", "tool on", "M48"};
  EXPECT_EQ(cycle_events(kSpindleCw, "G84 X10 Y10 Z-5 R2 P0.5\n"), want);
}

TEST(IsoCanned, G84LeavesAFeedOverrideSwitchedOffByM49Alone) {
  const auto ev = cycle_events(kSpindleCw + "M49\n", "G99 G84 X10 Y10 Z-5 R2\n");
  EXPECT_EQ(std::count(ev.begin(), ev.end(), "M48"), 0);
  EXPECT_EQ(std::count(ev.begin(), ev.end(), "M49"), 0);
  EXPECT_EQ(ev.back(), "tool on");
  EXPECT_EQ(ev[ev.size() - 5], "feed 10,10,2 @10");  // G99: out to R at the feed, then M5 M3
}

TEST(IsoCanned, G84NeedsTheSpindleTurningClockwise) {
  EXPECT_EQ(parse_errors("F600 G0 Z10\nG84 X1 Z-1 R1\n").at(0),
            "t.ngc:2:1: error: spindle not turning in G84: program M3 S… first");
  EXPECT_EQ(parse_errors("F600 S100 M4 G0 Z10\nG84 X1 Z-1 R1\n").at(0),
            "t.ngc:2:1: error: spindle turning counterclockwise in G84: right-hand taps need M3");
  EXPECT_EQ(parse_errors("F600 S100 M3 G0 Z10\nG74 X1 Z-1 R1\n").at(0),
            "t.ngc:2:1: error: spindle turning clockwise in G74: left-hand taps need M4");
  // M19 (orient) stops the spindle, M5 too.
  EXPECT_FALSE(parse_errors("F600 S100 M3 G0 Z10\nM19\nG84 X1 Z-1 R1\n").empty());
  EXPECT_FALSE(parse_errors("F600 S100 M3 G0 Z10\nM5\nG84 X1 Z-1 R1\n").empty());
}

TEST(IsoCanned, G74TapsLeftHanded) {
  const auto ev = cycle_events("G21 G90 G98\nS400 M4 F600\nG0 X0 Y0 Z10\n", "G74 X10 Y10 Z-5 R2\n");
  const std::vector<std::string> want = {
      "rapid 10,10,10", "rapid 10,10,2", "M49", "feed 10,10,-5 @10", "M5", "tool off", "M3", "tool on", "dwell 0",
      "feed 10,10,10 @10", "M5", "tool off", "M4", "tool on", "M48"};
  EXPECT_EQ(ev, want);
}

TEST(IsoCanned, G87BacksBoresThroughTheOffsetWayIn) {
  const std::vector<std::string> want = {
      "rapid 20,20,10", "rapid 20,20,2",  // to the hole, down to R
      "rapid 21.5,20,2", "M5", "tool off", "M19", "rapid 21.5,20,-20", "rapid 20,20,-20",  // in, oriented
      "M3", "tool on", "feed 20,20,-14 @10", "feed 20,20,-20 @10",                      // bore up and back
      "M5", "tool off", "M19", "rapid 21.5,20,-20", "rapid 21.5,20,10", "rapid 20,20,10", "M3", "tool on"};
  EXPECT_EQ(cycle_events(kSpindleCw, "G87 X20 Y20 Z-20 R2 I1.5 J0 K-14\n"), want);
}

TEST(IsoCanned, G87KeepsIJKWhileItRepeatsAndKIsFromTheBottomInG91) {
  const auto ev = cycle_events(kSpindleCw, "G99 G87 X20 Y20 Z-20 R2 I1.5 J0 K-14\nG91 X10 Z-10 R0 K3\n");
  // Second block: R = 0 from the initial level 10, bottom 0, top of the bore 0 + 3; offset I1.5 kept.
  EXPECT_NE(std::find(ev.begin(), ev.end(), "rapid 31.5,20,10"), ev.end());
  EXPECT_NE(std::find(ev.begin(), ev.end(), "feed 30,20,3 @10"), ev.end());
  EXPECT_EQ(parse_errors(kSpindleCw + "G87 X20 Y20 Z-20 R2 I1.5 K-14\n").at(0),
            "t.ngc:4:1: error: J word missing with G87: G87 needs I, J and K (offset of the way in, top of the bore)");
}

TEST(IsoCanned, G88PausesForTheOperatorThenLeavesTheHoleStraight) {
  const std::vector<std::string> want = {
      "rapid 5,5,10", "rapid 5,5,3", "feed 5,5,-8 @10", "dwell 1.5", "M5", "tool off", "pause",
      "rapid 5,5,10",  // softmc's addition: straight out along the hole's axis, spindle still stopped
      "M3", "tool on"};
  EXPECT_EQ(cycle_events(kSpindleCw, "G88 X5 Y5 Z-8 R3 P1.5\n"), want);
  EXPECT_EQ(parse_errors(kSpindleCw + "G88 X5 Y5 Z-8 R3\n").at(0),
            "t.ngc:4:1: error: P word missing: this canned cycle dwells P seconds at the bottom");
}

TEST(IsoCanned, G86RestartsTheSpindleInItsDirection) {
  const auto ev = cycle_events("G21 G90 G98\nS400 M4 F600\nG0 X0 Y0 Z10\n", "G86 X5 Y5 Z-8 R3 P0\n");
  const std::vector<std::string> want = {"rapid 5,5,10", "rapid 5,5,3", "feed 5,5,-8 @10", "dwell 0", "M5",
                                         "tool off", "rapid 5,5,10", "M4", "tool on"};
  EXPECT_EQ(ev, want);
  EXPECT_EQ(parse_errors("F600 G0 Z10\nG86 X1 Z-1 R1 P0\n").at(0),
            "t.ngc:2:1: error: spindle not turning in G86: program M3 or M4 first (the cycle stops and restarts it)");
}

TEST(IsoCanned, G85FeedsOutToRThenRapidsToTheClearHeight) {
  // LinuxCNC 2.9 convert_cycle_g85: feed down, feed out to R, rapid to the clear height. rs274 -g:
  // STRAIGHT_FEED(10, 10, -5), STRAIGHT_FEED(10, 10, 2), STRAIGHT_TRAVERSE(10, 10, 10) under G98;
  // under G99 the clear height is R and the feed to R ends the cycle.
  const std::vector<std::string> g98 = {"rapid 10,10,10", "rapid 10,10,2", "feed 10,10,-5 @10", "feed 10,10,2 @10",
                                        "rapid 10,10,10"};
  EXPECT_EQ(cycle_events(kSpindleCw, "G85 X10 Y10 Z-5 R2\n"), g98);
  const std::vector<std::string> g99 = {"rapid 10,10,10", "rapid 10,10,2", "feed 10,10,-5 @10", "feed 10,10,2 @10"};
  EXPECT_EQ(cycle_events(kSpindleCw, "G99 G85 X10 Y10 Z-5 R2\n"), g99);
}

TEST(IsoCanned, G89FeedsOutToTheClearHeightAfterItsDwell) {
  // LinuxCNC 2.9's G89 (unlike G85) feeds straight out to the clear height: rs274 -g prints
  // STRAIGHT_FEED(30, 0, -5), DWELL(1), STRAIGHT_FEED(30, 0, 10) under G98.
  const std::vector<std::string> want = {"rapid 30,0,10", "rapid 30,0,2", "feed 30,0,-5 @10", "dwell 1",
                                         "feed 30,0,10 @10"};
  EXPECT_EQ(cycle_events(kSpindleCw, "G89 X30 Z-5 R2 P1\n"), want);
}

TEST(IsoCanned, G91RIsFromTheInitialLevelAlsoAfterG99Cycles) {
  // rs274 2.9: a run of cycles keeps its initial level; G91's R counts from it even under G99. The
  // move to the second hole rises from R (2) to the new R (10) on the way, as rs274's does.
  const auto ev = cycle_events(kSpindleCw, "G99 G81 X10 Y10 Z-5 R2\nG91 X5 R0 Z-3\n");
  const std::vector<std::string> want = {"rapid 10,10,10", "rapid 10,10,2", "feed 10,10,-5 @10", "rapid 10,10,2",
                                         "rapid 15,10,10", "feed 15,10,7 @10", "rapid 15,10,10"};
  EXPECT_EQ(ev, want);
}

}  // namespace
}  // namespace softmc::program::iso
