// The SPC200 controller cycle: filter the inputs, run the mode's state machines, run the tasks, publish.
#include "control/spc/controller.hpp"

#include <utility>

namespace softmc::control::spc {

namespace {
constexpr double kTimeEpsS = 1e-9;
constexpr std::array<IoAddress, 2> kClk{sig::kClkA, sig::kClkB};
constexpr std::array<IoAddress, 2> kMc{sig::kMcA, sig::kMcB};
constexpr std::array<IoAddress, 2> kRc{sig::kRcA, sig::kRcB};
constexpr std::array<IoAddress, 2> kAck{sig::kAckA, sig::kAckB};
constexpr std::array<IoAddress, 2> kSyncO{sig::kSyncOA, sig::kSyncOB};

bool bit(const std::array<std::uint16_t, kIoModules>& w, IoAddress a) { return (w[a.module] >> a.bit) & 1u; }
}  // namespace

const char* to_string(SpcMode m) { return m == SpcMode::StartStop ? "StartStop" : "RecordSelect"; }

ControllerConfig controller_config_from(const machine::SpcMachineConfig& spc) {
  ControllerConfig c;
  c.mode = spc.mode == "record-select" ? SpcMode::RecordSelect : SpcMode::StartStop;
  c.program_a = spc.task_a;
  c.program_b = spc.task_b;
  c.self_test_s = spc.self_test_s;
  c.input_filter_s = spc.input_filter_s;
  return c;
}

Controller::Controller(const ControllerConfig& cfg, const program::spc::ProgramStore& store, Registers& regs,
                       TaskAxes& axes)
    : cfg_(cfg), axes_(axes), task_a_(TaskId::A, store, regs, axes), task_b_(TaskId::B, store, regs, axes) {
  task_a_.set_program(cfg.program_a);
  task_b_.set_program(cfg.program_b);
  filter_.set_all(cfg.input_filter_s);
}

// rt-safe
void Controller::update(double dt_s) {
  // 1 read: the terminals through the filter. The first cycle takes the terminals as they are, so
  // that power-up levels are not mistaken for edges.
  if (first_cycle_) {
    filter_.preset(terminals_.inputs);
    prev_in_ = terminals_.inputs;
    first_cycle_ = false;
  }
  image_.inputs = filter_.update(terminals_.inputs, dt_s);

  if (cfg_.mode == SpcMode::StartStop)
    start_stop_cycle(dt_s);
  else
    record_cycle(dt_s);

  // 5 write
  write_outputs();
  terminals_.outputs = image_.outputs;
  prev_in_ = image_.inputs;
  fault_this_cycle_ = false;
}

// rt-safe
void Controller::raise_fault(const char* message) {
  latch_error(message);
  new_fault_ = true;
  fault_this_cycle_ = true;
}

void Controller::latch_error(const char* message, int task, int program, int line) {
  if (!error_) {
    message_ = message;
    error_task_ = task;
    error_program_ = program;
    error_line_ = line;
  }
  error_ = true;
}

void Controller::clear_errors() {
  // A fault raised for this very cycle is still there (its cause persists): the reset cannot clear it.
  if (!fault_this_cycle_) {
    error_ = false;
    message_ = "";
    error_task_ = error_program_ = error_line_ = -1;
  }
  new_fault_ = false;
  // A task cannot go on past an instruction that failed: clearing its error puts its pointer back.
  for (int i = 0; i < kTasks; ++i) {
    if (task_at(i).status().error) task_at(i).reset();
    task_error_prev_[static_cast<std::size_t>(i)] = false;
  }
}

// Latches a task's error on its rising edge (a level would come back after every acknowledge).
void Controller::collect_task_errors() {
  for (int i = 0; i < kTasks; ++i) {
    const auto st = task_at(i).status();
    auto& prev = task_error_prev_[static_cast<std::size_t>(i)];
    if (st.error && !prev) {
      latch_error(st.message, i, st.program, st.line);
      new_fault_ = true;
    }
    prev = st.error;
  }
}

// Steps 3 and 4 of a cycle in either mode: both tasks and the axes, then the tasks' new errors.
// True when a fault is new this cycle (a task's error or one latched earlier in the cycle).
bool Controller::run_tasks(double dt_s) {
  task_a_.update(dt_s, image_);
  task_b_.update(dt_s, image_);
  axes_.step();
  collect_task_errors();
  return std::exchange(new_fault_, false);
}

bool Controller::self_test(double dt_s) {
  // S-8/S-9: the self-test runs with ENABLE=1, STOP=1, START/RESET=0 and starts over if they change.
  const auto& in = image_.inputs;
  if (!(bit(in, sig::kEnable) && bit(in, sig::kStop) && !bit(in, sig::kStart))) {
    self_test_elapsed_s_ = 0;
    return false;
  }
  self_test_elapsed_s_ += dt_s;
  return self_test_elapsed_s_ + kTimeEpsS >= cfg_.self_test_s;
}

void Controller::halt_all() {
  for (int i = 0; i < kTasks; ++i)
    if (!task_at(i).status().motion_done) halted_in_motion_[static_cast<std::size_t>(i)] = true;
  task_a_.halt();
  task_b_.halt();
  axes_.stop_all();  // S-8/S-9: at once, without a ramp
}

void Controller::reset_tasks() {
  task_a_.reset();
  task_b_.reset();
  task_error_prev_ = {};
  halted_in_motion_ = {};
  for (auto a : kSyncO) image_.set(a, false);  // S-8: SYNC_OA = SYNC_OB = 0
}

// ---------------------------------------------------------------- S-8 Start/Stop

void Controller::start_stop_event(StartStopEvent e) {
  const auto step = start_stop_transition(ss_, e);
  ss_ = step.next;
  const auto a = step.actions;
  if (a & ss_action::kHaltTasks) halt_all();
  if (a & ss_action::kClearErrors) clear_errors();
  if (a & ss_action::kResetTasks) reset_tasks();
  if (a & ss_action::kStartTasks)
    for (int i = 0; i < kTasks; ++i)
      if (assigned(i)) {
        task_at(i).start();
        halted_in_motion_[static_cast<std::size_t>(i)] = false;
      }
  if (a & ss_action::kDisableDrives) drives_enabled_ = false;
  if (a & ss_action::kEnableDrives) drives_enabled_ = true;
}

// rt-safe
void Controller::start_stop_cycle(double dt_s) {
  const auto& in = image_.inputs;
  auto rose = [&](IoAddress x) { return bit(in, x) && !bit(prev_in_, x); };
  auto fell = [&](IoAddress x) { return !bit(in, x) && bit(prev_in_, x); };
  using E = StartStopEvent;

  // 2 mode: inputs
  if (fell(sig::kEnable)) start_stop_event(E::EnableFell);
  if (rose(sig::kEnable)) start_stop_event(E::EnableRose);
  if (ss_ == StartStopState::SelfTest && self_test(dt_s))
    start_stop_event(cfg_.self_test_fails ? E::SelfTestFailed : E::SelfTestPassed);
  if (fell(sig::kStop)) start_stop_event(E::StopFell);
  if (rose(sig::kStart)) start_stop_event(bit(in, sig::kStop) ? E::StartPulse : E::ResetPulse);
  if (new_fault_ || error_) {
    new_fault_ = false;
    start_stop_event(E::Error);
  }

  // 3 tasks (M00 sync reads SYNC_IA/IB and writes SYNC_OA/OB through the image, S-7), 4 mode: results
  if (run_tasks(dt_s)) start_stop_event(E::Error);
  if (ss_ == StartStopState::Running) {
    bool any = false;
    for (int i = 0; i < kTasks; ++i) any = any || (assigned(i) && task_at(i).status().running);
    if (!any) start_stop_event(E::TasksEnded);
  }
}

// ---------------------------------------------------------------- S-9 Record Select

void Controller::record_system_event(RecordSystemEvent e) {
  const auto step = record_system_transition(rs_, e);
  rs_ = step.next;
  const auto a = step.actions;
  if (a & rs_action::kHaltTasks) {
    halt_all();
    for (int i = 0; i < kTasks; ++i) record_task_event(i, RecordTaskEvent::Halt);
  }
  if (a & rs_action::kClearErrors) clear_errors();
  if (a & rs_action::kResetTasks) {
    reset_tasks();
    for (int i = 0; i < kTasks; ++i) record_task_event(i, RecordTaskEvent::Reset);
  }
  if (a & rs_action::kDisableDrives) drives_enabled_ = false;
  if (a & rs_action::kEnableDrives) drives_enabled_ = true;
}

void Controller::record_task_event(int i, RecordTaskEvent e) {
  const auto k = static_cast<std::size_t>(i);
  const auto step = record_task_transition(rt_[k], e);
  switch (step.action) {
    case RecordTaskAction::None:
      rt_[k] = step.next;
      break;
    case RecordTaskAction::Accept: {
      // S-9: on the rising edge of CLK latch B0..B4 and start the line; ACK=1, RC=0.
      const int line = image_.line_bits();
      if (task_at(i).execute_record(line)) {
        rt_[k] = step.next;
        ++records_executed_[k];
        last_record_line_[k] = line;
      } else {
        // Names the reason (a relative line after a stop, ...) and the line ordered.
        latch_error(task_at(i).refusal(), i, task_at(i).program_number(), line);
        record_system_event(RecordSystemEvent::Error);
      }
      break;
    }
    case RecordTaskAction::Refuse:
      latch_error("order refused: CLK rose while the task or the controller could not accept it", i,
                  task_at(i).program_number(), image_.line_bits());
      record_system_event(RecordSystemEvent::Error);
      break;
  }
}

// rt-safe
void Controller::record_cycle(double dt_s) {
  const auto& in = image_.inputs;
  auto rose = [&](IoAddress x) { return bit(in, x) && !bit(prev_in_, x); };
  auto fell = [&](IoAddress x) { return !bit(in, x) && bit(prev_in_, x); };
  using E = RecordSystemEvent;
  const bool stop = bit(in, sig::kStop), enable = bit(in, sig::kEnable);

  // 2 mode: inputs
  if (fell(sig::kEnable)) record_system_event(E::EnableFell);
  if (rose(sig::kEnable)) record_system_event(E::EnableRose);
  if (rs_ == RecordSystemState::SelfTest && self_test(dt_s))
    record_system_event(cfg_.self_test_fails ? E::SelfTestFailed : E::SelfTestPassed);
  if (new_fault_) {
    new_fault_ = false;
    record_system_event(E::MotionFault);
  }
  if (fell(sig::kStop)) record_system_event(E::StopFell);
  // S-9: RESET counts once it has been high for reset_min_s (measured on the filtered input, which
  // keeps pulse widths); it acts while still high, so a PLC that drops RESET and raises STOP in the
  // same scan (S-10 ErrorOrden_5) is still seen as a reset with STOP=0.
  if (bit(in, sig::kReset)) {
    reset_high_s_ += dt_s;
    if (!reset_fired_ && reset_high_s_ + kTimeEpsS >= cfg_.reset_min_s) {
      reset_fired_ = true;
      record_system_event(stop ? E::Acknowledge : E::ResetFn);
    }
  } else {
    reset_high_s_ = 0;
    reset_fired_ = false;
  }
  for (int i = 0; i < kTasks; ++i) {
    const auto clk = kClk[static_cast<std::size_t>(i)];
    if (rose(clk))
      record_task_event(i, record_ready(rs_) && stop && enable ? RecordTaskEvent::Order : RecordTaskEvent::OrderBlocked);
    if (fell(clk)) record_task_event(i, RecordTaskEvent::ClkFell);
  }

  // 3 tasks, 4 mode: results
  if (run_tasks(dt_s)) record_system_event(E::MotionFault);
  for (int i = 0; i < kTasks; ++i) {
    const auto s = rt_[static_cast<std::size_t>(i)];
    if ((s == RecordTaskState::Accepted || s == RecordTaskState::Running) && task_at(i).status().motion_done)
      record_task_event(i, RecordTaskEvent::MotionDone);
  }
  // An error still latched (after ENABLE came back, say) keeps READY=0.
  if (error_ && rs_ == RecordSystemState::Ready) record_system_event(E::Error);
}

void Controller::write_outputs() {
  if (cfg_.mode == SpcMode::StartStop) {
    const bool live = ss_ != StartStopState::SelfTest && ss_ != StartStopState::Fatal;
    image_.set(sig::kReady, start_stop_ready(ss_));
    for (int i = 0; i < kTasks; ++i)
      image_.set(kMc[static_cast<std::size_t>(i)],
                 live && (!assigned(i) || (task_at(i).status().motion_done && !halted_in_motion_[static_cast<std::size_t>(i)])));
  } else {
    const bool live = rs_ != RecordSystemState::SelfTest && rs_ != RecordSystemState::Fatal;
    image_.set(sig::kReady, record_ready(rs_));
    for (std::size_t i = 0; i < kTasks; ++i) {
      image_.set(kRc[i], live && record_rc(rt_[i]));
      image_.set(kAck[i], live && record_ack(rt_[i]));
    }
  }
}

ControllerStatus Controller::status() const {
  ControllerStatus s;
  s.mode = cfg_.mode;
  s.start_stop = ss_;
  s.record = rs_;
  s.record_task = rt_;
  s.ready = image_.get(sig::kReady);
  s.drives_enabled = drives_enabled_;
  s.error = error_;
  s.fatal = ss_ == StartStopState::Fatal || rs_ == RecordSystemState::Fatal;
  s.message = message_;
  s.error_task = error_task_;
  s.error_program = error_program_;
  s.error_line = error_line_;
  s.records_executed = records_executed_;
  s.last_record_line = last_record_line_;
  return s;
}

}  // namespace softmc::control::spc
