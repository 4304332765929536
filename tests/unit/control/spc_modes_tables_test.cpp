// Table-driven tests of every transition of the S-8/S-9/S-10 state machines: each table below is an
// independent statement of the spec, one row per state, one column per event.
#include <gtest/gtest.h>

#include "control/spc/plc_client.hpp"
#include "control/spc/record_select.hpp"
#include "control/spc/start_stop.hpp"

namespace softmc::control::spc {
namespace {

// ---------------------------------------------------------------- S-8 Start/Stop

TEST(Spc200, S8_StartStopEveryTransition) {
  using S = StartStopState;
  using namespace ss_action;
  constexpr auto H = kHaltTasks, C = kClearErrors, R = kResetTasks, G = kStartTasks, D = kDisableDrives,
                 N = kEnableDrives;
  constexpr std::uint8_t O = kNone;
  // Columns: SelfTestPassed SelfTestFailed StartPulse ResetPulse StopFell EnableFell EnableRose Error TasksEnded
  const StartStopStep table[kStartStopStates][kStartStopEvents] = {
      /* SelfTest */ {{S::Idle, R}, {S::Fatal, O}, {S::SelfTest, O}, {S::SelfTest, O}, {S::SelfTest, O},
                      {S::SelfTest, O}, {S::SelfTest, O}, {S::SelfTest, O}, {S::SelfTest, O}},
      /* Idle */ {{S::Idle, O}, {S::Idle, O}, {S::Running, G}, {S::Idle, H | C | R}, {S::Idle, H},
                  {S::Disabled, H | D}, {S::Idle, O}, {S::Error, H}, {S::Idle, O}},
      /* Running */ {{S::Running, O}, {S::Running, O}, {S::Running, O}, {S::Idle, H | C | R}, {S::Stopped, H},
                     {S::Disabled, H | D}, {S::Running, O}, {S::Error, H}, {S::Idle, O}},
      /* Stopped */ {{S::Stopped, O}, {S::Stopped, O}, {S::Running, G}, {S::Idle, H | C | R}, {S::Stopped, H},
                     {S::Disabled, H | D}, {S::Stopped, O}, {S::Error, H}, {S::Stopped, O}},
      /* Error */ {{S::Error, O}, {S::Error, O}, {S::Stopped, C}, {S::Idle, H | C | R}, {S::Error, H},
                   {S::Disabled, H | D}, {S::Error, O}, {S::Error, O}, {S::Error, O}},
      /* Disabled */ {{S::Disabled, O}, {S::Disabled, O}, {S::Disabled, O}, {S::Disabled, O}, {S::Disabled, O},
                      {S::Disabled, O}, {S::Stopped, N}, {S::Disabled, O}, {S::Disabled, O}},
      /* Fatal */ {{S::Fatal, O}, {S::Fatal, O}, {S::Fatal, O}, {S::Fatal, O}, {S::Fatal, O}, {S::Fatal, O},
                   {S::Fatal, O}, {S::Fatal, O}, {S::Fatal, O}},
  };
  for (int s = 0; s < kStartStopStates; ++s)
    for (int e = 0; e < kStartStopEvents; ++e) {
      const auto st = static_cast<S>(s);
      const auto ev = static_cast<StartStopEvent>(e);
      const auto got = start_stop_transition(st, ev);
      EXPECT_EQ(got.next, table[s][e].next) << to_string(st) << " + " << to_string(ev) << " → " << to_string(got.next);
      EXPECT_EQ(got.actions, table[s][e].actions) << to_string(st) << " + " << to_string(ev);
    }
}

TEST(Spc200, S8_ReadyOnlyInLiveErrorFreeStates) {
  EXPECT_FALSE(start_stop_ready(StartStopState::SelfTest));
  EXPECT_TRUE(start_stop_ready(StartStopState::Idle));
  EXPECT_TRUE(start_stop_ready(StartStopState::Running));
  EXPECT_TRUE(start_stop_ready(StartStopState::Stopped));
  EXPECT_FALSE(start_stop_ready(StartStopState::Error));
  EXPECT_FALSE(start_stop_ready(StartStopState::Disabled));  // S-8: ENABLE=0 → READY=0
  EXPECT_FALSE(start_stop_ready(StartStopState::Fatal));
}

// ---------------------------------------------------------------- S-9 Record Select

TEST(Spc200, S9_RecordSystemEveryTransition) {
  using S = RecordSystemState;
  using namespace rs_action;
  constexpr auto H = kHaltTasks, C = kClearErrors, R = kResetTasks, D = kDisableDrives, N = kEnableDrives;
  constexpr std::uint8_t O = kNone;
  // Columns: SelfTestPassed SelfTestFailed MotionFault Error Acknowledge ResetFn StopFell EnableFell EnableRose
  const RecordSystemStep table[kRecordSystemStates][kRecordSystemEvents] = {
      /* SelfTest */ {{S::Ready, R}, {S::Fatal, O}, {S::SelfTest, O}, {S::SelfTest, O}, {S::SelfTest, O},
                      {S::SelfTest, O}, {S::SelfTest, O}, {S::SelfTest, O}, {S::SelfTest, O}},
      /* Ready */ {{S::Ready, O}, {S::Ready, O}, {S::Error, H}, {S::Error, O}, {S::Ready, C}, {S::Ready, C | R},
                   {S::Ready, H}, {S::Disabled, H | D}, {S::Ready, O}},
      /* Error */ {{S::Error, O}, {S::Error, O}, {S::Error, H}, {S::Error, O}, {S::Ready, C}, {S::Ready, C | R},
                   {S::Error, H}, {S::Disabled, H | D}, {S::Error, O}},
      /* Disabled */ {{S::Disabled, O}, {S::Disabled, O}, {S::Disabled, O}, {S::Disabled, O}, {S::Disabled, O},
                      {S::Disabled, O}, {S::Disabled, O}, {S::Disabled, O}, {S::Ready, N}},
      /* Fatal */ {{S::Fatal, O}, {S::Fatal, O}, {S::Fatal, O}, {S::Fatal, O}, {S::Fatal, O}, {S::Fatal, O},
                   {S::Fatal, O}, {S::Fatal, O}, {S::Fatal, O}},
  };
  for (int s = 0; s < kRecordSystemStates; ++s)
    for (int e = 0; e < kRecordSystemEvents; ++e) {
      const auto st = static_cast<S>(s);
      const auto ev = static_cast<RecordSystemEvent>(e);
      const auto got = record_system_transition(st, ev);
      EXPECT_EQ(got.next, table[s][e].next) << to_string(st) << " + " << to_string(ev) << " → " << to_string(got.next);
      EXPECT_EQ(got.actions, table[s][e].actions) << to_string(st) << " + " << to_string(ev);
    }
}

TEST(Spc200, S9_RecordTaskEveryTransition) {
  using S = RecordTaskState;
  using A = RecordTaskAction;
  // Columns: Order OrderBlocked ClkFell MotionDone Halt Reset
  const RecordTaskStep table[kRecordTaskStates][kRecordTaskEvents] = {
      /* Ready */ {{S::Accepted, A::Accept}, {S::Ready, A::Refuse}, {S::Ready, A::None}, {S::Ready, A::None},
                   {S::Ready, A::None}, {S::Ready, A::None}},
      /* Accepted */ {{S::Accepted, A::Refuse}, {S::Accepted, A::Refuse}, {S::Running, A::None},
                      {S::Finished, A::None}, {S::StoppedAcked, A::None}, {S::Ready, A::None}},
      /* Running */ {{S::Running, A::Refuse}, {S::Running, A::Refuse}, {S::Running, A::None}, {S::Ready, A::None},
                     {S::Stopped, A::None}, {S::Ready, A::None}},
      /* Finished */ {{S::Finished, A::Refuse}, {S::Finished, A::Refuse}, {S::Ready, A::None},
                      {S::Finished, A::None}, {S::Finished, A::None}, {S::Ready, A::None}},
      /* Stopped */ {{S::Accepted, A::Accept}, {S::Stopped, A::Refuse}, {S::Stopped, A::None},
                     {S::Stopped, A::None}, {S::Stopped, A::None}, {S::Ready, A::None}},
      /* StoppedAcked */ {{S::StoppedAcked, A::Refuse}, {S::StoppedAcked, A::Refuse}, {S::Stopped, A::None},
                          {S::StoppedAcked, A::None}, {S::StoppedAcked, A::None}, {S::Ready, A::None}},
  };
  for (int s = 0; s < kRecordTaskStates; ++s)
    for (int e = 0; e < kRecordTaskEvents; ++e) {
      const auto st = static_cast<S>(s);
      const auto ev = static_cast<RecordTaskEvent>(e);
      const auto got = record_task_transition(st, ev);
      EXPECT_EQ(got.next, table[s][e].next) << to_string(st) << " + " << to_string(ev) << " → " << to_string(got.next);
      EXPECT_EQ(got.action, table[s][e].action) << to_string(st) << " + " << to_string(ev);
    }
}

TEST(Spc200, S9_RcAndAckPerTaskState) {
  struct Row {
    RecordTaskState s;
    bool rc, ack;
  };
  const Row rows[] = {{RecordTaskState::Ready, true, false},    {RecordTaskState::Accepted, false, true},
                      {RecordTaskState::Running, false, false}, {RecordTaskState::Finished, true, true},
                      {RecordTaskState::Stopped, false, false}, {RecordTaskState::StoppedAcked, false, true}};
  static_assert(std::size(rows) == kRecordTaskStates);
  for (const auto& r : rows) {
    EXPECT_EQ(record_rc(r.s), r.rc) << to_string(r.s);
    EXPECT_EQ(record_ack(r.s), r.ack) << to_string(r.s);
  }
}

// ---------------------------------------------------------------- S-10 reference PLC

TEST(Spc200, S10_PlcOrderEveryTransition) {
  using S = PlcOrderStep;
  using A = PlcOrderAction;
  struct Row {
    S from;
    PlcOrderInputs in;  // has_order, cond, bus_free, timer_expired, ack, rc
    S to;
    A action;
  };
  const Row rows[] = {
      {S::Idle, {false, true, true, true, false, true}, S::Idle, A::None},
      {S::Idle, {true, false, false, false, false, false}, S::WaitCond, A::None},
      // 1. CondGen·CondTask, and the line bits not held by the other task
      {S::WaitCond, {true, false, true, true, false, true}, S::WaitCond, A::None},
      {S::WaitCond, {true, true, false, true, false, true}, S::WaitCond, A::None},
      {S::WaitCond, {true, true, true, false, false, true}, S::SettleLine, A::PutLine},
      // 3. 10 ms
      {S::SettleLine, {true, true, true, false, true, true}, S::SettleLine, A::None},
      {S::SettleLine, {true, false, false, true, false, false}, S::WaitAck, A::ClkOn},
      // 5. timer first, then ACK
      {S::WaitAck, {true, true, true, false, false, false}, S::WaitAck, A::None},
      {S::WaitAck, {true, true, true, false, true, false}, S::WaitAckFall, A::ClkOff},
      {S::WaitAck, {true, true, true, true, true, false}, S::Idle, A::OrderError},
      {S::WaitAck, {true, true, true, true, false, false}, S::Idle, A::OrderError},
      // 6.
      {S::WaitAckFall, {true, true, true, false, true, false}, S::WaitAckFall, A::None},
      {S::WaitAckFall, {true, true, true, false, false, false}, S::WaitRc, A::StartMotionTimer},
      {S::WaitAckFall, {true, true, true, true, false, false}, S::Idle, A::OrderError},
      // 7.
      {S::WaitRc, {true, true, true, false, false, false}, S::WaitRc, A::None},
      {S::WaitRc, {false, false, false, false, false, true}, S::Idle, A::Done},
      {S::WaitRc, {true, true, true, true, false, true}, S::Idle, A::MotionError},
      {S::WaitRc, {true, true, true, true, false, false}, S::Idle, A::MotionError},
  };
  bool covered[kPlcOrderSteps] = {};
  for (const auto& r : rows) {
    const auto got = plc_order_transition(r.from, r.in);
    EXPECT_EQ(got.next, r.to) << to_string(r.from) << " → " << to_string(got.next);
    EXPECT_EQ(got.action, r.action) << to_string(r.from) << ": " << to_string(got.action);
    covered[static_cast<int>(r.from)] = true;
  }
  for (bool c : covered) EXPECT_TRUE(c);
}

TEST(Spc200, S10_PlcErrorEveryTransition) {
  using S = PlcErrorStep;
  using A = PlcErrorAction;
  struct Row {
    S from;
    PlcErrorInputs in;  // order_error, motion_error, timer_expired, cond, ready
    S to;
    A action;
  };
  const Row rows[] = {
      {S::None, {false, false, true, true, true}, S::None, A::None},
      {S::None, {true, false, false, false, false}, S::OrderStop, A::StopOrder},
      {S::None, {true, true, false, false, false}, S::OrderStop, A::StopOrder},
      {S::None, {false, true, false, false, true}, S::MotionStop, A::StopMotion},
      // ErrorOrden_2 → 3
      {S::OrderStop, {false, false, false, true, true}, S::OrderStop, A::None},
      {S::OrderStop, {false, false, true, false, false}, S::ResetHigh, A::ResetOn},
      // 4 → 5
      {S::ResetHigh, {false, false, false, true, true}, S::ResetHigh, A::None},
      {S::ResetHigh, {false, false, true, false, false}, S::WaitInitial, A::ResetOff},
      // 6: timer first
      {S::WaitInitial, {false, false, false, false, true}, S::WaitInitial, A::None},
      {S::WaitInitial, {false, false, false, true, true}, S::None, A::Recovered},
      {S::WaitInitial, {false, false, true, true, true}, S::SystemError, A::SystemError},
      // MotionError
      {S::MotionStop, {false, false, false, true, true}, S::MotionStop, A::None},
      {S::MotionStop, {false, false, true, false, true}, S::None, A::StopOff},
      {S::MotionStop, {false, false, true, true, false}, S::ResetHigh, A::ResetOn},
      // SystemError: power off and on
      {S::SystemError, {true, true, true, true, true}, S::SystemError, A::None},
  };
  bool covered[kPlcErrorSteps] = {};
  for (const auto& r : rows) {
    const auto got = plc_error_transition(r.from, r.in);
    EXPECT_EQ(got.next, r.to) << to_string(r.from) << " → " << to_string(got.next);
    EXPECT_EQ(got.action, r.action) << to_string(r.from) << ": " << to_string(got.action);
    covered[static_cast<int>(r.from)] = true;
  }
  for (bool c : covered) EXPECT_TRUE(c);
}

}  // namespace
}  // namespace softmc::control::spc
