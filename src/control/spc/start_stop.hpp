// S-8 Start/Stop mode: the controller-wide state machine (self-test, START, STOP, reset, ENABLE, errors).
#pragma once

#include <cstdint>

namespace softmc::control::spc {

//            SelfTestPassed                StartPulse                 StopFell
//  SelfTest ───────────────► Idle ──────────────────► Running ─────────────────► Stopped
//     │ SelfTestFailed        ▲ ▲  ◄── TasksEnded ───┘   │ Error                 │ │ StartPulse → Running
//     ▼                       │ └──── ResetPulse ◄───────┼──────────────────────┘ │
//   Fatal                     │                          ▼                        │
//                             └──── ResetPulse ◄──── Error ── StartPulse ──────►──┘ (clears, to Stopped)
//  EnableFell from any live state → Disabled; EnableRose → Stopped (programs stay halted).
enum class StartStopState : std::uint8_t { SelfTest, Idle, Running, Stopped, Error, Disabled, Fatal };
inline constexpr int kStartStopStates = 7;

// Events the controller derives from the filtered inputs and the tasks, at most one at a time.
enum class StartStopEvent : std::uint8_t {
  SelfTestPassed,  // the self-test time elapsed with ENABLE=1, STOP=1, START=0
  SelfTestFailed,  // not clearable: power off and on
  StartPulse,      // rising edge of START with STOP=1
  ResetPulse,      // rising edge of START with STOP=0: the reset function
  StopFell,        // STOP 1 → 0
  EnableFell,      // ENABLE 1 → 0
  EnableRose,      // ENABLE 0 → 1
  Error,           // a clearable error is pending (a task's, a drive's)
  TasksEnded,      // every started task has ended (M30) or none was started
};
inline constexpr int kStartStopEvents = 9;

// What the controller does on a transition (a bit set, applied in this order).
namespace ss_action {
inline constexpr std::uint8_t kNone = 0;
inline constexpr std::uint8_t kHaltTasks = 1u << 0;     // halt() both tasks: axes stop at once, no ramp
inline constexpr std::uint8_t kClearErrors = 1u << 1;   // forget the latched errors
inline constexpr std::uint8_t kResetTasks = 1u << 2;    // reset() both tasks: pointers to the first line, MC=1
inline constexpr std::uint8_t kStartTasks = 1u << 3;    // start() the assigned tasks (from their pointers)
inline constexpr std::uint8_t kDisableDrives = 1u << 4; // open the position loops (ENABLE=0)
inline constexpr std::uint8_t kEnableDrives = 1u << 5;  // close them again, resynchronised to the actual position
}  // namespace ss_action

struct StartStopStep {
  StartStopState next;
  std::uint8_t actions;
  friend constexpr bool operator==(const StartStopStep&, const StartStopStep&) = default;
};

// rt-safe. The whole mode logic: every (state, event) pair has a defined result.
StartStopStep start_stop_transition(StartStopState s, StartStopEvent e);

// READY output (S-8: 0 = error): the controller is through its self-test, enabled and error-free.
constexpr bool start_stop_ready(StartStopState s) {
  return s == StartStopState::Idle || s == StartStopState::Running || s == StartStopState::Stopped;
}

const char* to_string(StartStopState s);
const char* to_string(StartStopEvent e);

}  // namespace softmc::control::spc
