// SPC runs end to end through the composition root (apps/softmc/spc_simulation): example stores, stimulus
// files, the reference PLC, task errors, retentive registers, and the `softmc run` command line itself.
#include <gtest/gtest.h>

#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_run.hpp"
#include "temp_dir.hpp"
#include "machine/config.hpp"
#include "program/spc/store.hpp"
#include "spc_simulation.hpp"

namespace softmc::app {
namespace {

namespace fs = std::filesystem;
using namespace control::spc;

std::string src(const std::string& rel) { return std::string(SOFTMC_SOURCE_DIR) + "/" + rel; }

machine::MachineConfig spc_machine(double self_test_s = 0.5) {
  auto m = machine::load_machine(src("examples/machines/spc_positioning.toml"));
  m.spc.self_test_s = self_test_s;
  return m;
}

program::spc::ProgramStore load(const std::string& dir, bool record_select) {
  program::spc::ProgramStore s;
  for (const auto& d : s.load_folder(dir, {record_select, -1})) ADD_FAILURE() << d.format();
  return s;
}

Stimulus stim(const std::string& text) {
  auto r = parse_stimulus(text, "test.stim");
  for (const auto& d : r.diagnostics) ADD_FAILURE() << d.format();
  return r.stimulus.value_or(Stimulus{});
}

bool bit(const report::SpcTraceRow& r, IoAddress a) { return ((a.output ? r.out : r.in)[a.module] >> a.bit) & 1u; }

// First time at or after t0 where `pred` holds in the trace; -1 if never.
template <class P>
double first_time(const report::SpcTrace& tr, double t0, P pred) {
  for (const auto& r : tr.rows)
    if (r.t_s >= t0 && pred(r)) return r.t_s;
  return -1;
}

using test::TempDir;

// S-8 and S-11: the binary position decoder in Start/Stop, driven by a stimulus file: the PLC sets the
// position bits, pulses START; X moves to the decoded position; READY and MC follow S-8.
TEST(Spc200, S8_StartStopRunFromStimulusFileReachesDecodedPosition) {
  const auto store = load(src("examples/spc/binary_position_decoder"), false);
  auto cfg = spc_machine();
  SpcRunConfig rc;
  rc.controller = controller_config_from(cfg.spc);
  rc.controller.program_a = 1;
  // 1234 × 0.1 mm: I2.1 (0.2) + I2.4 (1.6) + I2.6 (6.4) + I2.7 (12.8) + I0.0 (102.4) = 123.4 mm
  rc.stimulus = stim(
      "0 ENABLE 1\n0 STOP 1\n0 I2.1 1\n0 I2.4 1\n0 I2.6 1\n0 I2.7 1\n0 I0.0 1\n1.0 START 1\n1.05 START 0\n");
  const auto res = run_spc(store, cfg, rc, ":memory:");
  EXPECT_TRUE(res.ok) << (res.errors.empty() ? "" : res.errors[0].text);
  EXPECT_DOUBLE_EQ(res.final_mm[0], 123.4);
  const auto& tr = res.trace;
  // READY rises when the 0.5 s self-test has passed (not before).
  const double t_ready = first_time(tr, 0, [](auto& r) { return bit(r, sig::kReady); });
  EXPECT_NEAR(t_ready, 0.5, 0.01);
  // START passes the 5 ms input filter; then MC_A falls while X moves and rises when it has arrived.
  const double t_mc_low = first_time(tr, 1.0, [](auto& r) { return !bit(r, sig::kMcA); });
  EXPECT_NEAR(t_mc_low, 1.0 + 0.005, 0.003);
  const double t_mc_high = first_time(tr, t_mc_low, [](auto& r) { return bit(r, sig::kMcA); });
  ASSERT_GT(t_mc_high, t_mc_low);
  const double x_at_mc = first_time(tr, t_mc_high, [](auto&) { return true; });
  for (const auto& r : tr.rows) {
    if (r.t_s == x_at_mc) {
      EXPECT_DOUBLE_EQ(r.cmd[0], 123.4);
    }
  }
  // The drive followed: its measured position is within one encoder count of the target at the end.
  EXPECT_NEAR(tr.rows.back().act[0], 123.4, 100.0 / 4096 + 1e-9);
  EXPECT_TRUE(bit(tr.rows.back(), sig::kReady));
}

// S-9 and S-10: two tasks in Record Select ordered by the reference PLC through the composition root.
TEST(Spc200, S10_RecordSelectRunWithReferencePlcCompletesOrders) {
  const auto store = load(src("examples/spc/two_axes_independent"), true);
  auto cfg = spc_machine();
  SpcRunConfig rc;
  rc.controller = controller_config_from(cfg.spc);
  rc.controller.mode = SpcMode::RecordSelect;
  rc.controller.program_a = 1;   // X
  rc.controller.program_b = 10;  // Y
  auto script = parse_plc_script("0.6 A 31\n0.6 B 31\n1.5 A 0\n1.5 B 0\n", "orders.plc");
  ASSERT_TRUE(script.script);
  rc.plc = *script.script;
  const auto res = run_spc(store, cfg, rc, ":memory:");
  ASSERT_TRUE(res.ok) << (res.errors.empty() ? "" : res.errors[0].text);
  ASSERT_TRUE(res.plc);
  for (const auto& c : *res.plc) {
    EXPECT_EQ(c.ordered, 2u);
    EXPECT_EQ(c.completed, 2u);
    EXPECT_EQ(c.failed + c.order_errors + c.motion_errors, 0u);
  }
  // Both lines 31 were reached (X 500, Y 700) before the PLC ordered line 0, and the run ends at 0.
  const auto& tr = res.trace;
  const double t_x = first_time(tr, 0, [](auto& r) { return r.cmd[0] == 500.0; });
  const double t_y = first_time(tr, 0, [](auto& r) { return r.cmd[1] == 700.0; });
  EXPECT_GT(t_x, 0.6);
  EXPECT_LT(t_x, 1.5);
  EXPECT_GT(t_y, 0.6);
  EXPECT_LT(t_y, 1.6);
  EXPECT_DOUBLE_EQ(res.final_mm[0], 0.0);
  EXPECT_DOUBLE_EQ(res.final_mm[1], 0.0);
  // The handshake of S-9 on the wires: ACK_A rises after CLK_A, then RC_A falls; RC_A rises again at X = 500.
  const double t_clk = first_time(tr, 0.6, [](auto& r) { return bit(r, sig::kClkA); });
  const double t_ack = first_time(tr, t_clk, [](auto& r) { return bit(r, sig::kAckA); });
  ASSERT_GT(t_ack, t_clk);
  const double t_rc = first_time(tr, t_ack, [](auto& r) { return bit(r, sig::kRcA); });
  EXPECT_GE(t_rc, t_x);
}

// S-5 errors while running: READY=0 and a message naming task, program and line.
TEST(Spc200, S5_RegisterOverflowShowsReadyLowWithTaskProgramLine) {
  TempDir dir;
  dir.file("P1.spc", "N000 G01 X100 FX0\nN001 #LR1=32767\nN002 #AR1=1\nN003 M30\n");
  const auto store = load(dir.path.string(), false);
  auto cfg = spc_machine(0.2);
  SpcRunConfig rc;
  rc.controller = controller_config_from(cfg.spc);
  rc.controller.program_a = 1;
  rc.stimulus = default_stimulus(rc.controller);
  const auto res = run_spc(store, cfg, rc, ":memory:");
  EXPECT_FALSE(res.ok);
  ASSERT_EQ(res.errors.size(), 1u);
  const auto& e = res.errors[0];
  EXPECT_EQ(e.task, 0);
  EXPECT_EQ(e.program, 1);
  EXPECT_EQ(e.line, 2);
  EXPECT_NE(e.text.find("task A, P1 N002: integer register overflow"), std::string::npos) << e.text;
  EXPECT_FALSE(res.status.ready);
  EXPECT_FALSE(((res.outputs[0] >> sig::kReady.bit) & 1u) != 0);
  EXPECT_DOUBLE_EQ(res.final_mm[0], 100.0);  // N000 ran before the error
}

// S-2 ownership conflict and S-4 nesting depth, each in its own task and program.
TEST(Spc200, S2_OwnershipConflictAndS4NestingNameTaskProgramLine) {
  {
    TempDir dir;
    dir.file("P1.spc", "N000 G01 X1500 FX10\nN001 M30\n");
    dir.file("P2.spc", "N000 G04 10\nN001 G01 X10 FX0\nN002 M30\n");
    const auto store = load(dir.path.string(), false);
    auto cfg = spc_machine(0.2);
    SpcRunConfig rc;
    rc.controller = controller_config_from(cfg.spc);
    rc.controller.program_a = 1;
    rc.controller.program_b = 2;
    rc.stimulus = default_stimulus(rc.controller);
    const auto res = run_spc(store, cfg, rc, ":memory:");
    ASSERT_FALSE(res.errors.empty());
    EXPECT_NE(res.errors[0].text.find("task B, P2 N001: axis is moving under the other task"), std::string::npos)
        << res.errors[0].text;
  }
  {
    TempDir dir;
    dir.file("P1.spc", "N000 L2\n");
    dir.file("P2.spc", "N000 L3\n");
    dir.file("P3.spc", "N000 L4\n");
    dir.file("P4.spc", "N000 L5\n");
    dir.file("P5.spc", "N000 L6\n");
    dir.file("P6.spc", "N000 G01 X1 FX0\n");
    const auto store = load(dir.path.string(), false);
    auto cfg = spc_machine(0.2);
    SpcRunConfig rc;
    rc.controller = controller_config_from(cfg.spc);
    rc.controller.program_b = 1;
    rc.stimulus = default_stimulus(rc.controller);
    const auto res = run_spc(store, cfg, rc, ":memory:");
    ASSERT_FALSE(res.errors.empty());
    EXPECT_NE(res.errors[0].text.find("task B, P5 N000: a fifth nested call"), std::string::npos) << res.errors[0].text;
    EXPECT_DOUBLE_EQ(res.final_mm[0], 0.0);
  }
}

// S-9: a relative line after a stop is refused before ACK: the PLC's order times out, READY=0, and the
// message names the task, the record program and the line ordered.
TEST(Spc200, S9_RelativeOrderAfterStopIsRefusedWithTaskProgramLine) {
  TempDir dir;
  dir.file("P1.spc", "N000 G01 X1500 FX20\nN001 G01 G91 X5 FX0\n");
  const auto store = load(dir.path.string(), true);
  auto cfg = spc_machine(0.2);
  SpcRunConfig rc;
  rc.controller = controller_config_from(cfg.spc);
  rc.controller.mode = SpcMode::RecordSelect;
  rc.controller.program_a = 1;
  rc.until_s = 2.0;
  rc.stimulus = stim("0 ENABLE 1\n0 STOP 1\n0.3 LINE 0\n0.32 CLK_A 1\n0.4 CLK_A 0\n0.6 STOP 0\n0.7 STOP 1\n"
                     "0.8 LINE 1\n0.82 CLK_A 1\n0.9 CLK_A 0\n");
  const auto res = run_spc(store, cfg, rc, ":memory:");
  ASSERT_EQ(res.errors.size(), 1u);
  EXPECT_NE(res.errors[0].text.find("task A, P1 N001: relative move refused after a stop"), std::string::npos)
      << res.errors[0].text;
  EXPECT_GT(res.errors[0].t_s, 0.82);
  // No ACK for the refused order.
  EXPECT_LT(first_time(res.trace, 0.82, [](auto& r) { return bit(r, sig::kAckA); }), 0);
}

// S-5: position and integer registers are retentive: a second run (a power cycle) finds what the first wrote.
TEST(Spc200, S5_RegistersSurviveARestartThroughTheSqliteFile) {
  TempDir dir;
  dir.file("P1.spc", "N000 G28 @3 X12.34\nN001 #LR7=-123\nN002 M30\n");
  dir.file("P2.spc", "N000 #TR7=-123 2\nN001 M30\nN002 G01 X@3 FX0\nN003 M30\n");
  const auto store = load(dir.path.string(), false);
  const auto db = dir.path_of("registers.sqlite");
  auto cfg = spc_machine(0.2);
  for (int prog : {1, 2}) {
    SpcRunConfig rc;
    rc.controller = controller_config_from(cfg.spc);
    rc.controller.program_a = prog;
    rc.stimulus = default_stimulus(rc.controller);
    const auto res = run_spc(store, cfg, rc, db);
    EXPECT_TRUE(res.ok);
    if (prog == 2) {
      EXPECT_DOUBLE_EQ(res.final_mm[0], 12.34);
    }
  }
}

// The command line on an example: `softmc run STORE ... --json` prints the documented JSON.
TEST(Spc200, S11_CliRunsAnExampleStoreAndPrintsJson) {
  TempDir dir;
  const auto stim_file = dir.file("run.stim", "0 ENABLE 1\n0 STOP 1\n0.4 START 1\n0.45 START 0\n");
  const auto plot = dir.path_of("plot.png");
  const auto trace = dir.path_of("trace.csv");
  const auto r = test::run_softmc("run " + src("examples/spc/app4_grid_g91") + " --machine " +
                          src("examples/machines/spc_positioning.toml") +
                          " --set spc.self_test_s=0.3 --task-a 1 --task-b 10 --stimulus " + stim_file +
                          " --registers :memory: --plot " + plot + " --trace " + trace + " --json");
  EXPECT_EQ(r.exit, 0) << r.out << r.err;
  const auto& out = r.out;
  const auto j = nlohmann::json::parse(out);
  EXPECT_EQ(j["mode"], "start-stop");
  EXPECT_TRUE(j["ok"].get<bool>());
  EXPECT_TRUE(j["outputs"]["READY"].get<bool>());
  // app4: each task runs its two lines once per START: X to 0 then +40.5, Y to 0 then +63.8.
  EXPECT_DOUBLE_EQ(j["final_mm"]["X"].get<double>(), 40.5);
  EXPECT_DOUBLE_EQ(j["final_mm"]["Y"].get<double>(), 63.8);
  EXPECT_TRUE(j["errors"].empty());
  EXPECT_GT(fs::file_size(plot), 10000u);
  std::ifstream csv(trace);
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("t_s,X_cmd,X_act,Y_cmd,Y_act,Z_cmd,Z_act,U_cmd,U_act,READY,MC_A,MC_B", 0), 0u) << header;
}

}  // namespace
}  // namespace softmc::app
