// The SPC I/O image (S-6), the input filter (S-9) and the stimulus file format.
#include <gtest/gtest.h>

#include "control/spc/input_filter.hpp"
#include "control/spc/io_image.hpp"
#include "control/spc/stimulus.hpp"

namespace softmc::control::spc {
namespace {

TEST(Spc200, S6_AddressSpaceOfEachModule) {
  // First I/O module 10 in / 8 out, CP buses 16/16, modules 2, 4, 5 like the first.
  const int in_bits[] = {10, 16, 10, 16, 10, 10};
  const int out_bits[] = {8, 16, 8, 16, 8, 8};
  for (int m = 0; m < 6; ++m) {
    for (int b = 0; b < 16; ++b) {
      EXPECT_EQ(valid_input(m, b), b < in_bits[m]) << "I" << m << "." << b;
      EXPECT_EQ(valid_output(m, b), b < out_bits[m]) << "Q" << m << "." << b;
    }
  }
  EXPECT_FALSE(valid_input(6, 0));
  EXPECT_FALSE(valid_output(-1, 0));
  EXPECT_FALSE(parse_address("I0.10").has_value());
  EXPECT_FALSE(parse_address("Q0.8").has_value());
  EXPECT_FALSE(parse_address("I6.0").has_value());
  EXPECT_FALSE(parse_address("X0.1").has_value());
  EXPECT_FALSE(parse_address("I0").has_value());
  ASSERT_TRUE(parse_address("i3.15").has_value());
  EXPECT_EQ(*parse_address("i3.15"), (IoAddress{false, 3, 15}));
  EXPECT_EQ(*parse_address("Q1.15"), (IoAddress{true, 1, 15}));
  char buf[6];
  EXPECT_STREQ(format_address({true, 1, 15}, buf), "Q1.15");
  EXPECT_STREQ(format_address({false, 0, 7}, buf), "I0.7");
}

TEST(Spc200, S6_ImageBitsAreIndependent) {
  IoImage io;
  io.set_input(2, 9, true);
  io.set_output(3, 15, true);
  io.set_input(1, 0, true);
  EXPECT_TRUE(io.get_input(2, 9));
  EXPECT_TRUE(io.get_output(3, 15));
  EXPECT_TRUE(io.get_input(1, 0));
  EXPECT_FALSE(io.get_output(2, 7));
  EXPECT_FALSE(io.get_input(3, 15));
  io.set_input(2, 9, false);
  EXPECT_FALSE(io.get_input(2, 9));
  EXPECT_TRUE(io.get_input(1, 0));
  // Out of the address space: reads 0, writes ignored.
  io.set_output(0, 9, true);
  EXPECT_EQ(io.outputs[0], 0);
  EXPECT_FALSE(io.get_input(0, 12));
}

TEST(Spc200, S9_LineBitsAreBinaryOnI0_0ToI0_4) {
  IoImage io;
  io.set(sig::kStop, true);
  for (int line = 0; line < 32; ++line) {
    io.set_line_bits(line);
    EXPECT_EQ(io.line_bits(), line);
    const int decoded = io.get_input(0, 0) + 2 * io.get_input(0, 1) + 4 * io.get_input(0, 2) +
                        8 * io.get_input(0, 3) + 16 * io.get_input(0, 4);
    EXPECT_EQ(decoded, line);
    EXPECT_TRUE(io.get(sig::kStop));  // the other bits of the module are kept
  }
}

TEST(Spc200, S8_S9_SystemSignalNames) {
  EXPECT_EQ(*signal_address("STOP"), (IoAddress{false, 0, 7}));
  EXPECT_EQ(*signal_address("start"), (IoAddress{false, 0, 8}));
  EXPECT_EQ(*signal_address("RESET"), (IoAddress{false, 0, 8}));
  EXPECT_EQ(*signal_address("ENABLE"), (IoAddress{false, 0, 9}));
  EXPECT_EQ(*signal_address("CLK_A"), (IoAddress{false, 0, 6}));
  EXPECT_EQ(*signal_address("SYNC_IB"), (IoAddress{false, 0, 5}));
  EXPECT_EQ(*signal_address("RC_A"), (IoAddress{true, 0, 4}));
  EXPECT_EQ(*signal_address("MC_B"), (IoAddress{true, 0, 3}));
  EXPECT_EQ(*signal_address("ACK_B"), (IoAddress{true, 0, 5}));
  EXPECT_EQ(*signal_address("READY"), (IoAddress{true, 0, 7}));
  EXPECT_FALSE(signal_address("GO").has_value());
  for (int b = 3; b <= 7; ++b) EXPECT_TRUE(is_system_output(0, b));
  EXPECT_FALSE(is_system_output(0, 2));
  EXPECT_FALSE(is_system_output(2, 5));
}

// Runs `raw` (one level per 1 ms sample) of I0.7 through a 5 ms filter; returns the filtered levels.
std::vector<int> filter_run(InputFilter& f, const std::vector<int>& raw) {
  std::vector<int> out;
  std::array<std::uint16_t, kIoModules> w{};
  for (int v : raw) {
    w[0] = static_cast<std::uint16_t>(v << 7);
    out.push_back((f.update(w, 0.001)[0] >> 7) & 1);
  }
  return out;
}

TEST(Spc200, S9_InputFilterLevelCountsOnceStableFor5ms) {
  InputFilter f;
  // A change appears on the 5th consecutive sample of the new level.
  EXPECT_EQ(filter_run(f, {1, 1, 1, 1, 1, 1, 1}), (std::vector<int>{0, 0, 0, 0, 1, 1, 1}));
  // A 4 ms glitch never passes; the count restarts on the way back.
  EXPECT_EQ(filter_run(f, {0, 0, 0, 0, 1, 0, 0, 0, 0, 0}), (std::vector<int>{1, 1, 1, 1, 1, 1, 1, 1, 1, 0}));
}

TEST(Spc200, S9_InputFilterKeepsPulseWidth) {
  InputFilter f;
  std::vector<int> raw(40, 0);
  for (int i = 5; i < 15; ++i) raw[static_cast<std::size_t>(i)] = 1;  // a 10 ms pulse
  const auto out = filter_run(f, raw);
  int width = 0, first = -1;
  for (std::size_t i = 0; i < out.size(); ++i)
    if (out[i]) {
      ++width;
      if (first < 0) first = static_cast<int>(i);
    }
  EXPECT_EQ(width, 10);
  EXPECT_EQ(first, 9);  // delayed by the filter
}

TEST(Spc200, S9_InputFilterIsPerBitAndConfigurable) {
  InputFilter f;
  f.set(0, 6, 0.0);    // CLK_A unfiltered
  f.set(2, 0, 0.020);  // a slow sensor
  std::array<std::uint16_t, kIoModules> w{};
  w[0] = 1u << 6;
  w[2] = 1u;
  EXPECT_EQ(f.update(w, 0.001)[0], 1u << 6);  // at once
  for (int i = 0; i < 18; ++i) EXPECT_EQ(f.update(w, 0.001)[2], 0u) << i;
  EXPECT_EQ(f.update(w, 0.001)[2], 1u);  // 20th sample
  EXPECT_DOUBLE_EQ(f.filter_s(0, 7), InputFilter::kDefaultFilterS);
  EXPECT_DOUBLE_EQ(f.filter_s(2, 0), 0.020);
}

TEST(SpcStimulus, ParsesNamesAddressesAndLines) {
  const auto r = parse_stimulus("# power up\n0 ENABLE 1\n0 STOP 1   # normally closed\n\n10.5 start 1\n"
                                "10.52 START 0\n11 I2.3 1\n12 LINE 17\n",
                                "s.stim");
  ASSERT_TRUE(r.stimulus) << (r.diagnostics.empty() ? "" : r.diagnostics[0].format());
  const auto& ev = r.stimulus->events;
  ASSERT_EQ(ev.size(), 6u);
  EXPECT_EQ(ev[0].addr, sig::kEnable);
  EXPECT_EQ(ev[2].addr, sig::kStart);
  EXPECT_DOUBLE_EQ(ev[2].t_s, 10.5);
  EXPECT_EQ(ev[4].addr, (IoAddress{false, 2, 3}));
  EXPECT_TRUE(ev[5].line);
  EXPECT_EQ(ev[5].value, 17);
  EXPECT_EQ(ev[5].source_line, 8u);

  IoImage io;
  StimulusPlayer p(*r.stimulus);
  EXPECT_EQ(p.apply(0.0, io), 2);
  EXPECT_TRUE(io.get(sig::kEnable) && io.get(sig::kStop));
  EXPECT_EQ(p.apply(10.499, io), 0);
  EXPECT_EQ(p.apply(10.5, io), 1);
  EXPECT_TRUE(io.get(sig::kStart));
  EXPECT_EQ(p.apply(20, io), 3);
  EXPECT_FALSE(io.get(sig::kStart));
  EXPECT_EQ(io.line_bits(), 17);
  EXPECT_TRUE(io.get_input(2, 3));
  EXPECT_TRUE(p.finished());
}

TEST(SpcStimulus, ErrorsCarryFileLineColumn) {
  const auto r = parse_stimulus("0 STOP 1\n1 GO 1\n2 READY 1\nx STOP 0\n3 STOP 2\n0.5 STOP 1\n4 LINE 32\n5 STOP\n"
                                "6 I0.10 1\n7 STOP 1 extra\n",
                                "bad.stim");
  EXPECT_FALSE(r.stimulus);
  std::vector<std::string> got;
  for (const auto& d : r.diagnostics) got.push_back(d.format());
  for (const auto& g : got) SCOPED_TRACE(g);
  ASSERT_EQ(got.size(), 9u) << ::testing::PrintToString(got);
  EXPECT_NE(got[0].find("bad.stim:2:3: error: unknown signal or address 'GO'"), std::string::npos) << got[0];
  EXPECT_NE(got[1].find("bad.stim:3:3: error: 'READY' is an output"), std::string::npos) << got[1];
  EXPECT_NE(got[2].find("bad.stim:4:1: error: expected a time"), std::string::npos) << got[2];
  EXPECT_NE(got[3].find("bad.stim:5:8: error: expected 0 or 1"), std::string::npos) << got[3];
  EXPECT_NE(got[4].find("bad.stim:6:1: error: time goes backwards"), std::string::npos) << got[4];
  EXPECT_NE(got[5].find("bad.stim:7:8: error: expected a line number 0..31"), std::string::npos) << got[5];
  EXPECT_NE(got[6].find("bad.stim:8:7: error: expected a value"), std::string::npos) << got[6];
  EXPECT_NE(got[7].find("bad.stim:9:3: error: unknown signal or address 'I0.10'"), std::string::npos) << got[7];
  EXPECT_NE(got[8].find("bad.stim:10:10: error: unexpected text"), std::string::npos) << got[8];
}

TEST(SpcStimulus, UnreadableFileIsOneDiagnostic) {
  const auto r = load_stimulus("/nonexistent/x.stim");
  EXPECT_FALSE(r.stimulus);
  ASSERT_EQ(r.diagnostics.size(), 1u);
}

}  // namespace
}  // namespace softmc::control::spc
