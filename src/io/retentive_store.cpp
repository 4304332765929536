// SQLite persistence of the SPC registers: one table, one transaction per flush.
#include "io/retentive_store.hpp"

#include <sqlite3.h>

#include <vector>

namespace softmc::io {

namespace {
struct Row {
  int kind, axis, index, value;
};
}  // namespace

RetentiveStore::RetentiveStore(const std::string& path) {
  if (sqlite3_open(path.c_str(), &db_) != SQLITE_OK) {
    std::string msg = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw StoreError("cannot open register store " + path + ": " + msg);
  }
  sqlite3_busy_timeout(db_, 2000);
  exec("PRAGMA journal_mode=WAL");
  exec("PRAGMA synchronous=FULL");
  exec("CREATE TABLE IF NOT EXISTS spc_registers (kind INTEGER NOT NULL, axis INTEGER NOT NULL, "
       "idx INTEGER NOT NULL, value INTEGER NOT NULL, PRIMARY KEY (kind, axis, idx))");
}

RetentiveStore::~RetentiveStore() {
  stop();
  sqlite3_close(db_);
}

void RetentiveStore::exec(const char* sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
    std::string msg = err ? err : "?";
    sqlite3_free(err);
    throw StoreError(std::string("register store: ") + sql + ": " + msg);
  }
}

void RetentiveStore::restore(control::spc::Registers& regs) {
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db_, "SELECT kind, axis, idx, value FROM spc_registers", -1, &st, nullptr) != SQLITE_OK)
    throw StoreError(std::string("register store: ") + sqlite3_errmsg(db_));
  while (sqlite3_step(st) == SQLITE_ROW) {
    regs.restore(static_cast<control::spc::RegKind>(sqlite3_column_int(st, 0)), sqlite3_column_int(st, 1),
                 sqlite3_column_int(st, 2), sqlite3_column_int(st, 3));
  }
  sqlite3_finalize(st);
}

std::size_t RetentiveStore::flush(control::spc::Registers& regs) {
  std::vector<Row> rows;
  regs.drain_dirty([&](control::spc::RegKind k, int axis, int i, std::int32_t v) {
    rows.push_back({static_cast<int>(k), axis, i, v});
  });
  if (rows.empty()) return 0;
  exec("BEGIN IMMEDIATE");
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db_, "INSERT OR REPLACE INTO spc_registers (kind, axis, idx, value) VALUES (?, ?, ?, ?)", -1,
                         &st, nullptr) != SQLITE_OK) {
    exec("ROLLBACK");
    throw StoreError(std::string("register store: ") + sqlite3_errmsg(db_));
  }
  for (const auto& r : rows) {
    sqlite3_bind_int(st, 1, r.kind);
    sqlite3_bind_int(st, 2, r.axis);
    sqlite3_bind_int(st, 3, r.index);
    sqlite3_bind_int(st, 4, r.value);
    if (sqlite3_step(st) != SQLITE_DONE) {
      sqlite3_finalize(st);
      exec("ROLLBACK");
      throw StoreError(std::string("register store: ") + sqlite3_errmsg(db_));
    }
    sqlite3_reset(st);
  }
  sqlite3_finalize(st);
  exec("COMMIT");
  return rows.size();
}

void RetentiveStore::start(control::spc::Registers& regs, std::chrono::milliseconds period) {
  stop();
  running_ = true;
  thread_ = std::thread([this, &regs, period] {
    // A failing write (disk full, ...) must not kill the process: the dirty bits of a failed batch
    // are lost for this flush, the registers keep their values, and the next batch tries again.
    auto guarded = [&] {
      try {
        flush(regs);
      } catch (const StoreError&) {
      }
    };
    while (running_.load()) {
      guarded();
      std::this_thread::sleep_for(period);
    }
    guarded();
  });
}

void RetentiveStore::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

}  // namespace softmc::io
