// The S-8 Start/Stop transition function.
#include "control/spc/start_stop.hpp"

namespace softmc::control::spc {

// rt-safe
StartStopStep start_stop_transition(StartStopState s, StartStopEvent e) {
  using S = StartStopState;
  using E = StartStopEvent;
  using namespace ss_action;
  switch (s) {
    case S::SelfTest:
      // Only the self-test's outcome matters; the controller restarts its timer while the
      // power-up condition (ENABLE=1, STOP=1, START=0) does not hold.
      if (e == E::SelfTestPassed) return {S::Idle, kResetTasks};  // READY=1, MC=1, SYNC_O=0
      if (e == E::SelfTestFailed) return {S::Fatal, kNone};
      return {S::SelfTest, kNone};

    case S::Idle:
    case S::Running:
    case S::Stopped:
      switch (e) {
        case E::StartPulse:
          return {S::Running, s == S::Running ? kNone : kStartTasks};
        case E::ResetPulse:
          return {S::Idle, kHaltTasks | kClearErrors | kResetTasks};
        case E::StopFell:
          return {s == S::Idle ? S::Idle : S::Stopped, kHaltTasks};
        case E::EnableFell:
          return {S::Disabled, kHaltTasks | kDisableDrives};
        case E::Error:
          return {S::Error, kHaltTasks};
        case E::TasksEnded:
          // Programs halted by STOP have not ended: only a running machine goes back to Idle.
          return {s == S::Running ? S::Idle : s, kNone};
        case E::EnableRose:
        case E::SelfTestPassed:
        case E::SelfTestFailed:
          return {s, kNone};
      }
      break;

    case S::Error:
      switch (e) {
        case E::StartPulse:  // S-8: with a clearable error pending the START pulse clears it instead
          return {S::Stopped, kClearErrors};
        case E::ResetPulse:
          return {S::Idle, kHaltTasks | kClearErrors | kResetTasks};
        case E::EnableFell:
          return {S::Disabled, kHaltTasks | kDisableDrives};
        case E::StopFell:
          return {S::Error, kHaltTasks};
        default:
          return {S::Error, kNone};
      }

    case S::Disabled:
      // Back on, the programs stay halted: the operator resumes with START or resets. A still
      // pending error comes back as an Error event on the next cycle.
      if (e == E::EnableRose) return {S::Stopped, kEnableDrives};
      return {S::Disabled, kNone};

    case S::Fatal:
      return {S::Fatal, kNone};
  }
  return {s, kNone};
}

const char* to_string(StartStopState s) {
  switch (s) {
    case StartStopState::SelfTest: return "SelfTest";
    case StartStopState::Idle: return "Idle";
    case StartStopState::Running: return "Running";
    case StartStopState::Stopped: return "Stopped";
    case StartStopState::Error: return "Error";
    case StartStopState::Disabled: return "Disabled";
    case StartStopState::Fatal: return "Fatal";
  }
  return "?";
}

const char* to_string(StartStopEvent e) {
  switch (e) {
    case StartStopEvent::SelfTestPassed: return "SelfTestPassed";
    case StartStopEvent::SelfTestFailed: return "SelfTestFailed";
    case StartStopEvent::StartPulse: return "StartPulse";
    case StartStopEvent::ResetPulse: return "ResetPulse";
    case StartStopEvent::StopFell: return "StopFell";
    case StartStopEvent::EnableFell: return "EnableFell";
    case StartStopEvent::EnableRose: return "EnableRose";
    case StartStopEvent::Error: return "Error";
    case StartStopEvent::TasksEnded: return "TasksEnded";
  }
  return "?";
}

}  // namespace softmc::control::spc
