// Instruction sequencing of a Channel.
#include "control/channel.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <thread>

#include "control/path.hpp"
#include "core/ordered_parallel.hpp"
#include "motion/geometry/polyline_smoothing.hpp"

namespace softmc::control {

namespace {
constexpr double kArcPieceRad = 3.14159265358979323846 / 4;  // longest arc piece without jerk limits
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
  // Curves are built from where the program's previous motion ends: walk the programmed geometry.
  const auto n = prog.instructions.size();
  // Each instruction's pieces go into one compact store, in program order: a Segment is 1.5 kB,
  // and a CAM program's pieces (one a line) were most of a 200 000-line run's memory; the store
  // keeps what each piece's kind uses, on its axes only (about 590 bytes for a cubic on three axes).
  // The walk below builds the arcs' pieces and the curves as it goes (a curve's end is where the
  // next motion starts) and sets each run of lines aside; the runs are then smoothed on every
  // hardware thread at once and their pieces taken in program order (core::ordered_parallel): the
  // same pieces in the same places as one after the other, in about half the time on two cores.
  curve_segments_.clear();
  const auto& pc = planner_.config();
  const bool jerk = motion::jerk_mode(planner_.limits());
  const bool smooth = pc.smoothing_max_turn_rad > 0 && jerk;
  if (smooth) {  // about a piece a line (a smoothed line's, and a stub at each end of a run)
    const auto lines = static_cast<std::size_t>(std::count_if(prog.instructions.begin(), prog.instructions.end(), [](const auto& ins) {
      return std::holds_alternative<program::Linear>(ins.op);
    }));
    curve_segments_.reserve(lines + lines / 16 + 64, kPieceBytes);
  }
  curve_first_.assign(n + 1, 0);
  curve_error_.assign(n, nullptr);
  precomputed_.assign(n, 0);
  // What the walk hands on, in program order: a run of lines to smooth (pts, ins, tol), or pieces
  // built already. Either way its pieces end up in `store`, `owners` saying whose (instruction,
  // pieces), `marks` the precomputed_ flags to set.
  struct Item {
    std::vector<core::Vec> pts;
    std::vector<std::uint32_t> ins;
    double tol = 0;
    motion::SegmentStore store;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> owners;
    std::vector<std::pair<std::uint32_t, std::uint8_t>> marks;
  };
  std::vector<Item> items;
  // Pieces the walk builds for instruction i (arcs in pieces, curves): onto the last item when it
  // holds built pieces already (a run item is never added to once set aside).
  const auto built = [&](std::uint32_t i) -> Item& {
    if (items.empty() || !items.back().ins.empty()) items.emplace_back();
    Item& it = items.back();
    if (it.owners.empty() || it.owners.back().first != i) it.owners.push_back({i, 0});
    return it;
  };
  const auto add_built = [&](std::uint32_t i, const motion::Segment& seg) {
    Item& it = built(i);
    it.store.push_back(seg);
    ++it.owners.back().second;
  };
  core::Vec at = prog.start;
  std::vector<motion::Segment> tmp;
  // Jerk mode: runs of short lines become curvature-continuous B-splines (polyline_smoothing.hpp).
  double tol = -1;  // as PathMode sets it in update()
  double run_feed = 0;
  bool in_run = false;
  const auto close_run = [&] {
    if (in_run && items.back().ins.size() < 2) items.pop_back();  // one line alone: kept as programmed
    in_run = false;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const auto& op = prog.instructions[i].op;
    if (const auto* pm = std::get_if<program::PathMode>(&op))
      tol = pm->kind == program::PathKind::Blend ? (pm->tolerance_mm > 0 ? pm->tolerance_mm : -1.0) : 0.0;
    const auto* l = std::get_if<program::Linear>(&op);
    const double t = tol < 0 ? pc.tolerance_mm : tol;
    if (smooth && l && t > 0) {
      if (!in_run || l->feed_mm_s != run_feed || t != items.back().tol) {
        close_run();
        items.emplace_back();
        items.back().pts.push_back(at);
        items.back().tol = t;
        run_feed = l->feed_mm_s;
        in_run = true;
      }
      items.back().pts.push_back(l->end);
      items.back().ins.push_back(static_cast<std::uint32_t>(i));
    } else if (!std::holds_alternative<program::PathMode>(op)) {
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
          add_built(static_cast<std::uint32_t>(i),
                    motion::make_arc(from, to, seg->axis0, seg->axis1, seg->c0, seg->c1, seg->sweep > 0 ? 1 : -1));
          from = to;
        }
        precomputed_[i] = 1;
      }
      at = seg->end;
    } else if (is_curve(op)) {
      tmp.clear();
      if (const auto e = append_curve_segments(op, at, tmp); e != motion::CurveError::Ok) {
        curve_error_[i] = motion::to_string(e);
        continue;
      }
      if (!tmp.empty()) {
        for (const auto& seg : tmp) add_built(static_cast<std::uint32_t>(i), seg);
        at = tmp.back().end;
      }
    }
  }
  close_run();

  const std::size_t threads =
      load_threads_ > 0 ? load_threads_ : std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, kMaxLoadThreads);
  const auto runs = static_cast<std::size_t>(std::count_if(items.begin(), items.end(), [](const Item& it) { return !it.ins.empty(); }));
  // A run smoothed: its lines thinned, then the spline's pieces, each stretch packed as soon as the
  // smoothing finishes it (a run's pieces are never all held as 1.5 kB Segments).
  const auto smooth_run = [&](Item& run) {
    motion::PolylineSmoothing cfg;
    cfg.tolerance_mm = pc.smoothing_share * run.tol;
    cfg.max_turn_rad = pc.smoothing_max_turn_rad;
    cfg.threads = runs > 1 ? 1 : threads;  // the runs are what runs at once (one alone: its stretches)
    // Tiny collinear lines become legs of up to kThinLeg_mm (1 µm CAM lines would otherwise be a
    // piece each, which the planner cannot merge: the window then covers too little to brake in,
    // 31 mm/s on the built-in table instead of F6000). The points dropped lie within
    // thin_share·P of the legs, and the spline keeps to the rest of the smoothing share, so it
    // stays within smoothing_share·P of the program. Nothing dropped: every point is a leg's end.
    const double eps = pc.smoothing_thin_share * run.tol;
    std::vector<std::size_t> kept;
    if (eps > 0) motion::thin_polyline(run.pts, eps, kThinLeg_mm, kMaxThinned, kept);
    if (kept.size() < run.pts.size() && !kept.empty()) {
      cfg.tolerance_mm -= eps;
    } else {
      kept.resize(run.pts.size());
      std::iota(kept.begin(), kept.end(), std::size_t{0});
    }
    std::vector<core::Vec> thin_pts;
    thin_pts.reserve(kept.size());
    for (const std::size_t k : kept) thin_pts.push_back(run.pts[k]);
    std::vector<core::Vec>().swap(run.pts);
    run.store.reserve(kept.size() + kept.size() / 16 + 4, kPieceBytes);
    // Leg r stands for lines kept[r] … kept[r + 1] − 1: smoothed, the first carries its segments
    // and the others none (executed with it); kept as a line, all stay as programmed (collinear
    // lines, which the planner merges).
    std::vector<std::vector<motion::Segment>> out;
    motion::smooth_polyline(thin_pts, cfg, out, [&](std::size_t from, std::size_t to) {
      for (std::size_t r = from; r < to; ++r) {
        if (out[r].empty()) continue;
        const std::uint32_t owner = run.ins[kept[r]];
        for (const auto& seg : out[r]) run.store.push_back(seg);
        run.owners.push_back({owner, static_cast<std::uint32_t>(out[r].size())});
        std::vector<motion::Segment>().swap(out[r]);
        run.marks.push_back({owner, 1});
        for (std::size_t k = kept[r] + 1; k < kept[r + 1]; ++k) run.marks.push_back({run.ins[k], kAbsorbed});
      }
    });
    std::vector<std::uint32_t>().swap(run.ins);
  };
  std::size_t first_set = 0;  // curve_first_ is set for instructions below this
  core::ordered_parallel(
      items.size(), threads, kRunsAhead,
      [&](std::size_t k) {
        if (!items[k].ins.empty()) smooth_run(items[k]);
      },
      [&](std::size_t k) {  // in program order: the pieces' places and the marks
        Item& it = items[k];
        std::size_t at_piece = curve_segments_.size();
        for (const auto& [i, count] : it.owners) {
          for (; first_set <= i; ++first_set) curve_first_[first_set] = static_cast<std::uint32_t>(at_piece);
          at_piece += count;
        }
        for (const auto& [i, mark] : it.marks) precomputed_[i] = mark;
        curve_segments_.append(std::move(it.store));
        it = Item{};
      });
  for (; first_set <= n; ++first_set) curve_first_[first_set] = static_cast<std::uint32_t>(curve_segments_.size());
}

// rt-safe
bool Channel::push_curve(int& budget) {
  const program::Op& op = prog_->instructions[pc_].op;
  double feed = 0;
  if (const auto* b = std::get_if<program::Bezier>(&op)) feed = b->feed_mm_s;
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
  state_ = ChannelState::Running;
  return true;
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
      if (curve_error_[pc_]) return fail(curve_error_[pc_], motion::PlanResult::Infeasible);
      if (!push_curve(budget)) return;  // wait for room (or a planning fault)
      ++pc_;
      continue;
    }
    if (to_segment(op, plan_pos_, req_.geom)) {  // written in place: no Segment built per line
      if (planner_.queue().full() || planning_spent()) return;  // wait for room, or the next cycle
      double feed = 0;
      if (const auto* l = std::get_if<program::Linear>(&op)) feed = l->feed_mm_s;
      if (const auto* a = std::get_if<program::Arc>(&op)) feed = a->feed_mm_s;
      const auto r = planner_.push(request(feed, std::holds_alternative<program::Rapid>(op), true, pc_));
      if (r != motion::PlanResult::Ok) return fail(motion::to_string(r), r);
      plan_pos_ = req_.geom.end;
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
