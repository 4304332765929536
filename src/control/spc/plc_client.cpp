// The S-10 reference PLC: order and error sequences, timers, MemStop, and the scan that ties them to the wires.
#include "control/spc/plc_client.hpp"

namespace softmc::control::spc {

namespace {
constexpr double kTimeEpsS = 1e-9;  // timers count down by dt; this absorbs the float sum's ulps
constexpr std::array<IoAddress, 2> kClk{sig::kClkA, sig::kClkB};
constexpr std::array<IoAddress, 2> kAck{sig::kAckA, sig::kAckB};
constexpr std::array<IoAddress, 2> kRc{sig::kRcA, sig::kRcB};
}  // namespace

// rt-safe
PlcOrderResult plc_order_transition(PlcOrderStep s, const PlcOrderInputs& in) {
  using S = PlcOrderStep;
  using A = PlcOrderAction;
  switch (s) {
    case S::Idle:
      return {in.has_order ? S::WaitCond : S::Idle, A::None};
    case S::WaitCond:  // 1. CondGen·CondTask (and the shared line bits free) → 2. put the line
      if (in.cond && in.bus_free) return {S::SettleLine, A::PutLine};
      return {s, A::None};
    case S::SettleLine:  // 3. 10 ms → 4. CLK=1
      if (in.timer_expired) return {S::WaitAck, A::ClkOn};
      return {s, A::None};
    case S::WaitAck:  // 5.
      if (in.timer_expired) return {S::Idle, A::OrderError};
      if (in.ack) return {S::WaitAckFall, A::ClkOff};
      return {s, A::None};
    case S::WaitAckFall:  // 6.
      if (in.timer_expired) return {S::Idle, A::OrderError};
      if (!in.ack) return {S::WaitRc, A::StartMotionTimer};
      return {s, A::None};
    case S::WaitRc:  // 7.
      if (in.timer_expired) return {S::Idle, A::MotionError};
      if (in.rc) return {S::Idle, A::Done};
      return {s, A::None};
  }
  return {s, A::None};
}

// rt-safe
PlcErrorResult plc_error_transition(PlcErrorStep s, const PlcErrorInputs& in) {
  using S = PlcErrorStep;
  using A = PlcErrorAction;
  switch (s) {
    case S::None:
      if (in.order_error) return {S::OrderStop, A::StopOrder};
      if (in.motion_error) return {S::MotionStop, A::StopMotion};
      return {s, A::None};
    case S::OrderStop:  // ErrorOrden_2: 30 ms → 3: RESET=1
      if (in.timer_expired) return {S::ResetHigh, A::ResetOn};
      return {s, A::None};
    case S::ResetHigh:  // ErrorOrden_4: 10 ms → 5: RESET=0, STOP=1
      if (in.timer_expired) return {S::WaitInitial, A::ResetOff};
      return {s, A::None};
    case S::WaitInitial:  // ErrorOrden_6
      if (in.timer_expired) return {S::SystemError, A::SystemError};
      if (in.cond) return {S::None, A::Recovered};
      return {s, A::None};
    case S::MotionStop:
      // The source ends the MotionError at STOP=0 (an operator finds the cause). The reference client
      // goes on by itself: STOP back to 1 when the controller kept READY=1 (the remembered stop lets it
      // order again), else the reset of ErrorOrden_3..6.
      if (!in.timer_expired) return {s, A::None};
      if (in.ready) return {S::None, A::StopOff};
      return {S::ResetHigh, A::ResetOn};
    case S::SystemError:
      return {s, A::None};
  }
  return {s, A::None};
}

PlcClient::PlcClient(const PlcTiming& timing, std::size_t queue_capacity) : timing_(timing) {
  for (auto& t : task_) t.queue.reserve(queue_capacity);
}

bool PlcClient::order(TaskId t, int line) {
  auto& side = task_[ix(t)];
  if (line < 0 || line > 31 || side.queue.full()) return false;
  side.queue.push(static_cast<std::uint8_t>(line));
  ++side.count.ordered;
  return true;
}

bool PlcClient::idle() const {
  if (error_ != PlcErrorStep::None || stop_requested_) return false;
  for (const auto& t : task_)
    if (!t.queue.empty() || t.step != PlcOrderStep::Idle) return false;
  return true;
}

// An error sequence takes over: every order under way is abandoned.
void PlcClient::abort_orders() {
  for (auto& t : task_) {
    if (t.step == PlcOrderStep::WaitAck) {
      // CLK was up and no ACK seen: the controller may or may not have latched it. Dropped rather than
      // retried, so that an order is never executed twice.
      ++t.count.uncertain;
      t.queue.pop();
    } else if (t.step == PlcOrderStep::WaitAckFall || t.step == PlcOrderStep::WaitRc) {
      ++t.count.interrupted;
    }
    // WaitCond / SettleLine: CLK never rose, the order stays queued and is tried again.
    t.step = PlcOrderStep::Idle;
    t.clk = false;
    t.acked = false;
  }
  bus_owner_ = -1;
}

// rt-safe
void PlcClient::cycle(double dt_s, IoImage& wires) {
  const bool ready = wires.get(sig::kReady);
  std::array<bool, kTasks> ack{}, rc{};
  for (std::size_t i = 0; i < kTasks; ++i) {
    ack[i] = wires.get(kAck[i]);
    rc[i] = wires.get(kRc[i]);
  }
  for (auto& t : task_) t.timer_s -= dt_s;
  error_timer_s_ -= dt_s;

  const bool cond_gen = enable_ && ready && stop_ && !reset_;
  auto cond_task = [&](std::size_t i) { return !task_[i].clk && !ack[i] && (rc[i] || task_[i].mem_stop); };

  // The PLC's own stop waits for a handshake under way (≤ 10 ms + two filter times) and holds back new
  // ones: an order whose CLK is up when STOP falls could not be told accepted or not.
  bool handshake = false;
  for (const auto& t : task_)
    handshake = handshake || t.step == PlcOrderStep::SettleLine || t.step == PlcOrderStep::WaitAck ||
                t.step == PlcOrderStep::WaitAckFall;

  bool order_error = false, motion_error = false;
  if (error_ == PlcErrorStep::None) {
    for (int k = 0; k < kTasks && !order_error && !motion_error; ++k) {
      const auto i = static_cast<std::size_t>((bus_next_ + k) % kTasks);
      auto& t = task_[i];
      PlcOrderInputs in;
      in.has_order = !t.queue.empty();
      in.cond = cond_gen && cond_task(i);
      in.bus_free = !stop_requested_ && (bus_owner_ < 0 || bus_owner_ == static_cast<int>(i));
      in.timer_expired = t.timer_s <= kTimeEpsS;
      in.ack = ack[i];
      in.rc = rc[i];
      const auto r = plc_order_transition(t.step, in);
      t.step = r.next;
      switch (r.action) {
        case PlcOrderAction::None: break;
        case PlcOrderAction::PutLine:
          line_out_ = t.queue.front();
          bus_owner_ = static_cast<int>(i);
          bus_next_ = static_cast<int>((i + 1) % kTasks);
          t.timer_s = timing_.line_settle_s;
          break;
        case PlcOrderAction::ClkOn:
          t.clk = true;
          t.timer_s = timing_.order_timeout_s;
          break;
        case PlcOrderAction::ClkOff:
          t.clk = false;
          t.timer_s = timing_.order_timeout_s;
          t.acked = true;
          t.mem_stop = false;
          t.count.last_accepted_line = t.queue.front();
          ++t.count.accepted;
          t.queue.pop();
          bus_owner_ = -1;
          break;
        case PlcOrderAction::StartMotionTimer:
          t.timer_s = timing_.motion_timeout_s;
          break;
        case PlcOrderAction::Done:
          ++t.count.completed;
          t.acked = false;
          break;
        case PlcOrderAction::OrderError:
          ++t.count.order_errors;
          if (t.acked) {
            ++t.count.interrupted;  // ACK came but never fell
          } else {
            ++t.count.failed;  // no ACK: the controller refused or missed it
            t.queue.pop();
          }
          t.acked = false;
          t.clk = false;
          if (bus_owner_ == static_cast<int>(i)) bus_owner_ = -1;
          failed_task_ = static_cast<int>(i);
          order_error = true;
          break;
        case PlcOrderAction::MotionError:
          ++t.count.motion_errors;
          ++t.count.interrupted;
          t.acked = false;
          failed_task_ = static_cast<int>(i);
          motion_error = true;
          break;
      }
    }
  }

  PlcErrorInputs ei;
  ei.order_error = order_error;
  ei.motion_error = motion_error || (stop_requested_ && !handshake);
  ei.timer_expired = error_timer_s_ <= kTimeEpsS;
  ei.cond = cond_gen && cond_task(static_cast<std::size_t>(failed_task_));
  ei.ready = ready;
  const auto er = plc_error_transition(error_, ei);
  error_ = er.next;
  switch (er.action) {
    case PlcErrorAction::None:
    case PlcErrorAction::Recovered:
    case PlcErrorAction::SystemError: break;
    case PlcErrorAction::StopOrder:
      abort_orders();
      stop_ = false;
      error_timer_s_ = timing_.error_stop_wait_s;
      break;
    case PlcErrorAction::StopMotion:
      abort_orders();
      stop_ = false;
      stop_requested_ = false;
      // S-9: RC stays 0 after a stop; remembering the stop is what lets the PLC order again.
      for (auto& t : task_) t.mem_stop = true;
      error_timer_s_ = timing_.motion_stop_hold_s;
      break;
    case PlcErrorAction::ResetOn:
      reset_ = true;
      error_timer_s_ = timing_.reset_pulse_s;
      break;
    case PlcErrorAction::ResetOff:
      reset_ = false;
      stop_ = true;
      error_timer_s_ = timing_.initial_signals_timeout_s;
      break;
    case PlcErrorAction::StopOff:
      stop_ = true;
      break;
  }

  // The PLC's outputs onto the controller's input terminals.
  wires.set_line_bits(line_out_);
  for (std::size_t i = 0; i < kTasks; ++i) wires.set(kClk[i], task_[i].clk);
  wires.set(sig::kStop, stop_);
  wires.set(sig::kReset, reset_);
  wires.set(sig::kEnable, enable_);
}

const char* to_string(PlcOrderStep s) {
  switch (s) {
    case PlcOrderStep::Idle: return "Idle";
    case PlcOrderStep::WaitCond: return "WaitCond";
    case PlcOrderStep::SettleLine: return "SettleLine";
    case PlcOrderStep::WaitAck: return "WaitAck";
    case PlcOrderStep::WaitAckFall: return "WaitAckFall";
    case PlcOrderStep::WaitRc: return "WaitRc";
  }
  return "?";
}

const char* to_string(PlcOrderAction a) {
  switch (a) {
    case PlcOrderAction::None: return "None";
    case PlcOrderAction::PutLine: return "PutLine";
    case PlcOrderAction::ClkOn: return "ClkOn";
    case PlcOrderAction::ClkOff: return "ClkOff";
    case PlcOrderAction::StartMotionTimer: return "StartMotionTimer";
    case PlcOrderAction::Done: return "Done";
    case PlcOrderAction::OrderError: return "OrderError";
    case PlcOrderAction::MotionError: return "MotionError";
  }
  return "?";
}

const char* to_string(PlcErrorStep s) {
  switch (s) {
    case PlcErrorStep::None: return "None";
    case PlcErrorStep::OrderStop: return "OrderStop";
    case PlcErrorStep::ResetHigh: return "ResetHigh";
    case PlcErrorStep::WaitInitial: return "WaitInitial";
    case PlcErrorStep::MotionStop: return "MotionStop";
    case PlcErrorStep::SystemError: return "SystemError";
  }
  return "?";
}

const char* to_string(PlcErrorAction a) {
  switch (a) {
    case PlcErrorAction::None: return "None";
    case PlcErrorAction::StopOrder: return "StopOrder";
    case PlcErrorAction::StopMotion: return "StopMotion";
    case PlcErrorAction::ResetOn: return "ResetOn";
    case PlcErrorAction::ResetOff: return "ResetOff";
    case PlcErrorAction::StopOff: return "StopOff";
    case PlcErrorAction::Recovered: return "Recovered";
    case PlcErrorAction::SystemError: return "SystemError";
  }
  return "?";
}

}  // namespace softmc::control::spc
