// Trace CSV: header per configured axis, one line per row, values that round-trip.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "report/summary.hpp"
#include "synthetic_trace.hpp"

using namespace softmc;
using namespace softmc::report;
using namespace softmc::report::testing;

namespace {
std::vector<std::string> read_lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

std::uint32_t row_tag(const Trace& tr, std::size_t r) { return tr.rows[r].tag; }

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string f; std::getline(ss, f, ',');) out.push_back(f);
  return out;
}
}  // namespace

TEST(TraceCsv, HeaderRowsAndRoundTrip) {
  const auto prog = rounded_square();
  auto lined = prog;  // each instruction on line 10 + its index, as the source would give them
  for (std::size_t i = 0; i < lined.instructions.size(); ++i) lined.instructions[i].loc.line = static_cast<std::uint32_t>(10 + i);
  const auto tr = sample_program(prog, {.acc_mm_s2 = 1000, .lag_tau_s = 0.01, .quantum_mm = 0.127});
  const std::string path = ::testing::TempDir() + "report_trace_test.csv";
  write_trace_csv(path, tr, &lined);
  const auto lines = read_lines(path);
  ASSERT_EQ(lines.size(), tr.rows.size() + 1);
  EXPECT_EQ(lines[0], "t_s,x_cmd_mm,x_act_mm,x_vel_mm_s,y_cmd_mm,y_act_mm,y_vel_mm_s,path_v_mm_s,tool,line,dout,aout0,aout1,aout2,aout3");
  for (std::size_t r : {std::size_t{0}, tr.rows.size() / 3, tr.rows.size() - 1}) {
    const auto f = split(lines[r + 1]);
    ASSERT_EQ(f.size(), 15u) << lines[r + 1];
    EXPECT_EQ(f[10], "0") << "row " << r;  // no digital output set
    EXPECT_EQ(std::stoul(f[9]), 10u + row_tag(tr, r)) << "row " << r;
    const auto& row = tr.rows[r];
    const double expect[] = {row.t_s,    row.cmd[0], row.act[0],
                             row.vel[0], row.cmd[1], row.act[1],
                             row.vel[1], row.path_v, row.tool_on ? 1.0 : 0.0};
    for (std::size_t k = 0; k < 9; ++k)
      EXPECT_NEAR(std::stod(f[k]), expect[k], 1e-8 * std::max(1.0, std::abs(expect[k]))) << "row " << r << " col " << k;
  }
  // Nanometre-level detail survives: a position 1 nm off a round value is still 1 nm off.
  Trace fine;
  fine.axes = core::axis_bit(0);
  fine.rows.resize(1);
  fine.rows[0].cmd[0] = 123.456789;
  fine.rows[0].tool_on = true;
  fine.rows[0].dout = (std::uint64_t{1} << 63) | 5;  // outputs 0, 2 and 63
  fine.rows[0].aout = {0, 12.5, 0, -0.125};
  write_trace_csv(path, fine);
  const auto fl = read_lines(path);
  ASSERT_EQ(fl.size(), 2u);
  EXPECT_EQ(fl[0], "t_s,x_cmd_mm,x_act_mm,x_vel_mm_s,path_v_mm_s,tool,line,dout,aout0,aout1,aout2,aout3");
  EXPECT_EQ(fl[1], "0,123.456789,0,0,0,1,0,9223372036854775813,0,12.5,0,-0.125");  // no program: line 0
}

TEST(TraceCsv, AxesInIndexOrderAndOnlyTheConfiguredOnes) {
  Trace tr;
  tr.axes = core::axis_bit(2) | core::axis_bit(0) | core::axis_bit(6);
  const std::string path = ::testing::TempDir() + "report_trace_axes.csv";
  write_trace_csv(path, tr);
  const auto lines = read_lines(path);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0],
            "t_s,x_cmd_mm,x_act_mm,x_vel_mm_s,z_cmd_mm,z_act_mm,z_vel_mm_s,u_cmd_mm,u_act_mm,u_vel_mm_s,"
            "path_v_mm_s,tool,line,dout,aout0,aout1,aout2,aout3");
}

TEST(TraceCsv, UnopenableFileThrows) {
  EXPECT_THROW(write_trace_csv("/nonexistent-dir/for/sure/trace.csv", Trace{}), std::runtime_error);
}
