// Retentive SPC registers in SQLite (S-5): restore at start-up, persist dirty registers outside the cycle.
//
// The cycle only writes control::spc::Registers in memory (and sets dirty bits); flush() — called by
// the persistence thread started with start(), or by hand — drains the dirty bits and writes them in
// ONE transaction, so a crash leaves each batch wholly old or wholly new (WAL, synchronous=FULL).
#pragma once

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

#include "control/spc/registers.hpp"

struct sqlite3;

namespace softmc::io {

struct StoreError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class RetentiveStore {
 public:
  // Opens (creating) the database; throws StoreError with SQLite's message.
  explicit RetentiveStore(const std::string& path);
  ~RetentiveStore();
  RetentiveStore(const RetentiveStore&) = delete;
  RetentiveStore& operator=(const RetentiveStore&) = delete;

  // Loads every stored register into `regs` (not marking them dirty). Not rt.
  void restore(control::spc::Registers& regs);
  // Writes every dirty register of `regs` in one transaction; returns how many. Not rt.
  std::size_t flush(control::spc::Registers& regs);
  // A background thread flushing every `period` until stop() (which flushes once more).
  void start(control::spc::Registers& regs, std::chrono::milliseconds period);
  void stop();

 private:
  void exec(const char* sql);

  sqlite3* db_ = nullptr;
  std::thread thread_;
  std::atomic<bool> running_{false};
};

}  // namespace softmc::io
