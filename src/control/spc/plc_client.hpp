// S-10: the reference PLC of Record Select, exactly the source's sequence, as a cyclic state machine
// that sees the controller only through the wires (the controller's outputs in, its inputs out).
#pragma once

#include <array>
#include <cstdint>

#include "control/spc/io_image.hpp"
#include "core/ring.hpp"

namespace softmc::control::spc {

enum class TaskId : std::uint8_t;  // task.hpp: A = 0, B = 1

// ---- One task's order sequence (steps 1..7 of S-10).
//   CondGen  = ENABLE·READY·STOP·¬RESET
//   CondTask = ¬CLK·¬ACK·(RC + MemStop)
//
//  Idle ─order queued─► WaitCond ─CondGen·CondTask·bus free / put line bits─► SettleLine
//  SettleLine ─10 ms / CLK=1, order timer─► WaitAck ─ACK=1 / CLK=0, order timer─► WaitAckFall
//  WaitAckFall ─ACK=0 / motion timer─► WaitRc ─RC=1─► Idle (done)
//  WaitAck, WaitAckFall ─order timer─► OrderError;   WaitRc ─motion timer─► MotionError
enum class PlcOrderStep : std::uint8_t { Idle, WaitCond, SettleLine, WaitAck, WaitAckFall, WaitRc };
inline constexpr int kPlcOrderSteps = 6;

struct PlcOrderInputs {
  bool has_order = false;      // an order is queued for this task
  bool cond = false;           // CondGen·CondTask
  bool bus_free = false;       // the line bits B0..B4 are not held by the other task's order
  bool timer_expired = false;  // the step's timer (10 ms, order timer or motion timer)
  bool ack = false;
  bool rc = false;
};

enum class PlcOrderAction : std::uint8_t {
  None,
  PutLine,           // step 2: line bits out, take the bus, start the 10 ms timer (step 3)
  ClkOn,             // step 4: CLK=1, start the order timer
  ClkOff,            // step 5: ACK seen: CLK=0, restart the order timer, release the bus, forget MemStop
  StartMotionTimer,  // step 6: ACK fell: the order is accepted
  Done,              // step 7: RC=1
  OrderError,
  MotionError,
};

struct PlcOrderResult {
  PlcOrderStep next;
  PlcOrderAction action;
  friend constexpr bool operator==(const PlcOrderResult&, const PlcOrderResult&) = default;
};

// rt-safe. The source checks the timer before the signal in steps 5, 6 and 7; so does this.
PlcOrderResult plc_order_transition(PlcOrderStep s, const PlcOrderInputs& in);

// ---- The error sequences (OrderError, MotionError, SystemError of S-10).
//  None ─order error / CLK=0, STOP=0─► OrderStop ─30 ms / RESET=1─► ResetHigh ─10 ms / RESET=0, STOP=1─► WaitInitial
//  WaitInitial ─CondGen·CondTask─► None;  ─initial-signals timer─► SystemError (power off and on)
//  None ─motion error or stop request / STOP=0, MemStop─► MotionStop ─hold, READY=1 / STOP=1─► None
//                                                         MotionStop ─hold, READY=0 / RESET=1─► ResetHigh
enum class PlcErrorStep : std::uint8_t { None, OrderStop, ResetHigh, WaitInitial, MotionStop, SystemError };
inline constexpr int kPlcErrorSteps = 6;

struct PlcErrorInputs {
  bool order_error = false;
  bool motion_error = false;  // a MotionError, or the PLC's own stop request
  bool timer_expired = false;
  bool cond = false;          // CondGen·CondTask of the task that failed
  bool ready = false;
};

enum class PlcErrorAction : std::uint8_t {
  None,
  StopOrder,   // ErrorOrden_1: CLK=0, STOP=0; wait 30 ms
  StopMotion,  // ErrorMovimiento_1: STOP=0, MemStop=1; hold
  ResetOn,     // ErrorOrden_3: RESET=1; wait 10 ms
  ResetOff,    // ErrorOrden_5: RESET=0, STOP=1; start the initial-signals timer
  StopOff,     // after a MotionError with READY still 1: STOP=1, orders go on thanks to MemStop
  Recovered,   // ErrorOrden_6: CondGen·CondTask holds again
  SystemError,
};

struct PlcErrorResult {
  PlcErrorStep next;
  PlcErrorAction action;
  friend constexpr bool operator==(const PlcErrorResult&, const PlcErrorResult&) = default;
};

// rt-safe
PlcErrorResult plc_error_transition(PlcErrorStep s, const PlcErrorInputs& in);

// Times of the sequence; the source's values where it gives them.
struct PlcTiming {
  double line_settle_s = 0.010;            // step 3 (the controller's 5 ms input filter + margin)
  double order_timeout_s = 0.100;          // order timer, steps 5 and 6
  double motion_timeout_s = 10.0;          // motion timer, step 7
  double error_stop_wait_s = 0.030;        // ErrorOrden_2
  double reset_pulse_s = 0.010;            // ErrorOrden_4
  double initial_signals_timeout_s = 1.0;  // ErrorOrden_5..6
  double motion_stop_hold_s = 0.030;       // decision: STOP=0 held this long after a MotionError or stop request
};

struct PlcCounters {
  std::uint64_t ordered = 0;      // orders taken into the queue
  std::uint64_t accepted = 0;     // ACK seen: the controller took the order
  std::uint64_t completed = 0;    // RC seen at the end of the motion
  std::uint64_t failed = 0;       // OrderError before ACK: the order is dropped, not retried
  std::uint64_t interrupted = 0;  // accepted, but a stop or error came before RC
  std::uint64_t uncertain = 0;    // CLK was up when the other task's error aborted it: dropped, may have run
  std::uint64_t order_errors = 0;
  std::uint64_t motion_errors = 0;
  std::uint8_t last_accepted_line = 0;
};

class PlcClient {
 public:
  static constexpr int kTasks = 2;

  explicit PlcClient(const PlcTiming& timing = {}, std::size_t queue_capacity = 1024);

  // Queue an order for a task (line 0..31). Not rt (the PLC's program decides what to order).
  bool order(TaskId task, int line);
  // The PLC's own stop (operator button, light curtain): STOP=0 for motion_stop_hold_s, MemStop.
  void request_stop() { stop_requested_ = true; }
  void set_enable(bool on) { enable_ = on; }

  // rt-safe: one PLC scan. Reads READY, RC_x, ACK_x from wires.outputs and writes B0..B4, CLK_x, STOP,
  // RESET, ENABLE into wires.inputs (the other input bits are left alone).
  void cycle(double dt_s, IoImage& wires);

  const PlcCounters& counters(TaskId t) const { return task_[ix(t)].count; }
  PlcOrderStep order_step(TaskId t) const { return task_[ix(t)].step; }
  PlcErrorStep error_step() const { return error_; }
  bool system_error() const { return error_ == PlcErrorStep::SystemError; }
  bool mem_stop(TaskId t) const { return task_[ix(t)].mem_stop; }
  std::size_t pending(TaskId t) const { return task_[ix(t)].queue.size(); }
  // Nothing queued, no order under way, no error sequence running.
  bool idle() const;

 private:
  struct TaskSide {
    core::Ring<std::uint8_t> queue;
    PlcOrderStep step = PlcOrderStep::Idle;
    double timer_s = 0;
    bool clk = false;
    bool mem_stop = false;
    bool acked = false;  // the current order got its ACK
    PlcCounters count;
  };
  static std::size_t ix(TaskId t) { return static_cast<std::size_t>(t); }
  void abort_orders();

  PlcTiming timing_;
  std::array<TaskSide, kTasks> task_;
  PlcErrorStep error_ = PlcErrorStep::None;
  double error_timer_s_ = 0;
  int failed_task_ = 0;
  int bus_owner_ = -1;  // task holding B0..B4 from step 2 to the ACK
  int bus_next_ = 0;    // fairness: who gets the bus when both wait
  std::uint8_t line_out_ = 0;
  bool enable_ = true, stop_ = true, reset_ = false;
  bool stop_requested_ = false;
};

const char* to_string(PlcOrderStep s);
const char* to_string(PlcOrderAction a);
const char* to_string(PlcErrorStep s);
const char* to_string(PlcErrorAction a);

}  // namespace softmc::control::spc
