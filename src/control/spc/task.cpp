// SPC task execution: the instruction switch, motion start and completion, waits, calls, M00.
#include "control/spc/task.hpp"

#include <cmath>

namespace softmc::control::spc {

using namespace program;

SyncState sync_step(SyncState s, bool in_prev, bool in, bool& out) {
  switch (s) {
    case SyncState::Idle: return SyncState::Idle;
    case SyncState::WaitRise:
      if (!in_prev && in) {
        out = true;  // S-7: tell the PLC the pointer stands on the M00 line
        return SyncState::WaitFall;
      }
      return SyncState::WaitRise;
    case SyncState::WaitFall:
      if (in_prev && !in) {
        out = false;
        return SyncState::Done;
      }
      return SyncState::WaitFall;
    case SyncState::Done: return SyncState::Done;
  }
  return s;
}

Task::Task(TaskId id, const program::spc::ProgramStore& store, Registers& regs, TaskAxes& axes)
    : id_(id), store_(store), regs_(regs), axes_(axes) {
  mc_cond_.fill(1);
}

void Task::set_program(int number) {
  main_program_ = number;
  absolute_ = true;
  accel_pct_ = {};
  decel_pct_ = {};
  pass_pct_ = {};
  mc_cond_.fill(1);
  reset();
}

const program::spc::SpcProgram* Task::current() const { return store_.get(program_); }

void Task::clear_sync_output() {
  if (sync_out_) sync_out_dirty_ = true;
  sync_out_ = false;
  sync_ = SyncState::Idle;
}

void Task::start() {
  if (error_ || main_program_ < 0 || !store_.get(main_program_)) return;
  if (program_ < 0) program_ = static_cast<std::int16_t>(main_program_);
  running_ = true;
  record_ = false;
  halted_record_ = false;
}

void Task::halt() {
  if (record_ && running_) halted_record_ = true;
  running_ = false;
  // The line the task stood on runs again from its start at the next START (a motion is re-issued).
  if (phase_ == Phase::Sync) clear_sync_output();
  phase_ = Phase::Fetch;
  dwell_left_s_ = 0;
}

void Task::reset() {
  running_ = false;
  record_ = false;
  halted_record_ = false;
  error_ = false;
  message_ = "";
  program_ = static_cast<std::int16_t>(main_program_);
  pc_ = 0;
  depth_ = 0;
  if (phase_ == Phase::Sync) clear_sync_output();
  phase_ = Phase::Fetch;
  dwell_left_s_ = 0;
  motion_axes_ = 0;
}

bool Task::execute_record(int line) {
  auto refuse = [&](const char* why) {
    refusal_ = why;
    return false;
  };
  if (error_) return refuse("order refused: the task has an error");
  if (running_) return refuse("order refused: the task is still executing a line");
  if (line < 0 || line > program::spc::kRecordMaxLine) return refuse("order refused: line number outside 0..31");
  const auto* p = store_.get(main_program_);
  if (!p) return refuse("order refused: no record program assigned");
  const int idx = p->index(line);
  if (idx < 0) return refuse("order refused: the record program has no such line");
  // S-9: after a stop only absolute moves are accepted until each axis has had one. Checked here, before
  // ACK, so that the PLC sees a refused order (no ACK, READY=0) and runs its OrderError sequence.
  if (const auto* m = std::get_if<SpcMove>(&p->ir.instructions[static_cast<std::size_t>(idx)].op)) {
    const bool rel = m->coord == SpcCoord::Relative || (m->coord == SpcCoord::Modal && !absolute_);
    for (std::size_t a = 0; rel && a < kSpcAxes; ++a)
      if ((m->axes & (1u << a)) && axes_.needs_absolute(static_cast<int>(a)))
        return refuse(to_string(AxisCmd::NeedsAbsolute));
  }
  refusal_ = "";
  program_ = static_cast<std::int16_t>(main_program_);
  pc_ = idx;
  depth_ = 0;
  phase_ = Phase::Fetch;
  record_ = true;
  halted_record_ = false;
  running_ = true;
  return true;
}

bool Task::all_complete() const {
  for (std::size_t a = 0; a < kSpcAxes; ++a)
    if ((motion_axes_ & (1u << a)) && !axes_.complete(static_cast<int>(a), mc_cond_[a])) return false;
  return true;
}

TaskStatus Task::status() const {
  TaskStatus s;
  s.running = running_;
  s.waiting_sync = phase_ == Phase::Sync;
  s.motion_done = !(record_ && (running_ || halted_record_)) && all_complete();
  s.error = error_;
  s.message = message_;
  if (error_) {
    s.program = static_cast<std::uint8_t>(error_program_);
    s.line = error_line_;
  } else if (const auto* p = current()) {
    s.program = static_cast<std::uint8_t>(program_);
    s.line = pc_ >= 0 && static_cast<std::size_t>(pc_) < p->size() ? p->lines[pc_] : 0;
  }
  return s;
}

Task::Step Task::fail(const char* message) {
  error_ = true;
  running_ = false;
  message_ = message;
  error_program_ = program_;
  const auto* p = current();
  error_line_ = p && pc_ >= 0 && static_cast<std::size_t>(pc_) < p->size() ? p->lines[pc_] : 0;
  phase_ = Phase::Fetch;
  return Step::Fail;
}

void Task::end_program() {
  depth_ = 0;
  program_ = static_cast<std::int16_t>(main_program_);
  pc_ = 0;
  running_ = false;
}

// rt-safe
void Task::update(double dt_s, IoImage& io) {
  if (sync_out_dirty_) {
    io.set_output(0, id_ == TaskId::A ? 6 : 5, sync_out_);
    sync_out_dirty_ = false;
  }
  if (!running_ || error_) return;
  for (int budget = kMaxInstructionsPerCycle; budget > 0; --budget) {
    Step s;
    if (phase_ != Phase::Fetch) {
      s = resume(dt_s, io);
    } else {
      const auto* p = current();
      if (!p) {
        fail("the task's program is missing");
        return;
      }
      if (pc_ < 0 || static_cast<std::size_t>(pc_) >= p->size()) {
        // Decision: running off the end of a subroutine returns (as M02); off the main program ends it (as M30).
        if (depth_ > 0) {
          --depth_;
          program_ = stack_[depth_].program;
          pc_ = stack_[depth_].return_index;
          continue;
        }
        end_program();
        return;
      }
      ++executed_;
      s = execute(p->ir.instructions[pc_], io);
    }
    switch (s) {
      case Step::Next:
        ++pc_;
        if (record_) {  // S-9: one line per order
          running_ = false;
          return;
        }
        break;
      case Step::Jumped: break;
      case Step::Block:
      case Step::Stop:
      case Step::Fail: return;
    }
  }
}

Task::Step Task::resume(double dt_s, IoImage& io) {
  switch (phase_) {
    case Phase::Dwell:
      dwell_left_s_ -= dt_s;
      if (dwell_left_s_ > 1e-9) return Step::Block;
      phase_ = Phase::Fetch;
      return Step::Next;
    case Phase::Motion: return finish_motion();
    case Phase::Sync: {
      const bool in = io.get_input(0, id_ == TaskId::A ? 6 : 5);  // SYNC_IA / SYNC_IB (S-8)
      bool out = sync_out_;
      sync_ = sync_step(sync_, sync_in_prev_, in, out);
      sync_in_prev_ = in;
      if (out != sync_out_) {
        sync_out_ = out;
        io.set_output(0, id_ == TaskId::A ? 6 : 5, out);  // SYNC_OA / SYNC_OB
      }
      if (sync_ != SyncState::Done) return Step::Block;
      sync_ = SyncState::Idle;
      phase_ = Phase::Fetch;
      return Step::Next;
    }
    case Phase::Fetch: break;
  }
  return Step::Next;
}

Task::Step Task::jump_to_line(int line) {
  const auto* p = current();
  const int idx = p ? p->index(line) : -1;
  if (idx < 0) return fail("jump to a line this program does not have (S-4)");
  if (idx == pc_) return Step::Block;  // a jump to its own line is a wait: once per cycle (S-6)
  pc_ = idx;
  return Step::Jumped;
}

namespace {
double pct(std::uint8_t p) { return (p == 0 ? 100 : p) / 100.0; }
}  // namespace

Task::Step Task::motion(const SpcMove& m) {
  const int task = id_ == TaskId::A ? 0 : 1;
  if (m.coord != SpcCoord::Modal) absolute_ = m.coord == SpcCoord::Absolute;  // modal per task (S-2)
  const bool rel = !absolute_;
  std::array<double, kSpcAxes> target{};
  // Validate every axis first, then start them all in this cycle.
  for (std::size_t a = 0; a < kSpcAxes; ++a) {
    if (!(m.axes & (1u << a))) continue;
    const auto& op = m.target[a];
    const double v = op.is_reg ? regs_.position_mm(static_cast<int>(a), op.reg) : op.centi / 100.0;
    // Relative to the axis's last target, so repeated G91 steps do not accumulate a following error.
    target[a] = rel ? axes_.target_mm(static_cast<int>(a)) + v : v;
    const AxisCmd r = axes_.check(task, static_cast<int>(a), target[a], rel);
    if (r != AxisCmd::Ok) return fail(to_string(r));
  }
  const auto& cfg = axes_.config();
  for (std::size_t a = 0; a < kSpcAxes; ++a) {
    if (!(m.axes & (1u << a))) continue;
    const auto& ac = cfg.axis[a];
    const double v = m.profile == SpcProfile::Rapid ? ac.v_max_mm_s : pct(m.speed_pct[a]) * ac.v_max_mm_s;
    const double from = axes_.setpoint_mm(static_cast<int>(a));
    axes_.command(task, static_cast<int>(a), target[a], v, pct(accel_pct_[a]) * ac.a_max_mm_s2,
                  pct(decel_pct_[a]) * ac.a_max_mm_s2, m.profile, rel);
    // G25 decision (S-3): pass point = n/100 × final position, met once reached in the direction of travel.
    pass_active_[a] = pass_pct_[a] != 0;
    pass_point_mm_[a] = pass_pct_[a] / 100.0 * target[a];
    pass_dir_[a] = target[a] > from ? 1.0 : target[a] < from ? -1.0 : 0.0;
  }
  motion_axes_ = m.axes;
  phase_ = Phase::Motion;
  return Step::Block;  // the axes step after the tasks: completion is checked from the next cycle
}

Task::Step Task::finish_motion() {
  for (std::size_t a = 0; a < kSpcAxes; ++a) {
    if (!(motion_axes_ & (1u << a))) continue;
    const int ai = static_cast<int>(a);
    bool met;
    if (pass_active_[a] && !record_) {
      met = pass_dir_[a] * (axes_.setpoint_mm(ai) - pass_point_mm_[a]) >= 0 || axes_.complete(ai, 1);
    } else {
      met = axes_.complete(ai, mc_cond_[a]);
    }
    if (!met) return Step::Block;
  }
  phase_ = Phase::Fetch;
  return Step::Next;
}

bool Task::read_bit(const SpcBit& b, const IoImage& io) const {
  switch (b.space) {
    case SpcBitSpace::Input: return io.get_input(b.module, b.bit);
    case SpcBitSpace::Output: return io.get_output(b.module, b.bit);
    case SpcBitSpace::Flag: return regs_.flag(b.bit);
  }
  return false;
}

// rt-safe: one instruction.
Task::Step Task::execute(const Instruction& ins, IoImage& io) {
  return std::visit(
      [&](const auto& op) -> Step {
        using T = std::decay_t<decltype(op)>;
        if constexpr (std::is_same_v<T, SpcMove>) {
          return motion(op);
        } else if constexpr (std::is_same_v<T, SpcAxisSetting>) {
          for (std::size_t a = 0; a < kSpcAxes; ++a) {
            if (!(op.axes & (1u << a))) continue;
            switch (op.kind) {
              case SpcSetting::Accel: accel_pct_[a] = op.value[a]; break;
              case SpcSetting::Decel: decel_pct_[a] = op.value[a]; break;
              case SpcSetting::PassThrough: pass_pct_[a] = op.value[a]; break;
              case SpcSetting::MotionComplete: mc_cond_[a] = op.value[a]; break;
              case SpcSetting::Mass: axes_.set_mass_pct(static_cast<int>(a), op.value[a]); break;
            }
          }
          return Step::Next;
        } else if constexpr (std::is_same_v<T, SpcDwell>) {
          dwell_left_s_ = op.hundredths / 100.0;
          if (dwell_left_s_ <= 0) return Step::Next;
          phase_ = Phase::Dwell;
          return Step::Block;
        } else if constexpr (std::is_same_v<T, SpcJump>) {
          if (!op.via_reg) {
            if (op.index == pc_) return Step::Block;
            pc_ = op.index;
            return Step::Jumped;
          }
          return jump_to_line(regs_.integer(op.reg));
        } else if constexpr (std::is_same_v<T, SpcCall>) {
          const int n = op.via_reg ? regs_.integer(op.reg) : op.program;
          const auto* callee = store_.get(n);
          if (!callee || callee->size() == 0) return fail("call of an empty or missing program (S-4)");
          if (depth_ >= kMaxCallDepth) return fail("a fifth nested call: at most 4 (S-4)");
          stack_[depth_++] = Frame{program_, pc_ + 1};
          program_ = static_cast<std::int16_t>(n);
          pc_ = 0;
          return Step::Jumped;
        } else if constexpr (std::is_same_v<T, SpcReturn>) {
          if (depth_ == 0) return fail("M02 outside a subroutine");
          --depth_;
          program_ = stack_[depth_].program;
          pc_ = stack_[depth_].return_index;
          return Step::Jumped;
        } else if constexpr (std::is_same_v<T, SpcEnd>) {
          end_program();
          return Step::Stop;
        } else if constexpr (std::is_same_v<T, SpcSync>) {
          sync_ = SyncState::WaitRise;
          sync_in_prev_ = io.get_input(0, id_ == TaskId::A ? 6 : 5);  // an input already high is no edge
          phase_ = Phase::Sync;
          return Step::Block;
        } else if constexpr (std::is_same_v<T, SpcPosReg>) {
          std::array<std::int64_t, kSpcAxes> v{};
          for (std::size_t a = 0; a < kSpcAxes; ++a) {  // validate all axes, then write
            if (!(op.axes & (1u << a))) continue;
            const int ai = static_cast<int>(a);
            const auto& o = op.value[a];
            const std::int64_t operand = o.is_reg ? regs_.position_centi(ai, o.reg) : o.centi;
            switch (op.op) {
              case SpcPosRegOp::Load: v[a] = operand; break;
              case SpcPosRegOp::Add: v[a] = regs_.position_centi(ai, op.reg) + operand; break;
              case SpcPosRegOp::Capture: v[a] = std::llround(axes_.actual_mm(ai) * 100.0); break;
            }
            if (v[a] < -kSpcPosMaxCenti || v[a] > kSpcPosMaxCenti)
              return fail("position register out of range -9999.99..9999.99 (S-5)");
          }
          for (std::size_t a = 0; a < kSpcAxes; ++a)
            if (op.axes & (1u << a)) regs_.set_position_centi(static_cast<int>(a), op.reg, v[a]);
          return Step::Next;
        } else if constexpr (std::is_same_v<T, SpcIntReg>) {
          switch (op.op) {
            case SpcIntRegOp::Load:
              if (regs_.set_integer(op.reg, op.value) != RegResult::Ok) return fail("integer register value out of range (S-5)");
              return Step::Next;
            case SpcIntRegOp::Add:
              if (regs_.add_integer(op.reg, op.value) != RegResult::Ok)
                return fail("integer register overflow: outside -32767..32767 (S-5)");
              return Step::Next;
            case SpcIntRegOp::Test:
              if (regs_.integer(op.reg) != op.value) return Step::Next;
              if (op.index == pc_) return Step::Block;
              pc_ = op.index;
              return Step::Jumped;
          }
          return Step::Next;
        } else if constexpr (std::is_same_v<T, SpcBitTest>) {
          if (read_bit(op.bit, io) != op.jump_when) return Step::Next;
          if (op.index == pc_) return Step::Block;  // a wait: re-evaluated once per cycle (S-6)
          pc_ = op.index;
          return Step::Jumped;
        } else if constexpr (std::is_same_v<T, SpcBitWrite>) {
          if (op.bit.space == SpcBitSpace::Flag)
            regs_.set_flag(op.bit.bit, op.value);
          else
            io.set_output(op.bit.module, op.bit.bit, op.value);
          return Step::Next;
        } else {
          return fail("not an SPC instruction");
        }
      },
      ins.op);
}

}  // namespace softmc::control::spc
