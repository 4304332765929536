// Stimulus files of G-code runs: the PLC's motion signals (P-2, P-5, P-8) over time.
#include <gtest/gtest.h>

#include "control/channel_stimulus.hpp"

using namespace softmc;
using control::MotionSignal;

namespace {
const core::AxisMask kXY = core::axis_bit(0) | core::axis_bit(1);

std::vector<std::string> errors(std::string_view text) {
  const auto r = control::parse_channel_stimulus(text, "run.stim", kXY);
  EXPECT_EQ(r.stimulus.has_value(), r.diagnostics.empty());
  std::vector<std::string> out;
  for (const auto& d : r.diagnostics) out.push_back(d.format());
  return out;
}
}  // namespace

TEST(ChannelStimulus, EverySignalIsReadWithItsValue) {
  const auto r = control::parse_channel_stimulus(
      "# a PLC\n"
      "0.5 feed_override_permille 500\n"
      "0.5 FEED_OVERRIDE_MULTIPLIER_PERMILLE 800  # case does not matter\n"
      "1   feed_hold 1\n"
      "\n"
      "2   axis_enable[y] 0\n"
      "2.5 stop_pulse 1\n"
      "3   stop_request 1\n"
      "3   emergency_stop_request 1\n",
      "run.stim", kXY);
  ASSERT_TRUE(r.stimulus) << (r.diagnostics.empty() ? "" : r.diagnostics.front().format());
  const auto& e = r.stimulus->events;
  ASSERT_EQ(e.size(), 7u);
  EXPECT_EQ(e[0].signal, MotionSignal::FeedOverride);
  EXPECT_EQ(e[0].value, 500);
  EXPECT_EQ(e[0].t_s, 0.5);
  EXPECT_EQ(e[0].source_line, 2u);
  EXPECT_EQ(e[1].signal, MotionSignal::FeedOverrideMultiplier);
  EXPECT_EQ(e[1].value, 800);
  EXPECT_EQ(e[2].signal, MotionSignal::FeedHold);
  EXPECT_EQ(e[3].signal, MotionSignal::AxisEnable);
  EXPECT_EQ(e[3].axis, 1);
  EXPECT_EQ(e[3].value, 0);
  EXPECT_EQ(e[3].source_line, 6u);
  EXPECT_EQ(e[4].signal, MotionSignal::StopPulse);
  EXPECT_EQ(e[5].signal, MotionSignal::StopRequest);
  EXPECT_EQ(e[6].signal, MotionSignal::EmergencyStopRequest);
}

TEST(ChannelStimulus, BadLinesAreReportedWithFileLineAndColumnAndNothingIsKept) {
  EXPECT_EQ(errors("1 feed_holt 1\n"),
            std::vector<std::string>{"run.stim:1:3: error: unknown signal 'feed_holt' (feed_override_permille, "
                                     "feed_override_multiplier_permille, feed_limit_request, feed_limit_mm_min, "
                                     "rapid_limit_request, rapid_limit_mm_min, feed_hold, axis_enable[L], stop_pulse, "
                                     "stop_request, emergency_stop_request)"});
  EXPECT_EQ(errors("0 feed_hold 0\n1 axis_enable[Z] 0\n"),
            std::vector<std::string>{"run.stim:2:3: error: expected axis_enable[L] with L one of the machine's axes (X, Y), got 'axis_enable[Z]'"});
  EXPECT_EQ(errors("1 axis_enable 0\n"),
            std::vector<std::string>{"run.stim:1:3: error: axis_enable needs an axis: axis_enable[L] with L one of X, Y"});
  EXPECT_EQ(errors("1 feed_hold[X] 0\n"),
            std::vector<std::string>{"run.stim:1:3: error: expected axis_enable[L] with L one of the machine's axes (X, Y), got 'feed_hold[X]'"});
  EXPECT_EQ(errors("1 stop_request 0\n"),
            std::vector<std::string>{"run.stim:1:16: error: expected 1 (the channel clears the request when it takes it), got '0'"});
  EXPECT_EQ(errors("1 feed_hold 2\n"), std::vector<std::string>{"run.stim:1:13: error: expected 0 or 1, got '2'"});
  EXPECT_EQ(errors("1 feed_override_permille 65536\n"),
            std::vector<std::string>{"run.stim:1:26: error: expected a whole number of per mille 0..65535, got '65536'"});
  EXPECT_EQ(errors("1 feed_override_permille 50.5\n").size(), 1u);
  EXPECT_EQ(errors("1 rapid_limit_mm_min -3\n"),
            std::vector<std::string>{"run.stim:1:22: error: expected a whole number of mm/min 0..65535, got '-3'"});
  EXPECT_EQ(errors("2 feed_hold 1\n1 feed_hold 0\n"),
            std::vector<std::string>{"run.stim:2:1: error: time goes backwards: 1 s after 2.000000 s"});
  EXPECT_EQ(errors("1 feed_hold\n"), std::vector<std::string>{"run.stim:1:12: error: expected a value after the signal"});
  EXPECT_EQ(errors("1\n"), std::vector<std::string>{"run.stim:1:2: error: expected a signal name after the time"});
  EXPECT_EQ(errors("1 feed_hold 1 0\n"), std::vector<std::string>{"run.stim:1:15: error: unexpected text after the value: '0'"});
  EXPECT_EQ(errors("-1 feed_hold 1\n").size(), 1u);
  // Every bad line is reported, and one bad line keeps the whole file out.
  EXPECT_EQ(errors("0 feed_hold 1\n1 feed_hold 7\n2 nothing 1\n").size(), 2u);
}

TEST(ChannelStimulus, APlayerWritesEachEventAtTheFirstCycleAtOrAfterItsTime) {
  const auto r = control::parse_channel_stimulus("0.002 feed_hold 1\n0.002 axis_enable[X] 0\n0.0035 feed_hold 0\n",
                                                 "run.stim", kXY);
  ASSERT_TRUE(r.stimulus);
  control::ChannelStimulusPlayer p(*r.stimulus);
  control::MotionSignals s;
  EXPECT_EQ(p.apply(0.001, s), 0);
  EXPECT_FALSE(s.feed_hold);
  EXPECT_EQ(p.apply(0.002, s), 2);
  EXPECT_TRUE(s.feed_hold);
  EXPECT_FALSE(s.axis_enable[0]);
  EXPECT_TRUE(s.axis_enable[1]);
  EXPECT_EQ(p.apply(0.003, s), 0);
  EXPECT_FALSE(p.finished());
  EXPECT_EQ(p.apply(0.004, s), 1);
  EXPECT_FALSE(s.feed_hold);
  EXPECT_TRUE(p.finished());
}

TEST(ChannelStimulus, P8_OverrideIsPerMilleTimesTheMultiplier) {
  control::MotionSignals s;
  EXPECT_EQ(s.feed_override(), 1.0);  // defaults: the programmed feed
  s.feed_override_permille = 500;
  s.feed_override_multiplier_permille = 800;
  EXPECT_DOUBLE_EQ(s.feed_override(), 0.4);
}

TEST(ChannelStimulus, P8_FeedAndRapidLimitsAreReadInMillimetresPerMinute) {
  const auto r = control::parse_channel_stimulus(
      "1 feed_limit_mm_min 1200\n1 feed_limit_request 1\n2 rapid_limit_mm_min 3000\n2 rapid_limit_request 1\n",
      "run.stim", kXY);
  ASSERT_TRUE(r.stimulus);
  control::MotionSignals s;
  EXPECT_EQ(s.feed_limit_mm_s(), 0.0);  // none by default
  control::ChannelStimulusPlayer p(*r.stimulus);
  p.apply(1.0, s);
  EXPECT_DOUBLE_EQ(s.feed_limit_mm_s(), 20.0);
  EXPECT_EQ(s.rapid_limit_mm_s(), 0.0);
  p.apply(2.0, s);
  EXPECT_DOUBLE_EQ(s.rapid_limit_mm_s(), 50.0);
  s.feed_limit_request = false;
  EXPECT_EQ(s.feed_limit_mm_s(), 0.0);
}
