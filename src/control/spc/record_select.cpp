// The S-9 Record Select transition functions (system READY machine and per-task order handshake).
#include "control/spc/record_select.hpp"

namespace softmc::control::spc {

// rt-safe
RecordSystemStep record_system_transition(RecordSystemState s, RecordSystemEvent e) {
  using S = RecordSystemState;
  using E = RecordSystemEvent;
  using namespace rs_action;
  switch (s) {
    case S::SelfTest:
      if (e == E::SelfTestPassed) return {S::Ready, kResetTasks};  // READY=1, RC=1, ACK=0
      if (e == E::SelfTestFailed) return {S::Fatal, kNone};
      return {S::SelfTest, kNone};

    case S::Ready:
    case S::Error:
      switch (e) {
        case E::MotionFault: return {S::Error, kHaltTasks};
        case E::Error: return {S::Error, kNone};
        case E::Acknowledge: return {S::Ready, kClearErrors};
        case E::ResetFn: return {S::Ready, kClearErrors | kResetTasks};
        case E::StopFell: return {s, kHaltTasks};
        case E::EnableFell: return {S::Disabled, kHaltTasks | kDisableDrives};
        case E::EnableRose:
        case E::SelfTestPassed:
        case E::SelfTestFailed: return {s, kNone};
      }
      break;

    case S::Disabled:
      // Back on with READY=1; an error still latched comes back as an event on the next cycle.
      if (e == E::EnableRose) return {S::Ready, kEnableDrives};
      return {S::Disabled, kNone};

    case S::Fatal:
      return {S::Fatal, kNone};
  }
  return {s, kNone};
}

// rt-safe
RecordTaskStep record_task_transition(RecordTaskState s, RecordTaskEvent e) {
  using S = RecordTaskState;
  using E = RecordTaskEvent;
  using A = RecordTaskAction;
  if (e == E::Reset) return {S::Ready, A::None};  // RC=1, ACK=0 from anywhere
  // S-9 decision: a CLK edge that cannot be accepted is a refused order (an error, READY=0), never
  // silently dropped — the PLC's order timer would otherwise be the only one to notice.
  if (e == E::OrderBlocked) return {s, A::Refuse};
  switch (s) {
    case S::Ready:
      if (e == E::Order) return {S::Accepted, A::Accept};
      return {S::Ready, A::None};  // ClkFell, MotionDone, Halt: nothing is moving for this task
    case S::Accepted:
      if (e == E::Order) return {s, A::Refuse};  // busy (cannot occur without a CLK fall in between)
      if (e == E::ClkFell) return {S::Running, A::None};  // S-9: ACK falls with CLK
      if (e == E::MotionDone) return {S::Finished, A::None};
      if (e == E::Halt) return {S::StoppedAcked, A::None};
      break;
    case S::Running:
      if (e == E::Order) return {s, A::Refuse};  // busy: RC=0
      if (e == E::MotionDone) return {S::Ready, A::None};
      if (e == E::Halt) return {S::Stopped, A::None};
      return {s, A::None};
    case S::Finished:
      if (e == E::Order) return {s, A::Refuse};
      if (e == E::ClkFell) return {S::Ready, A::None};
      return {s, A::None};  // MotionDone again, or a stop after the motion ended: RC stays 1
    case S::Stopped:
      // S-9: after a stop RC stays 0, and the PLC (which remembers the stop) may order again.
      if (e == E::Order) return {S::Accepted, A::Accept};
      return {s, A::None};
    case S::StoppedAcked:
      if (e == E::Order) return {s, A::Refuse};
      if (e == E::ClkFell) return {S::Stopped, A::None};
      return {s, A::None};
  }
  return {s, A::None};
}

const char* to_string(RecordSystemState s) {
  switch (s) {
    case RecordSystemState::SelfTest: return "SelfTest";
    case RecordSystemState::Ready: return "Ready";
    case RecordSystemState::Error: return "Error";
    case RecordSystemState::Disabled: return "Disabled";
    case RecordSystemState::Fatal: return "Fatal";
  }
  return "?";
}

const char* to_string(RecordSystemEvent e) {
  switch (e) {
    case RecordSystemEvent::SelfTestPassed: return "SelfTestPassed";
    case RecordSystemEvent::SelfTestFailed: return "SelfTestFailed";
    case RecordSystemEvent::MotionFault: return "MotionFault";
    case RecordSystemEvent::Error: return "Error";
    case RecordSystemEvent::Acknowledge: return "Acknowledge";
    case RecordSystemEvent::ResetFn: return "ResetFn";
    case RecordSystemEvent::StopFell: return "StopFell";
    case RecordSystemEvent::EnableFell: return "EnableFell";
    case RecordSystemEvent::EnableRose: return "EnableRose";
  }
  return "?";
}

const char* to_string(RecordTaskState s) {
  switch (s) {
    case RecordTaskState::Ready: return "Ready";
    case RecordTaskState::Accepted: return "Accepted";
    case RecordTaskState::Running: return "Running";
    case RecordTaskState::Finished: return "Finished";
    case RecordTaskState::Stopped: return "Stopped";
    case RecordTaskState::StoppedAcked: return "StoppedAcked";
  }
  return "?";
}

const char* to_string(RecordTaskEvent e) {
  switch (e) {
    case RecordTaskEvent::Order: return "Order";
    case RecordTaskEvent::OrderBlocked: return "OrderBlocked";
    case RecordTaskEvent::ClkFell: return "ClkFell";
    case RecordTaskEvent::MotionDone: return "MotionDone";
    case RecordTaskEvent::Halt: return "Halt";
    case RecordTaskEvent::Reset: return "Reset";
  }
  return "?";
}

const char* to_string(RecordTaskAction a) {
  switch (a) {
    case RecordTaskAction::None: return "None";
    case RecordTaskAction::Accept: return "Accept";
    case RecordTaskAction::Refuse: return "Refuse";
  }
  return "?";
}

}  // namespace softmc::control::spc
