// Retentive SPC registers in SQLite (S-5): round trip, dirty-only flushes, and crash safety under SIGKILL.
#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <random>
#include <string>

#include "io/retentive_store.hpp"

namespace softmc::io {
namespace {

using control::spc::Registers;

std::string temp_db(const char* name) {
  const auto p = std::filesystem::temp_directory_path() / (std::string(name) + "_" + std::to_string(::getpid()) + ".db");
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(p.string() + suffix);
  return p.string();
}

TEST(Spc200, S5_RegistersSurviveARestart) {
  const auto path = temp_db("spc_regs_roundtrip");
  {
    Registers regs;
    RetentiveStore store(path);
    ASSERT_EQ(regs.set_position_centi(2, 17, -999999), control::spc::RegResult::Ok);
    ASSERT_EQ(regs.set_integer(99, 32767), control::spc::RegResult::Ok);
    regs.set_flag(3, true);
    EXPECT_EQ(store.flush(regs), 2u);
    EXPECT_EQ(store.flush(regs), 0u);  // nothing dirty any more
  }
  Registers fresh;
  RetentiveStore store(path);
  store.restore(fresh);
  EXPECT_EQ(fresh.position_centi(2, 17), -999999);
  EXPECT_EQ(fresh.integer(99), 32767);
  EXPECT_FALSE(fresh.flag(3));       // flags start at 0
  EXPECT_FALSE(fresh.any_dirty());   // restoring is not a write
}

TEST(Spc200, S5_BackgroundThreadPersistsWithoutTheCycleWaiting) {
  const auto path = temp_db("spc_regs_thread");
  Registers regs;
  {
    RetentiveStore store(path);
    store.start(regs, std::chrono::milliseconds(1));
    for (int i = 0; i < 1000; ++i) regs.set_integer(i % 100, i);  // the cycle side: plain stores
    store.stop();  // flushes once more
  }
  Registers fresh;
  RetentiveStore(path).restore(fresh);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(fresh.integer(i), 900 + i);
}

// A child process writes every register to generation g, flushes (one transaction), g+1, ...; the
// parent kills it at random moments. Each time the database must open, pass SQLite's integrity
// check, and hold one whole generation — the old or the new, never a mixture.
TEST(Spc200, S5_CrashLeavesOldOrNewNeverTorn) {
  const auto path = temp_db("spc_regs_crash");
  std::mt19937 rng(12345);
  int last_gen = 0;
  for (int iteration = 0; iteration < 8; ++iteration) {
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      Registers regs;
      RetentiveStore store(path);
      store.restore(regs);
      for (int g = regs.integer(0) + 1;; ++g) {
        for (int a = 0; a < 4; ++a)
          for (int i = 0; i < 100; ++i) regs.set_position_centi(a, i, g);
        for (int i = 0; i < 100; ++i) regs.set_integer(i, g % 32767);
        store.flush(regs);
      }
    }
    ::usleep(std::uniform_int_distribution<int>(20000, 120000)(rng));
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status));

    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    sqlite3_stmt* st = nullptr;
    ASSERT_EQ(sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &st, nullptr), SQLITE_OK);
    ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
    EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(st, 0)), "ok");
    sqlite3_finalize(st);
    sqlite3_close(db);

    Registers regs;
    RetentiveStore(path).restore(regs);
    const int g = regs.integer(0);
    EXPECT_GE(g, last_gen) << "iteration " << iteration;  // never older than what was seen before
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 100; ++i) ASSERT_EQ(regs.position_centi(a, i), g) << "iteration " << iteration;
    for (int i = 0; i < 100; ++i) ASSERT_EQ(regs.integer(i), g) << "iteration " << iteration;
    last_gen = g;
  }
  EXPECT_GT(last_gen, 8);  // the child really wrote batches between the kills
}

}  // namespace
}  // namespace softmc::io
