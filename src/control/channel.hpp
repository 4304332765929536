// A Channel executes one Program: motions go to the planner, everything else waits for the
// motion before it to finish (exact stop at non-motion instructions, for now). It reads the PLC's
// motion signals (MotionSignals: override, feed hold, axis enables, stops) and drives the
// interpolator with them.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "control/motion_signals.hpp"
#include "core/ring.hpp"
#include "motion/geometry/curve_result.hpp"
#include "motion/geometry/segment_store.hpp"
#include "motion/interp/interpolator.hpp"
#include "motion/planner/planner.hpp"
#include "program/ir/program.hpp"

namespace softmc::control {

// Stopping: a stop (P-5) was taken, the path brakes to rest on itself and no instruction is executed
// any more; Stopped: at rest, everything planned dropped. A stopped program is not resumed: load it again.
enum class ChannelState : std::uint8_t { Idle, Running, Finished, Fault, Stopping, Stopped };
const char* to_string(ChannelState s);

class Channel {
 public:
  // Instructions a channel may execute in one cycle: bounds the cycle's work however the program
  // looks. Most of a motion's cost is the block it commits (Planner::blocks_committed), so those
  // are bounded apart: 1 µm CAM lines merge 16 to a block and run at 1 m/s before the 1024 binds,
  // against 64 mm/s when 64 instructions of any kind were the bound.
  static constexpr int kMaxInstructionsPerCycle = 1024;
  // Blocks the planner may commit in one cycle (a line, arc or spline piece, a blend: about 0.5 µs
  // each on lines, several on spline pieces).
  static constexpr std::uint64_t kMaxBlocksPerCycle = 64;
  // What a cycle may commit is kFillBlocksPerCycle plus twice the blocks the path passed in the
  // cycle before, up to kMaxBlocksPerCycle: a window filling while the path is at rest or slow (a
  // program's start, after every stop) fills over a dozen cycles instead of taking the whole 64 in
  // its first one or two (the worst cycles of a run were those: BM_ProgramCycle), while a path
  // that passes many short blocks a cycle gets its 64 again one cycle later.
  static constexpr std::uint64_t kFillBlocksPerCycle = 16;
  // Curves the planner may try in one cycle (corner quintics, curve blends, fillets: each one's fit
  // or search, 60–800 µs of CPU, taken or not: Planner::curves_tried), checked before each push (one
  // push tries at most four): the planning work of a cycle stays bounded however many sharp corners
  // its instructions hold (bench BM_ProgramCycle measures the worst cycles).
  static constexpr std::uint64_t kMaxCurvesPerCycle = 2;
  // Thinning before smoothing (motion::thin_polyline): tiny collinear lines become legs of at most
  // kThinLeg_mm, at most kMaxThinned points dropped in a row (the work of load stays linear). Legs
  // of 50 µm keep the blocks of a smoothed run at 64 a cycle (kMaxBlocksPerCycle) up to 3.2 m/s, and
  // a window of 2 000 of them 100 mm long. 20 µm legs cost 3D_Chips 0.5 % less in jerk mode, but a
  // circle of 2 µm chords printed to 4 decimals ran 48 % slower on them (the rounding is curvature
  // noise on short pieces): 1.75 s, as unthinned, with 50 µm; 2.58 s with 20 µm.
  static constexpr double kThinLeg_mm = 0.05;
  // Threads load() uses by default: each holds a stretch of up to 1 000 lines' pieces as whole
  // Segments (1.5 MB) while it smooths them.
  static constexpr std::size_t kMaxLoadThreads = 8;
  static constexpr std::size_t kMaxThinned = 64;

  Channel(motion::Planner& planner, motion::Interpolator& interp) : planner_(planner), interp_(interp) {}

  // Not rt: binds a checked program and resets the pointer. The program must outlive the run.
  // Curves (G5/G5.1/G5.2) are expanded into segments here, because their construction allocates;
  // a curve that cannot be built faults the channel when the program reaches it. With jerk limits,
  // runs of short lines are smoothed here too (PlannerConfig::smoothing_max_turn_rad).
  void load(const program::Program& prog);
  // Not rt: threads load() smooths runs of lines on (0: one a hardware thread, at most
  // kMaxLoadThreads; the pieces are the same whatever the count).
  void set_load_threads(std::size_t n) { load_threads_ = n; }
  // rt-safe: start from the first instruction (Idle or Finished), planning from `from`. Curves,
  // smoothed runs and arc pieces were built at load from the program's start point: `from` must be
  // that point (the applications pass it).
  bool start(const core::Vec& from);
  // rt-safe: executes until the program blocks (queue full, waiting for motion, dwell) or the budget ends.
  void update(double dt_s);
  // rt-safe: after the interpolator's step. The outputs M62/M63 and M67 set synchronised with
  // motion take effect in the first cycle that moves on the motion after them, as LinuxCNC sets them
  // at the start of the next move (each output's last value before that move); one with no motion
  // after it changes nothing, and none switches while the path stands (a hold).
  void sync_outputs();
  // rt-safe: fault from outside (a drive, a switch): the channel stops executing.
  void fault(const char* message);
  // rt-safe: the PLC's motion signals, once per cycle before update() (P-2, P-5, P-8): they act on
  // the interpolator's next step. Clears the acknowledged requests (stop_request,
  // emergency_stop_request) it takes; a stop is taken only while the program runs.
  void apply(MotionSignals& signals);

  ChannelState state() const { return state_; }
  std::uint32_t pc() const { return pc_; }          // next instruction to execute
  bool tool_on() const { return tool_on_; }
  // Digital outputs 0…63 (bit n: output n), as M62…M65 set them; analog outputs 0…3 (M67/M68).
  std::uint64_t digital_outputs() const { return dout_; }
  const std::array<double, program::kAnalogOutputs>& analog_outputs() const { return aout_; }
  bool dwelling() const { return dwell_left_s_ > 0; }
  int last_m() const { return last_m_; }
  const char* fault_message() const { return fault_; }
  motion::PlanResult plan_error() const { return plan_error_; }
  std::uint32_t fault_instruction() const { return fault_pc_; }
  // P-7 stop_confirmed: a running program was actually stopped; stays true until a program is
  // loaded again (a stopped program is not started again).
  bool stop_confirmed() const { return state_ == ChannelState::Stopped; }
  motion::StopKind stop_kind() const { return stop_kind_; }  // the strongest stop taken (None: none)
  // The instruction the program stopped at: the block the path came to rest on, or with nothing in
  // motion the instruction it waited at or dwelt in (stopped_in_motion() tells which).
  std::uint32_t stop_instruction() const { return stop_pc_; }
  bool stopped_in_motion() const { return stop_in_motion_; }

 private:
  void fail(const char* message, motion::PlanResult r);
  void stop(motion::StopKind kind);
  // rt-safe: the override the interpolator runs with: the PLC's, or 1 under M49.
  void set_override() { interp_.set_feed_override(override_enabled_ ? feed_override_ : 1.0); }
  // rt-safe: req_ for the motion at pc_, whose geometry is already in req_.geom: every other field set.
  const motion::PathRequest& request(double feed_mm_s, bool rapid, bool mergeable, std::uint32_t tag_last);
  // rt-safe: pushes the precomputed segments of the curve at pc_; false while the queue is full.
  bool push_curve(int& budget);
  // rt-safe: this cycle's planning budget is spent (kMaxCurvesPerCycle curves tried, or
  // kMaxBlocksPerCycle blocks committed, since it began).
  bool planning_spent() const {
    return planner_.curves_tried() - curves_at_cycle_ >= kMaxCurvesPerCycle ||
           planner_.blocks_committed() - blocks_at_cycle_ >= blocks_this_cycle_;
  }

  motion::Planner& planner_;
  motion::Interpolator& interp_;
  const program::Program* prog_ = nullptr;
  ChannelState state_ = ChannelState::Idle;
  std::uint32_t pc_ = 0;
  core::Vec plan_pos_;  // where the last planned motion ends
  // The request every push is built in (a Segment is 1.3 kB: built and copied anew for each
  // programmed line, it was most of a merged line's cost).
  motion::PathRequest req_;
  double path_tolerance_mm_ = -1;  // G61/G64 P: PathRequest::tolerance_mm (< 0: the planner's default)
  double dwell_left_s_ = 0;
  bool tool_on_ = false;
  int last_m_ = -1;
  std::uint64_t dout_ = 0;
  std::array<double, program::kAnalogOutputs> aout_{};
  // The outputs M62/M63/M67 set between two motions, applied together once the path moves on the
  // motion after them.
  struct OutputBatch {
    std::uint32_t after = 0;         // the batch's last output instruction
    std::uint64_t on = 0, off = 0;   // digital outputs switched on, off
    std::uint8_t analog = 0;         // bit k: analog output k set to value[k]
    std::array<double, program::kAnalogOutputs> value{};
    void add(const program::DigitalOutput& d);
    void add(const program::AnalogOutput& a);
  };
  // Sized at load to the planner's window (each batch but the newest waits for a block in it) and
  // one more.
  core::Ring<OutputBatch> batches_;
  // The newest batch still takes outputs: no motion has made a block since. The motion after it is
  // not merged into the line before (it begins a block of its own).
  bool batch_open_ = false;
  void apply(const OutputBatch& b);
  const char* fault_ = "";
  motion::PlanResult plan_error_ = motion::PlanResult::Ok;
  std::uint32_t fault_pc_ = 0;
  motion::StopKind stop_kind_ = motion::StopKind::None;
  std::uint32_t stop_pc_ = 0;
  bool stop_in_motion_ = false;
  bool stop_pulse_was_ = false;  // stop_pulse in the last apply(): a stop on its rising edge only
  double feed_override_ = 1;      // the PLC's override (P-8) from the last apply()
  bool override_enabled_ = true;  // M48 (on) / M49 (off: the programmed feed, whatever the override)
  // Precomputed curve segments: curve_first_[i] .. curve_first_[i + 1] are instruction i's
  // (sized at load, one entry per instruction plus one).
  motion::SegmentStore curve_segments_;  // compact: a tenth of a Segment's 1.5 kB a smoothed piece
  std::vector<std::uint32_t> curve_first_;
  std::vector<motion::CurveError> curve_error_;  // per instruction: why its curve could not be built (a byte, not a pointer)
  std::uint32_t curve_next_ = 0;           // next segment of the current curve to push
  std::uint64_t curves_at_cycle_ = 0;      // planner_.curves_tried() when this cycle's update began
  std::uint64_t blocks_at_cycle_ = 0;      // planner_.blocks_committed() likewise
  std::uint64_t blocks_this_cycle_ = kMaxBlocksPerCycle;  // this cycle's bound (kFillBlocksPerCycle)
  std::uint64_t pops_at_cycle_ = 0;        // the window's pops when the cycle before began
  std::vector<std::uint8_t> precomputed_;     // per instruction: a line replaced by smoothing segments,
                                           // or an arc cut into pieces (pushed like a curve's), or
                                           // kAbsorbed: a thinned line the leg before it runs
  static constexpr std::uint8_t kAbsorbed = 2;
  std::size_t load_threads_ = 0;
};

}  // namespace softmc::control
