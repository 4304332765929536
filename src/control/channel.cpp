// Instruction sequencing of a Channel.
#include "control/channel.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <thread>

#include "control/path.hpp"
#include "motion/geometry/polyline_smoothing.hpp"

namespace softmc::control {

namespace {
constexpr double kArcPieceRad = 3.14159265358979323846 / 4;  // longest arc piece without jerk limits

// M62/M63/M67 (LinuxCNC's outputs synchronised with motion): their M function passes with them.
bool synced_output_m(int number) { return number == 62 || number == 63 || number == 67; }
bool synced_output(const program::Op& op) {
  if (const auto* d = std::get_if<program::DigitalOutput>(&op)) return d->synced;
  if (const auto* a = std::get_if<program::AnalogOutput>(&op)) return a->synced;
  return false;
}
// What the path runs through: a path mode, and outputs synchronised with motion (with their M
// function). Neither ends a run of lines to smooth.
bool passes_through(const program::Op& op) {
  if (std::holds_alternative<program::PathMode>(op) || synced_output(op)) return true;
  const auto* m = std::get_if<program::MFunction>(&op);
  return m && synced_output_m(m->number);
}
}  // namespace

const char* to_string(ChannelState s) {
  switch (s) {
    case ChannelState::Idle: return "idle";
    case ChannelState::Running: return "running";
    case ChannelState::Finished: return "finished";
    case ChannelState::Fault: return "fault";
    case ChannelState::Stopping: return "stopping";
    case ChannelState::Stopped: return "stopped";
  }
  return "?";
}

void Channel::load(const program::Program& prog) {
  prog_ = &prog;
  state_ = ChannelState::Idle;
  pc_ = 0;
  curve_next_ = 0;
  batches_.reserve(planner_.queue().capacity() + 1);
  // Curves are built from where the program's previous motion ends: walk the programmed geometry.
  const auto n = prog.instructions.size();
  // Each instruction's pieces go straight into one compact store, in program order (a run's lines
  // are smoothed when it closes, before the instruction that closed it adds its own): a Segment is
  // 1.5 kB, and a CAM program's pieces (one a line) were most of a 200 000-line run's memory; the
  // store keeps what each piece's kind uses, on its axes only (about 160 bytes for a cubic on three
  // axes in its compact form), in chunks that are never moved. With smoothing, its offsets are
  // reserved at about one piece a line (a smoothed line's piece, and a stub at each end of a run);
  // without, only arcs and curves give pieces, and nothing is set aside for the lines (a review:
  // address space a line that strict overcommit would refuse for a million).
  curve_segments_.clear();
  const auto& pc = planner_.config();
  const bool jerk = motion::jerk_mode(planner_.limits());
  const bool smooth = pc.smoothing_max_turn_rad > 0 && jerk;
  if (smooth) {
    const auto lines = static_cast<std::size_t>(std::count_if(prog.instructions.begin(), prog.instructions.end(), [](const auto& ins) {
      return std::holds_alternative<program::Linear>(ins.op);
    }));
    curve_segments_.reserve(lines + lines / 16 + 64);
  }
  curve_first_.assign(n + 1, 0);
  std::size_t first_set = 0;  // curve_first_ is set for instructions below this
  const auto add_pieces = [&](std::size_t i, auto begin, auto end) {
    for (; first_set <= i; ++first_set) curve_first_[first_set] = static_cast<std::uint32_t>(curve_segments_.size());
    for (auto it = begin; it != end; ++it) curve_segments_.push_back(*it);
  };
  curve_error_.assign(n, motion::CurveError::Ok);
  precomputed_.assign(n, 0);
  const std::size_t threads =
      load_threads_ > 0 ? load_threads_ : std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, kMaxLoadThreads);
  core::Vec at = prog.start;
  std::vector<motion::Segment> tmp;
  // Jerk mode: runs of short lines become curvature-continuous B-splines (polyline_smoothing.hpp).
  double tol = -1;  // as PathMode sets it in update()
  std::vector<core::Vec> run_pts;
  std::vector<std::size_t> run_ins;
  double run_feed = 0, run_tol = 0;
  std::vector<std::vector<motion::Segment>> run_out;
  std::vector<std::size_t> kept;
  const auto close_run = [&] {
    if (run_ins.size() >= 2) {
      motion::PolylineSmoothing cfg;
      cfg.tolerance_mm = pc.smoothing_share * run_tol;
      cfg.max_turn_rad = pc.smoothing_max_turn_rad;
      // The run's stretches (up to its sharp turns, at most max_run_lines) are smoothed on several
      // threads at once and handed over in order (core::ordered_parallel): the same pieces.
      cfg.threads = threads;
      // Tiny collinear lines become legs of up to kThinLeg_mm (1 µm CAM lines would otherwise be a
      // piece each, which the planner cannot merge: the window then covers too little to brake in,
      // 31 mm/s on the built-in table instead of F6000). The points dropped lie within
      // thin_share·P of the legs, and the spline keeps to the rest of the smoothing share, so it
      // stays within smoothing_share·P of the program. Nothing dropped: every point is a leg's end.
      const double eps = pc.smoothing_thin_share * run_tol;
      kept.clear();
      if (eps > 0) motion::thin_polyline(run_pts, eps, kThinLeg_mm, kMaxThinned, kept);
      // The points smoothed are the kept ones, moved to the front of the run's own (kept rises, and
      // kept[r] ≥ r): a run may be the whole program, and a copy of its points was 72 bytes a line more.
      if (kept.size() < run_pts.size() && !kept.empty()) {
        cfg.tolerance_mm -= eps;
        for (std::size_t r = 0; r < kept.size(); ++r) run_pts[r] = run_pts[kept[r]];
        run_pts.resize(kept.size());
      } else {
        kept.resize(run_pts.size());
        std::iota(kept.begin(), kept.end(), std::size_t{0});
      }
      // Leg r stands for lines kept[r] … kept[r + 1] − 1: smoothed, the first carries its segments
      // and the others none (executed with it); kept as a line, all stay as programmed (collinear
      // lines, which the planner merges). Each stretch the smoothing finishes (up to a sharp turn,
      // at most max_run_lines) is taken and freed at once: a whole program's pieces are not held
      // twice.
      motion::smooth_polyline(run_pts, cfg, run_out, [&](std::size_t from, std::size_t to) {
        for (std::size_t r = from; r < to; ++r) {
          if (run_out[r].empty()) continue;
          add_pieces(run_ins[kept[r]], run_out[r].begin(), run_out[r].end());
          std::vector<motion::Segment>().swap(run_out[r]);
          precomputed_[run_ins[kept[r]]] = 1;
          for (std::size_t k = kept[r] + 1; k < kept[r + 1]; ++k) precomputed_[run_ins[k]] = kAbsorbed;
        }
      });
    }
    run_pts.clear();
    run_ins.clear();
  };
  for (std::size_t i = 0; i < n; ++i) {
    const auto& op = prog.instructions[i].op;
    if (const auto* pm = std::get_if<program::PathMode>(&op))
      tol = pm->kind == program::PathKind::Blend ? (pm->tolerance_mm > 0 ? pm->tolerance_mm : -1.0) : 0.0;
    const auto* l = std::get_if<program::Linear>(&op);
    const double t = tol < 0 ? pc.tolerance_mm : tol;
    if (smooth && l && t > 0) {
      if (run_ins.empty() || l->feed_mm_s != run_feed || t != run_tol) {
        close_run();
        run_pts.push_back(at);
        run_feed = l->feed_mm_s;
        run_tol = t;
      }
      run_pts.push_back(l->end);
      run_ins.push_back(i);
    } else if (!passes_through(op)) {
      close_run();
    }
    if (auto seg = to_segment(op, at)) {
      // Without jerk limits, arcs are cut into pieces of at most 45°: each piece's own sweep bounds
      // its axes' shares of tangent and normal, and each ramp may use the tangential acceleration
      // its own top speed leaves (tangent_law.hpp), so a circle is not planned at its worst angle.
      if (!jerk && seg->kind == motion::SegmentKind::Arc && std::abs(seg->sweep) > kArcPieceRad) {
        const int pieces = static_cast<int>(std::ceil(std::abs(seg->sweep) / kArcPieceRad));
        core::Vec from = seg->start;
        for (int k = 1; k <= pieces; ++k) {
          const core::Vec to = k == pieces ? seg->end : seg->point(seg->length * k / pieces);
          const auto piece = motion::make_arc(from, to, seg->axis0, seg->axis1, seg->c0, seg->c1, seg->sweep > 0 ? 1 : -1);
          add_pieces(i, &piece, &piece + 1);
          from = to;
        }
        precomputed_[i] = 1;
      }
      at = seg->end;
    } else if (is_curve(op)) {
      tmp.clear();
      if (const auto e = append_curve_segments(op, at, tmp); e != motion::CurveError::Ok) {
        curve_error_[i] = e;
        continue;
      }
      add_pieces(i, tmp.begin(), tmp.end());
      if (!tmp.empty()) at = tmp.back().end;
    }
  }
  close_run();
  for (; first_set <= n; ++first_set) curve_first_[first_set] = static_cast<std::uint32_t>(curve_segments_.size());
}

// rt-safe
bool Channel::push_curve(int& budget) {
  const program::Op& op = prog_->instructions[pc_].op;
  double feed = 0;
  if (const auto* b = program::op_if<program::Bezier>(op)) feed = b->feed_mm_s;
  if (const auto* nb = std::get_if<program::Nurbs>(&op)) feed = nb->feed_mm_s;
  if (const auto* l = std::get_if<program::Linear>(&op)) feed = l->feed_mm_s;  // a smoothed line
  if (const auto* a = std::get_if<program::Arc>(&op)) feed = a->feed_mm_s;     // an arc in pieces
  const bool smoothed = std::holds_alternative<program::Linear>(op);
  const std::uint32_t first = curve_first_[pc_], last = curve_first_[pc_ + 1];
  // A smoothed leg stands for the thinned lines after it too: its setpoints name them all.
  std::uint32_t tag_last = pc_;
  while (tag_last + 1 < precomputed_.size() && precomputed_[tag_last + 1] == kAbsorbed) ++tag_last;
  while (first + curve_next_ < last) {
    if (planner_.queue().full() || budget <= 0 || planning_spent()) return false;
    curve_segments_.get(first + curve_next_, req_.geom);
    // Not mergeable: a smoothed run's stubs keep the direction their spline leaves along. Its
    // pieces lie up to smoothing_share·P off the lines they replace: a blend at the run's ends
    // keeps to the rest of P (a stub into a tangent arc went 1.28·P off the program before).
    request(feed, false, false, tag_last);
    if (smoothed) req_.offset_mm = planner_.config().smoothing_share * (path_tolerance_mm_ < 0 ? planner_.config().tolerance_mm : path_tolerance_mm_);
    const auto r = planner_.push(req_);
    if (r != motion::PlanResult::Ok) {
      fail(motion::to_string(r), r);
      return false;
    }
    plan_pos_ = req_.geom.end;
    ++curve_next_;
    --budget;
  }
  curve_next_ = 0;
  return true;
}

// rt-safe
const motion::PathRequest& Channel::request(double feed_mm_s, bool rapid, bool mergeable, std::uint32_t tag_last) {
  req_.feed_mm_s = feed_mm_s;
  req_.rapid = rapid;
  req_.tag = pc_;
  req_.tag_last = tag_last;
  req_.tolerance_mm = path_tolerance_mm_;
  req_.profile = motion::ProfileKind::Scurve;
  req_.mergeable = mergeable;
  req_.offset_mm = 0;
  return req_;
}

// rt-safe
bool Channel::start(const core::Vec& from) {
  if (!prog_ || (state_ != ChannelState::Idle && state_ != ChannelState::Finished)) return false;
  pc_ = 0;
  stop_kind_ = motion::StopKind::None;
  interp_.cancel_stop();  // a stop a fault cut short must not end this run at once
  override_enabled_ = true;
  set_override();
  plan_pos_ = from;
  path_tolerance_mm_ = -1;
  dwell_left_s_ = 0;
  pops_at_cycle_ = planner_.queue().ring().pops();  // what braked before is not this path's pace
  batches_.clear();
  batch_open_ = false;
  state_ = ChannelState::Running;
  return true;
}

void Channel::OutputBatch::add(const program::DigitalOutput& d) {
  const std::uint64_t bit = std::uint64_t{1} << (d.index & 63);
  on = d.on ? on | bit : on & ~bit;
  off = d.on ? off & ~bit : off | bit;
}

void Channel::OutputBatch::add(const program::AnalogOutput& a) {
  if (a.index < 0 || a.index >= program::kAnalogOutputs) return;
  analog |= static_cast<std::uint8_t>(1u << a.index);
  value[a.index] = a.value;
}

void Channel::apply(const OutputBatch& b) {
  dout_ = (dout_ | b.on) & ~b.off;
  for (std::size_t k = 0; k < aout_.size(); ++k)
    if (b.analog & (1u << k)) aout_[k] = b.value[k];
}

// rt-safe
void Channel::sync_outputs() {
  const auto& sp = interp_.setpoint();
  while (!batches_.empty() && sp.moving && sp.path_v > 0 && sp.tag > batches_.front().after) {
    apply(batches_.front());
    batches_.pop();
  }
}

// rt-safe
void Channel::fail(const char* message, motion::PlanResult r) {
  state_ = ChannelState::Fault;
  fault_ = message;
  plan_error_ = r;
  fault_pc_ = pc_;
}

// rt-safe
void Channel::fault(const char* message) {
  if (state_ == ChannelState::Fault) return;
  fail(message, motion::PlanResult::Ok);
  fault_pc_ = interp_.setpoint().tag;  // the instruction being executed, not the next one planned
}

// rt-safe
void Channel::apply(MotionSignals& signals) {
  feed_override_ = signals.feed_override();
  set_override();
  interp_.set_speed_limits(signals.feed_limit_mm_s(), signals.rapid_limit_mm_s());
  interp_.set_feed_hold(signals.feed_hold);
  // P-2: the channel's path moves all its axes together, so one axis held holds the path.
  bool enable = true;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (planner_.limits().present(i) && !signals.axis_enable[i]) enable = false;
  interp_.set_motion_enable(enable);
  // P-5: the strongest stop asked for this cycle.
  auto kind = motion::StopKind::None;
  if (signals.stop_pulse && !stop_pulse_was_) kind = motion::StopKind::Normal;
  stop_pulse_was_ = signals.stop_pulse;
  if (signals.stop_request) kind = motion::StopKind::Normal;
  if (signals.emergency_stop_request) kind = motion::StopKind::Emergency;
  signals.stop_request = signals.emergency_stop_request = false;  // taken (acknowledged) or refused
  if (kind != motion::StopKind::None) stop(kind);
}

// rt-safe
void Channel::stop(motion::StopKind kind) {
  if (state_ != ChannelState::Running && state_ != ChannelState::Stopping) return;
  if (kind > stop_kind_) stop_kind_ = kind;  // an emergency stop is never weakened
  if (state_ == ChannelState::Running) {
    // Where the program stopped: with nothing in motion, the instruction it waits at or dwells in;
    // otherwise the block the path comes to rest on (update()).
    stop_in_motion_ = !interp_.idle();
    const auto n = static_cast<std::uint32_t>(prog_->instructions.size());
    stop_pc_ = std::min(dwelling() && pc_ > 0 ? pc_ - 1 : pc_, n > 0 ? n - 1 : 0);
  }
  state_ = ChannelState::Stopping;
  dwell_left_s_ = 0;
  interp_.request_stop(kind);
}

// rt-safe
void Channel::update(double dt_s) {
  if (state_ == ChannelState::Stopping) {
    // The interpolator drops everything planned at rest; with nothing in motion there is nothing to brake.
    if (!interp_.stopped() && !interp_.idle()) {
      // The path only slows from here: each cycle, the curves ahead get the limits their geometry
      // allows at the speed it has now, and it brakes harder as it slows (Planner::limit_for_stop).
      if (interp_.stopping()) planner_.limit_for_stop(interp_.path_speed(), interp_.path_acceleration(), interp_.front_progress());
      return;
    }
    interp_.acknowledge_stop();
    if (stop_in_motion_) stop_pc_ = interp_.setpoint().tag;
    state_ = ChannelState::Stopped;
    return;
  }
  if (state_ != ChannelState::Running) return;
  // A feed hold or an enable drop brakes as a stop does (above); at rest the curves take back the
  // limits they were planned with before the path goes on (Planner::restore_limits).
  if (interp_.held()) planner_.limit_for_stop(interp_.path_speed(), interp_.path_acceleration(), interp_.front_progress());
  // (The setpoint's speed: path_speed() is the jerk follower's own and stale while the trapezoid
  // follower moves.)
  if (planner_.limits_raised() && interp_.setpoint().path_v == 0 && interp_.path_acceleration() == 0)
    planner_.restore_limits();
  if (dwell_left_s_ > 0) {
    dwell_left_s_ -= dt_s;
    if (dwell_left_s_ > 1e-12) return;
    dwell_left_s_ = 0;
  }
  const auto& ins = prog_->instructions;
  curves_at_cycle_ = planner_.curves_tried();
  blocks_at_cycle_ = planner_.blocks_committed();
  const std::uint64_t pops = planner_.queue().ring().pops();
  blocks_this_cycle_ = std::min(kMaxBlocksPerCycle, kFillBlocksPerCycle + 2 * (pops - pops_at_cycle_));
  pops_at_cycle_ = pops;
  for (int budget = kMaxInstructionsPerCycle; budget > 0 && pc_ < ins.size(); --budget) {
    const program::Op& op = ins[pc_].op;
    if (const auto* pm = std::get_if<program::PathMode>(&op)) {
      // G61/G61.1: exact stop at every corner; G64 P (G23): blend within P, G64 alone: the default P.
      // A mode change needs no stop: it applies to the corners the following moves start with.
      path_tolerance_mm_ = pm->kind == program::PathKind::Blend ? (pm->tolerance_mm > 0 ? pm->tolerance_mm : -1.0) : 0.0;
      ++pc_;
      continue;
    }
    if (is_curve(op) || precomputed_[pc_]) {
      if (curve_error_[pc_] != motion::CurveError::Ok) return fail(motion::to_string(curve_error_[pc_]), motion::PlanResult::Infeasible);
      if (!push_curve(budget)) return;  // wait for room (or a planning fault)
      batch_open_ = false;
      ++pc_;
      continue;
    }
    if (to_segment(op, plan_pos_, req_.geom)) {  // written in place: no Segment built per line
      if (planner_.queue().full() || planning_spent()) return;  // wait for room, or the next cycle
      double feed = 0;
      if (const auto* l = std::get_if<program::Linear>(&op)) feed = l->feed_mm_s;
      if (const auto* a = std::get_if<program::Arc>(&op)) feed = a->feed_mm_s;
      const std::uint64_t taken = planner_.pushes_taken();
      const auto r = planner_.push(request(feed, std::holds_alternative<program::Rapid>(op), !batch_open_, pc_));
      if (r != motion::PlanResult::Ok) return fail(motion::to_string(r), r);
      if (planner_.pushes_taken() != taken) batch_open_ = false;  // a zero-length move is not the batch's move
      plan_pos_ = req_.geom.end;
      ++pc_;
      continue;
    }
    // M62/M63 and M67 (and their M function, for the PLC's record): the output waits for the motion
    // after it to begin, and the path goes on through them (LinuxCNC's motion-synchronised outputs).
    if (synced_output(op)) {
      if (!batch_open_) {
        if (batches_.full()) return;  // wait for the path to reach the batches before
        batches_.push(OutputBatch{});
        batch_open_ = true;
      }
      OutputBatch& b = batches_.back();
      b.after = pc_;
      if (const auto* d = std::get_if<program::DigitalOutput>(&op)) b.add(*d);
      if (const auto* a = std::get_if<program::AnalogOutput>(&op)) b.add(*a);
      ++pc_;
      continue;
    }
    if (const auto* m = std::get_if<program::MFunction>(&op); m && synced_output_m(m->number)) {
      last_m_ = m->number;
      ++pc_;
      continue;
    }
    // Non-motion instructions act when the motion before them has finished; the planner is told that
    // no more motion follows for now, so the path is planned to stop there.
    planner_.flush();
    if (!interp_.idle()) return;
    if (const auto* d = std::get_if<program::Dwell>(&op)) {
      ++pc_;
      if (d->seconds > 0) {
        dwell_left_s_ = d->seconds;
        return;
      }
    } else if (const auto* t = std::get_if<program::ToolSwitch>(&op)) {
      tool_on_ = t->on;
      ++pc_;
    } else if (const auto* m = std::get_if<program::MFunction>(&op)) {
      last_m_ = m->number;
      // M48/M49 (and G84's own): the motion before has ended, so the override applies exactly
      // from the next motion on, already in this cycle's step.
      if (m->number == 48 || m->number == 49) {
        override_enabled_ = m->number == 48;
        set_override();
      }
      ++pc_;
    } else if (std::holds_alternative<program::DigitalOutput>(op) || std::holds_alternative<program::AnalogOutput>(op)) {
      OutputBatch now;  // M64/M65/M68 at once
      if (const auto* d = std::get_if<program::DigitalOutput>(&op)) now.add(*d);
      if (const auto* a = std::get_if<program::AnalogOutput>(&op)) now.add(*a);
      apply(now);
      ++pc_;
    } else if (std::holds_alternative<program::ProgramEnd>(op)) {
      tool_on_ = false;  // program end switches the tool off (RS274: M2/M30 imply M5)
      pc_ = static_cast<std::uint32_t>(ins.size());
    } else {
      ++pc_;
    }
  }
  if (pc_ >= ins.size()) planner_.flush();  // a program may end on a motion
  if (pc_ >= ins.size() && interp_.idle() && dwell_left_s_ <= 0) state_ = ChannelState::Finished;
}

}  // namespace softmc::control
