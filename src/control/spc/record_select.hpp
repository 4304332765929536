// S-9 Record Select mode: the controller-wide READY machine and the per-task order handshake (CLK/ACK/RC).
#pragma once

#include <cstdint>

namespace softmc::control::spc {

// ---- The system machine: READY and the global functions (self-test, RESET, ENABLE, errors).
//
//  SelfTest ──Passed──► Ready ◄──Acknowledge / ResetFn── Error     EnableFell → Disabled ──EnableRose──► Ready
//     └─Failed─► Fatal    └──── MotionFault / Error ──►┘
enum class RecordSystemState : std::uint8_t { SelfTest, Ready, Error, Disabled, Fatal };
inline constexpr int kRecordSystemStates = 5;

enum class RecordSystemEvent : std::uint8_t {
  SelfTestPassed,
  SelfTestFailed,
  MotionFault,   // an axis cannot reach its target, a limit, a following error, a task error: stop all axes
  Error,         // a refused order, or an error still latched: READY=0, motion in progress goes on
  Acknowledge,   // RESET pulse (≥ 10 ms) with STOP=1: acknowledge the error
  ResetFn,       // RESET pulse (≥ 10 ms) with STOP=0: clear errors, RC=1, ACK=0
  StopFell,      // STOP 1 → 0: all axes stop at once, no ramp
  EnableFell,
  EnableRose,
};
inline constexpr int kRecordSystemEvents = 9;

namespace rs_action {
inline constexpr std::uint8_t kNone = 0;
inline constexpr std::uint8_t kHaltTasks = 1u << 0;      // halt() both tasks and send Halt to both task machines
inline constexpr std::uint8_t kClearErrors = 1u << 1;
inline constexpr std::uint8_t kResetTasks = 1u << 2;     // reset() both tasks and send Reset to both task machines
inline constexpr std::uint8_t kDisableDrives = 1u << 3;
inline constexpr std::uint8_t kEnableDrives = 1u << 4;
}  // namespace rs_action

struct RecordSystemStep {
  RecordSystemState next;
  std::uint8_t actions;
  friend constexpr bool operator==(const RecordSystemStep&, const RecordSystemStep&) = default;
};

// rt-safe
RecordSystemStep record_system_transition(RecordSystemState s, RecordSystemEvent e);
constexpr bool record_ready(RecordSystemState s) { return s == RecordSystemState::Ready; }

// ---- The task machine: one per task, the order handshake.
//
//   state          RC ACK   meaning
//   Ready           1  0    waiting for an order
//   Accepted        0  1    line latched and started, CLK still 1
//   Running         0  0    CLK fell, motion going on
//   Finished        1  1    motion done before CLK fell
//   Stopped         0  0    a stop (or fault) cut the motion: RC stays 0, an order is accepted again
//   StoppedAcked    0  1    the same while CLK is still 1
//
//   Ready ──Order──► Accepted ──ClkFell──► Running ──MotionDone──► Ready
//                       └──MotionDone──► Finished ──ClkFell──────────┘
//   Accepted/Running ──Halt──► StoppedAcked/Stopped ──Order──► Accepted      any ──Reset──► Ready
enum class RecordTaskState : std::uint8_t { Ready, Accepted, Running, Finished, Stopped, StoppedAcked };
inline constexpr int kRecordTaskStates = 6;

enum class RecordTaskEvent : std::uint8_t {
  Order,         // rising edge of CLK while READY=1, STOP=1, ENABLE=1
  OrderBlocked,  // rising edge of CLK while not (READY=1, STOP=1, ENABLE=1)
  ClkFell,
  MotionDone,    // the task reports its line's G61 condition met
  Halt,          // STOP fell or a motion fault stopped every axis
  Reset,         // the reset function
};
inline constexpr int kRecordTaskEvents = 6;

// What the controller does; Accept and Refuse are exclusive.
enum class RecordTaskAction : std::uint8_t {
  None,
  Accept,  // latch B0..B4 and call execute_record(line); if the task refuses, the order is refused
  Refuse,  // raise a refused-order error (READY=0); no ACK, the state does not change
};

struct RecordTaskStep {
  RecordTaskState next;
  RecordTaskAction action;
  friend constexpr bool operator==(const RecordTaskStep&, const RecordTaskStep&) = default;
};

// rt-safe
RecordTaskStep record_task_transition(RecordTaskState s, RecordTaskEvent e);

// The outputs of one task's machine (S-9).
constexpr bool record_rc(RecordTaskState s) { return s == RecordTaskState::Ready || s == RecordTaskState::Finished; }
constexpr bool record_ack(RecordTaskState s) {
  return s == RecordTaskState::Accepted || s == RecordTaskState::Finished || s == RecordTaskState::StoppedAcked;
}

const char* to_string(RecordSystemState s);
const char* to_string(RecordSystemEvent e);
const char* to_string(RecordTaskState s);
const char* to_string(RecordTaskEvent e);
const char* to_string(RecordTaskAction a);

}  // namespace softmc::control::spc
