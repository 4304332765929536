// One SPC task (A or B): runs its program line by line, holding on motions, waits, M00 and calls (S-1..S-7).
//
// Cycle order (the composition root / spc-modes calls, every cycle):
//   io read → task_a.update(dt, io) → task_b.update(dt, io) → axes.step(dt) → io write.
// A task executes instructions until one blocks (a motion, a dwell, M00, a wait = a jump to its own
// line) or kMaxInstructionsPerCycle have run; the next cycle resumes where it stopped. Blocked
// conditions are re-evaluated once per cycle, so a `#TNI0.0 102` wait costs one evaluation per cycle.
#pragma once

#include <array>
#include <cstdint>

#include "control/spc/io_image.hpp"
#include "control/spc/registers.hpp"
#include "control/spc/task_axes.hpp"
#include "program/spc/store.hpp"

namespace softmc::control::spc {

enum class TaskId : std::uint8_t { A, B };

struct TaskStatus {
  bool running = false;       // started and not ended (M30), halted or in error
  bool waiting_sync = false;  // on an M00 line (S-7)
  bool motion_done = true;    // MC/RC: the G61 condition holds for every axis of the current/last motion line
  bool error = false;
  std::uint8_t program = 0;   // program and N line of the pointer (of the error when error)
  std::uint16_t line = 0;
  const char* message = "";   // static text; "" when no error
};

// Instructions one task may execute in one cycle: bounds the cycle's work however the program loops.
inline constexpr int kMaxInstructionsPerCycle = 64;
// Nested subroutine calls (S-4): a fifth is an error.
inline constexpr int kMaxCallDepth = 4;

// M00 handshake (S-7), one enum and one transition function.
enum class SyncState : std::uint8_t { Idle, WaitRise, WaitFall, Done };
// rt-safe. `in_prev`/`in` are the SYNC input in the previous and this cycle; `out` is the SYNC output.
SyncState sync_step(SyncState s, bool in_prev, bool in, bool& out);

class Task {
 public:
  // The store, registers and axes are shared by both tasks and must outlive the task.
  Task(TaskId id, const program::spc::ProgramStore& store, Registers& regs, TaskAxes& axes);

  // Configuration (not rt): the task's program, the start program of S-1 or the record program of
  // S-9; -1 = none. Resets the task.
  void set_program(int number);
  int program_number() const { return main_program_; }
  TaskId id() const { return id_; }

  void start();               // S-8: run the start program from its current pointer
  void halt();                // STOP=0: halt where it is (axes stop without ramp: done by the axis layer)
  void reset();               // S-8/S-9 reset: pointer to first line, clear error, call stack cleared
  bool execute_record(int line);  // S-9: execute one line (0..31) of the record-select program; false = refused
  // Why the last execute_record() refused its line (static text; "" after an accepted one).
  const char* refusal() const { return refusal_; }
  void update(double dt_s, IoImage& io);  // rt-safe: executes until blocked, bounded instructions per cycle
  TaskStatus status() const;

  // Diagnostics for tests and benchmarks.
  std::uint64_t instructions_executed() const { return executed_; }
  int call_depth() const { return depth_; }

 private:
  enum class Phase : std::uint8_t { Fetch, Motion, Dwell, Sync };
  enum class Step : std::uint8_t { Next, Jumped, Block, Stop, Fail };
  struct Frame {
    std::int16_t program = -1;
    std::int32_t return_index = 0;
  };

  Step execute(const program::Instruction& ins, IoImage& io);
  Step motion(const program::SpcMove& m);
  Step finish_motion();
  Step resume(double dt_s, IoImage& io);
  bool all_complete() const;
  void clear_sync_output();
  Step jump_to_line(int line);
  Step fail(const char* message);
  void end_program();
  bool read_bit(const program::SpcBit& b, const IoImage& io) const;
  const program::spc::SpcProgram* current() const;

  TaskId id_;
  const program::spc::ProgramStore& store_;
  Registers& regs_;
  TaskAxes& axes_;

  int main_program_ = -1;
  std::int16_t program_ = -1;  // program the pointer is in
  std::int32_t pc_ = 0;        // instruction index
  std::array<Frame, kMaxCallDepth> stack_{};
  int depth_ = 0;

  Phase phase_ = Phase::Fetch;
  bool running_ = false;
  bool record_ = false;        // executing one record (S-9): stop after the line
  bool error_ = false;
  const char* message_ = "";
  const char* refusal_ = "";
  std::uint16_t error_line_ = 0;
  std::int16_t error_program_ = 0;

  bool absolute_ = true;       // G90/G91 modal (S-2)
  std::array<std::uint8_t, kSpcAxes> accel_pct_{}, decel_pct_{}, pass_pct_{}, mc_cond_{};
  program::SpcAxes motion_axes_ = 0;  // SPC axis bits of the current/last motion line
  std::array<bool, kSpcAxes> pass_active_{};  // G25 in force for this motion (S-3)
  std::array<double, kSpcAxes> pass_point_mm_{}, pass_dir_{};
  bool halted_record_ = false;  // S-9: a record stopped by STOP=0 keeps RC at 0
  bool sync_out_ = false, sync_out_dirty_ = false;
  double dwell_left_s_ = 0;
  SyncState sync_ = SyncState::Idle;
  bool sync_in_prev_ = false;
  std::uint64_t executed_ = 0;
};

}  // namespace softmc::control::spc
