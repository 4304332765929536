// The real `softmc programs` and `softmc registers` binaries (S-12): import, list, delete, export, registers
// get/set, and a register set from outside that `softmc run` then moves to.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_run.hpp"
#include "program/spc/store.hpp"
#include "temp_dir.hpp"

namespace softmc::app {
namespace {

namespace fs = std::filesystem;

std::string src(const std::string& rel) { return std::string(SOFTMC_SOURCE_DIR) + "/" + rel; }

using test::TempDir;

// Runs `softmc ARGS` with stdout and stderr apart.
test::CliRun softmc(const std::string& args) { return test::run_softmc(args); }

TEST(Spc200, S12_CliImportListShowDeleteExport) {
  TempDir d;
  const auto store = (d.path / "store").string();
  fs::create_directory(store);
  const auto p1 = d.file("P1.spc", "N000 G01 X@5 FX0 ; go to @5\nN001 L2\nN002 M30\n");
  const auto p2 = d.file("P2.spc", "; sub\nN000 #LR1=5\nN001 M02\n");
  const auto bad = d.file("bad.spc", "N000 G01 X10.123 FX0\n");

  // P1 alone calls a missing P2: refused with the caller's file:line:col, store empty.
  auto r = softmc("programs " + store + " import " + p1);
  EXPECT_EQ(r.exit, 1);
  EXPECT_NE(r.err.find(p1 + ":2:6: error: call of program P2"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(store));

  r = softmc("programs " + store + " import " + p1 + " " + p2);
  EXPECT_EQ(r.exit, 0) << r.err;
  r = softmc("programs " + store + " import " + bad + " --as 4");
  EXPECT_EQ(r.exit, 1);
  EXPECT_NE(r.err.find(bad + ":1:"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(fs::path(store) / "P4.spc"));

  const auto machine = d.file("m.toml", "[spc]\ntask_a = 1\n");
  r = softmc("programs " + store + " list --machine " + machine);
  EXPECT_EQ(r.exit, 0) << r.err;
  EXPECT_EQ(r.out, "P1      3 lines  start A   go to @5\nP2      2 lines            sub\n");
  r = softmc("programs " + store + " list --json");
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j[1]["number"], 2);
  EXPECT_EQ(j[1]["lines"], 2);

  r = softmc("programs " + store + " show P2");
  EXPECT_EQ(r.out, "; sub\nN000 #LR1=5\nN001 M02\n");

  r = softmc("programs " + store + " delete 2");
  EXPECT_EQ(r.exit, 1);
  EXPECT_NE(r.err.find("called by P1"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(fs::path(store) / "P2.spc"));

  const auto out = (d.path / "out").string();
  fs::create_directory(out);
  r = softmc("programs " + store + " export 1 2 --to " + out);
  EXPECT_EQ(r.exit, 0) << r.err;
  EXPECT_EQ(*program::spc::read_text_file(out + "/P1.spc"), *program::spc::read_text_file(p1));
  EXPECT_EQ(softmc("programs " + store + " check").exit, 0);
}

TEST(Spc200, S12_CliRegistersSetGetAndARunUsesThem) {
  TempDir d;
  const auto store = (d.path / "store").string();
  fs::create_directory(store);
  d.file("store/P1.spc", "N000 G01 X@5 FX0\nN001 #LR1=5\nN002 M30\n");

  auto r = softmc("registers " + store + " set @5 X=12.34 R3=-4");
  EXPECT_EQ(r.exit, 0) << r.err;
  // A range error anywhere: nothing written.
  r = softmc("registers " + store + " set R3=1 @5X=1.234");
  EXPECT_EQ(r.exit, 1);
  EXPECT_NE(r.err.find("more than two decimals"), std::string::npos) << r.err;
  r = softmc("registers " + store + " set R3=32768");
  EXPECT_EQ(r.exit, 1);
  r = softmc("registers " + store + " set F1=1");
  EXPECT_EQ(r.exit, 1);
  EXPECT_NE(r.err.find("not retentive"), std::string::npos) << r.err;
  r = softmc("registers " + store + " get @5 X R3");
  EXPECT_EQ(r.exit, 0) << r.err;
  EXPECT_EQ(r.out, "@5X=12.34\nR3=-4\n");

  // `softmc run` restores the same file: X goes to @5, and the program's R1 comes back out.
  r = softmc("run " + store + " --machine " + src("examples/machines/spc_positioning.toml") +
             " --set spc.self_test_s=0.3 --task-a 1 --json");
  ASSERT_EQ(r.exit, 0) << r.err;
  EXPECT_DOUBLE_EQ(nlohmann::json::parse(r.out)["final_mm"]["X"].get<double>(), 12.34);
  r = softmc("registers " + store + " get --json");
  EXPECT_EQ(nlohmann::json::parse(r.out), nlohmann::json::parse(R"({"@5X":12.34,"R1":5,"R3":-4})"));
}

}  // namespace
}  // namespace softmc::app
