// The SPC200 controller: the two tasks, the I/O image and its input filter, and the active operating
// mode (S-8 Start/Stop or S-9 Record Select), run once per cycle in a fixed order.
#pragma once

#include <array>
#include <cstdint>

#include "control/spc/input_filter.hpp"
#include "control/spc/io_image.hpp"
#include "control/spc/record_select.hpp"
#include "control/spc/start_stop.hpp"
#include "control/spc/task.hpp"

namespace softmc::control::spc {

enum class SpcMode : std::uint8_t { StartStop, RecordSelect };
const char* to_string(SpcMode m);

struct ControllerConfig {
  SpcMode mode = SpcMode::StartStop;
  int program_a = -1;  // "Operating mode / Start program": start (S-8) or record (S-9) program; -1 = none
  int program_b = -1;
  double self_test_s = 10.0;     // S-8/S-9: about 10 s in the source; tests shorten it
  double input_filter_s = InputFilter::kDefaultFilterS;
  double reset_min_s = 0.010;    // S-9: a RESET pulse counts once it has been high this long
  bool self_test_fails = false;  // simulation: the self-test finds a fault (not clearable)
};

// The [spc] table of a machine configuration as controller settings (mode, start programs, times).
ControllerConfig controller_config_from(const machine::SpcMachineConfig& spc);

struct ControllerStatus {
  SpcMode mode = SpcMode::StartStop;
  StartStopState start_stop = StartStopState::SelfTest;
  RecordSystemState record = RecordSystemState::SelfTest;
  std::array<RecordTaskState, 2> record_task{RecordTaskState::Ready, RecordTaskState::Ready};
  bool ready = false;
  bool drives_enabled = true;  // false while ENABLE=0: the composition root opens the position loops
  bool error = false;          // an error is latched (READY=0 until acknowledged)
  bool fatal = false;          // not clearable: power off and on
  const char* message = "";
  // Where the latched error comes from: the task (0 = A, 1 = B; -1 = from outside, e.g. a drive fault),
  // its program and N line (a task's error, or the line of a refused order); -1 when unknown.
  int error_task = -1;
  int error_program = -1;
  int error_line = -1;
  std::array<std::uint64_t, 2> records_executed{};  // S-9 orders the tasks accepted (execute_record true)
  std::array<int, 2> last_record_line{-1, -1};
};

class Controller {
 public:
  // The store, registers and axes must outlive the controller. Not rt: configures the tasks.
  Controller(const ControllerConfig& cfg, const program::spc::ProgramStore& store, Registers& regs, TaskAxes& axes);

  // The terminals as wired: the outside (a PLC, buttons, a stimulus file, Modbus) writes `inputs` and
  // reads `outputs`. Written inputs take effect at the next update(), through the input filter.
  IoImage& terminals() { return terminals_; }
  const IoImage& terminals() const { return terminals_; }
  // The image the programs and the modes see: filtered inputs, outputs before publication.
  const IoImage& image() const { return image_; }
  InputFilter& filter() { return filter_; }

  // rt-safe. One cycle, in this order:
  //   1 read     terminals' inputs → input filter → image inputs; edges against the previous cycle
  //   2 mode     the mode's events from the filtered inputs (ENABLE, self-test, STOP, START/RESET,
  //              CLK), each through the mode's transition function, actions applied at once
  //   3 tasks    task A then task B update (programs run, record lines move), then the axes step
  //   4 mode     the tasks' results as events: errors, motion done (RC), tasks ended
  //   5 write    system outputs (READY, MC/RC, ACK) into the image; image outputs → terminals
  void update(double dt_s);

  // rt-safe: an error from outside the tasks (a drive's following error, a limit switch, a blocked
  // axis): stops every axis, READY=0 until acknowledged. A fault the outside keeps raising comes back
  // after every reset. `message` must be a static or long-lived string.
  void raise_fault(const char* message);

  ControllerStatus status() const;
  const Task& task(TaskId t) const { return t == TaskId::A ? task_a_ : task_b_; }
  Task& task(TaskId t) { return t == TaskId::A ? task_a_ : task_b_; }
  const ControllerConfig& config() const { return cfg_; }

 private:
  static constexpr int kTasks = 2;
  Task& task_at(int i) { return i == 0 ? task_a_ : task_b_; }
  const Task& task_at(int i) const { return i == 0 ? task_a_ : task_b_; }
  bool assigned(int i) const { return (i == 0 ? cfg_.program_a : cfg_.program_b) >= 0; }

  bool self_test(double dt_s);  // true when the self-test time has elapsed this cycle
  void latch_error(const char* message, int task = -1, int program = -1, int line = -1);
  void clear_errors();
  void collect_task_errors();
  bool run_tasks(double dt_s);

  void start_stop_cycle(double dt_s);
  void start_stop_event(StartStopEvent e);
  void record_cycle(double dt_s);
  void record_system_event(RecordSystemEvent e);
  void record_task_event(int i, RecordTaskEvent e);
  void halt_all();
  void reset_tasks();
  void write_outputs();

  ControllerConfig cfg_;
  TaskAxes& axes_;
  Task task_a_, task_b_;
  IoImage terminals_, image_;
  InputFilter filter_;
  std::array<std::uint16_t, kIoModules> prev_in_{};
  bool first_cycle_ = true;

  StartStopState ss_ = StartStopState::SelfTest;
  RecordSystemState rs_ = RecordSystemState::SelfTest;
  std::array<RecordTaskState, kTasks> rt_{RecordTaskState::Ready, RecordTaskState::Ready};

  double self_test_elapsed_s_ = 0;
  double reset_high_s_ = 0;
  bool reset_fired_ = false;
  bool drives_enabled_ = true;

  bool error_ = false, new_fault_ = false;
  bool fault_this_cycle_ = false;  // raise_fault since the last update: a reset cannot clear it
  const char* message_ = "";
  int error_task_ = -1, error_program_ = -1, error_line_ = -1;
  std::array<bool, kTasks> task_error_prev_{};
  std::array<bool, kTasks> halted_in_motion_{};  // S-8: a stopped motion is not a finished one (MC stays 0)
  std::array<std::uint64_t, kTasks> records_executed_{};
  std::array<int, kTasks> last_record_line_{-1, -1};
};

}  // namespace softmc::control::spc
