// Interpreter: applies one checked block to the modal state and emits canonical IR operations.
#include "program/iso/interpreter.hpp"

#include <bit>
#include <cmath>
#include <cstdint>

#include "program/iso/arc.hpp"
#include "program/iso/exec.hpp"
#include "program/iso/expression.hpp"

namespace softmc::program::iso {

using detail::error;

void rotate_xy(core::Vec& v, double deg) {
  if (deg == 0) return;
  const double c = std::cos(deg * kDeg), s = std::sin(deg * kDeg);
  const double x = v[0] * c - v[1] * s;
  const double y = v[0] * s + v[1] * c;
  v[0] = x;
  v[1] = y;
}

namespace {

const char* word_users(char letter) {
  switch (letter) {
    case 'I': case 'J': case 'K': return "G2/G3 arcs, G5/G5.1 splines, G87";
    case 'R': return "G2/G3 arcs, canned cycles, G10 L2";
    case 'P': return "G4, G2/G3, G5, G5.2, G10, G64, canned cycles, M62…M66";
    case 'Q': return "G5, G64, G73/G83, M66, M61, M67/M68";
    case 'L': return "G10, canned cycles, G5.2, M66";
    case 'E': return "M66, M67/M68";
    case 'D': return "G41/G42, G96";
    case 'H': return "G43";
    default: return "";
  }
}

}  // namespace

bool no_offsets(const ModalState& st) {
  std::uint64_t bits = std::bit_cast<std::uint64_t>(st.rotation_deg);
  for (std::size_t a = 0; a < core::kMaxAxes; ++a)
    bits |= std::bit_cast<std::uint64_t>(st.work[a]) | std::bit_cast<std::uint64_t>(st.axis[a]) |
            std::bit_cast<std::uint64_t>(st.tool[a]);
  return bits == 0;
}

core::Vec to_machine(const ModalState& st, const core::Vec& program) {
  if (no_offsets(st)) {
    core::Vec m = program;
    for (double& x : m.v) x += 0.0;  // as adding the zero offsets does: -0 becomes 0
    return m;
  }
  core::Vec m = program + st.axis;
  rotate_xy(m, st.rotation_deg);
  return m + st.work + st.tool;
}

core::Vec to_program(const ModalState& st, const core::Vec& machine) {
  if (no_offsets(st)) return machine;  // x - 0 is x, -0 included
  return to_program(machine, st.tool, st.work, st.rotation_deg, st.axis);
}

core::Vec to_program(const core::Vec& machine, const core::Vec& tool, const core::Vec& work, double rotation_deg,
                     const core::Vec& axis) {
  core::Vec p = machine - tool - work;
  rotate_xy(p, -rotation_deg);
  return p - axis;
}

OffsetsChanged offsets_of(const ModalState& st) {
  OffsetsChanged o;
  o.coord_system = st.coord_system;
  o.work = st.work;
  o.axis = st.axis;
  o.tool = st.tool;
  o.rotation_deg = st.rotation_deg;
  return o;
}

namespace detail {

std::optional<LineError> Exec::feed_for(std::uint32_t col, double length_mm, double rotary_deg, double& feed) {
  if (st.feed_mode == FeedMode::InverseTime) {
    if (!st.feed_in_block && !st.feed_uncertain)
      return error(col, "inverse time feed (G93): every feed move needs its own F word");
    if (!(st.feed_word > 0) && !st.feed_uncertain)
      return error(col, "inverse time feed (G93): F must be greater than 0 (moves per minute)");
    const double minutes = st.feed_word > 0 ? 1.0 / st.feed_word : 1.0;
    const double path = length_mm > 0 ? length_mm : rotary_deg;
    feed = path / (minutes * 60.0);
    if (!(feed > 0)) feed = st.feed_usable() ? *st.feed_mm_s : 1.0;  // a move of length 0: any positive speed
    return std::nullopt;
  }
  if (auto e = feed_missing(col)) return e;
  feed = st.feed_usable() ? *st.feed_mm_s : 1.0;  // else only after an earlier error (feed_uncertain): any speed
  // A move of rotary axes only takes F in degrees per minute, whatever G20/G21 (LinuxCNC).
  if (length_mm == 0 && rotary_deg > 0 && st.units == Units::Inch) feed /= kMmPerInch;
  return std::nullopt;
}

std::optional<LineError> Exec::run() {
  // Every length and the F word of a block are read in the units in effect after the block's own
  // G20/G21, so "G20 F10" is 10 in/min.
  if (auto e = polar_words()) return e;  // LinuxCNC checks them when it reads the block
  if (b.units) st.units = b.units->value;
  if (b.feed_mode && b.feed_mode->value != st.feed_mode) {
    // F means another thing in the other mode: it must be programmed again (LinuxCNC sets the feed
    // to 0 at every G93/G94; softmc only where the mode changes, so a header's repeated G94 keeps F).
    st.feed_mode = b.feed_mode->value;
    st.feed_mm_s.reset();
    st.feed_word = 0;
  }
  st.feed_in_block = false;
  if (const auto& f = w('F')) {
    st.feed_word = f->value;
    st.feed_in_block = true;
    if (st.feed_mode == FeedMode::PerMinute) st.feed_mm_s = f->value * k() / 60.0;  // F is per minute; inside, mm/s
  }
  if (auto e = non_motion_m_and_words()) return e;
  if (auto e = modes()) return e;
  if (auto e = setup()) return e;
  if (auto e = motion()) return e;
  if (auto e = stops()) return e;
  return unused_words();
}

// S, T, M6/M61, spindle, coolant and other M functions, I/O, dwell: LinuxCNC steps 3…10.
std::optional<LineError> Exec::non_motion_m_and_words() {
  const MTable& mt = *opt.mtable;
  auto mfn = [&](const Block::MCode& m) { emit(MFunction{m.number, static_cast<std::uint8_t>(m.group)}); };

  if (b.spindle_mode) {
    const bool css = b.spindle_mode->value == 960;
    if (css && !b.has('S')) return error(b.spindle_mode->col, "G96 needs an S word: the surface speed");
    st.css = css;  // modal: a later S alone is a surface speed too (LinuxCNC), with the same D limit
    const auto& d = w('D');
    st.css_max_rpm = css && d ? d->value : 0.0;
  }
  if (const auto& s = w('S')) {
    SpindleSpeed sp;
    st.spindle_speed = s->value;
    if (st.css) {
      sp.css = true;
      sp.surface_m_min = st.units == Units::Inch ? s->value * 0.3048 : s->value;  // ft/min → m/min
      sp.max_rpm = st.css_max_rpm;
    } else {
      sp.rpm = s->value;
    }
    emit(sp);
  }
  if (const auto& t = w('T')) {
    st.selected_tool = static_cast<int>(t->value);
    emit(ToolSelect{st.selected_tool});
  }
  for (std::size_t k = 0; k < b.m_count; ++k) {
    const auto& m = b.m[k];
    switch (m.number) {
      case 0: case 1: case 2: case 30: case 60: continue;  // stops come last
      case 6:
        if (st.comp != Comp::Off) return error(m.col, "cannot change tools with cutter radius compensation on (G40 first)");
        mfn(m);
        st.current_tool = st.selected_tool;
        emit(ToolChange{st.current_tool});
        continue;
      case 61: {
        const auto& q = w('Q');
        if (!q || q->value < 0 || q->value != std::floor(q->value))
          return error(m.col, "M61 needs a Q word: the tool number now in the spindle");
        mfn(m);
        st.current_tool = static_cast<int>(q->value);
        continue;
      }
      case 3: case 4: case 5:
        mfn(m);
        emit(ToolSwitch{m.number != 5});
        st.spindle = m.number == 3 ? SpindleDir::Cw : m.number == 4 ? SpindleDir::Ccw : SpindleDir::Stopped;
        continue;
      case 48: case 49:
        mfn(m);
        st.feed_override = m.number == 48;
        continue;
      case 7: case 8: case 9: case 17:  // coolant (P-10 group 5): mist, flood, off, both
        mfn(m);
        st.mist = m.number == 7 || m.number == 17 || (m.number == 8 && st.mist);
        st.flood = m.number == 8 || m.number == 17 || (m.number == 7 && st.flood);
        continue;
      case 62: case 63: case 64: case 65: case 67: case 68: {
        if (st.comp != Comp::Off)  // LinuxCNC refuses them too (its outputs are not held with the moves)
          return error(m.col, fmt::format("M{} cannot set an output with cutter radius compensation on (G40 first)",
                                          m.number));
        if (m.number >= 67) {
          const auto& e = w('E');
          const auto& q = w('Q');
          if (!e) return error(m.col, fmt::format("M{} needs an E word: the number of the analog output (0 … {})",
                                                  m.number, kAnalogOutputs - 1));
          if (e->value < 0 || e->value >= kAnalogOutputs || e->value != std::floor(e->value))
            return error(e->col, fmt::format("M{} E{:g}: analog outputs are numbered 0 … {}", m.number, e->value,
                                             kAnalogOutputs - 1));
          if (!q) return error(m.col, fmt::format("M{} needs a Q word: the value to set", m.number));
          mfn(m);
          emit(AnalogOutput{static_cast<int>(e->value), q->value, m.number == 67});
          continue;
        }
        const auto& p = w('P');
        if (!p || p->value < 0 || p->value != std::floor(p->value))
          return error(m.col, fmt::format("M{} needs a P word: the number of the digital output", m.number));
        if (p->value > 63) return error(p->col, fmt::format("M{} P{:g}: digital outputs are numbered 0 … 63", m.number, p->value));
        mfn(m);
        emit(DigitalOutput{static_cast<int>(p->value), m.number == 62 || m.number == 64, m.number <= 63});
        continue;
      }
      case 66: {
        const auto& p = w('P');
        const auto& e = w('E');
        if (p && e) return error(e->col, "M66 takes either P (digital input) or E (analog input), not both");
        if (!p && !e) return error(m.col, "M66 needs a P word (digital input) or an E word (analog input)");
        const auto& in = p ? p : e;
        if (in->value < 0 || in->value != std::floor(in->value)) return error(in->col, "input number must be a whole number, 0 or more");
        WaitInput wi;
        wi.index = static_cast<int>(in->value);
        wi.digital = p.has_value();
        if (const auto& l = w('L')) {
          if (l->value < 0 || l->value > 4 || l->value != std::floor(l->value))
            return error(l->col, "M66 wait mode (L) must be 0 … 4");
          wi.mode = static_cast<int>(l->value);
        }
        if (!wi.digital && wi.mode != 0) return error(m.col, "M66 with an analog input (E) only reads it: L must be 0");
        if (const auto& q = w('Q')) {
          if (q->value < 0) return error(q->col, "M66 timeout (Q) must be 0 or more");
          wi.timeout_s = q->value;
        } else if (wi.mode != 0) {
          return error(m.col, "M66 with a wait mode (L1 … L4) needs a Q word: the timeout in seconds");
        }
        mfn(m);
        emit(wi);
        out.m66 = true;
        continue;
      }
      case 19:
        (void)w('R'), (void)w('Q'), (void)w('P');  // orientation angle, timeout, direction: the PLC's
        mfn(m);
        st.spindle = SpindleDir::Stopped;  // an oriented spindle stands (LinuxCNC: spindle_turning = STOPPED)
        continue;
      default:
        (void)mt;
        mfn(m);
        continue;
    }
  }
  if (b.non_modal && b.non_modal->value == 40) {
    const auto& p = w('P');
    if (!p) return error(b.non_modal->col, "G4 needs a P word: the dwell time in seconds");
    if (p->value < 0) return error(p->col, "dwell time (P) must be 0 or more");
    emit(Dwell{p->value});
  }
  return std::nullopt;
}

// Plane, units (already applied), cutter compensation, tool length, coordinate system, path
// control, distance modes, retract mode: LinuxCNC steps 11…18.
std::optional<LineError> Exec::modes() {
  if (b.plane) {
    if (st.comp != Comp::Off && b.plane->value != st.plane)
      return error(b.plane->col, "cannot change the plane with cutter radius compensation on (G40 first)");
    st.plane = b.plane->value;
  }
  if (b.comp) {
    const int c = b.comp->value;
    if (c == 400) {
      if (st.comp != Comp::Off) {
        out.comp = BlockOutput::CompChange{out.ops.size(), false};
        st.arc_not_allowed = st.comp_radius_mm > 0 && st.comp_moved;
      }
      st.comp = Comp::Off;
    } else {
      if (st.comp != Comp::Off)
        return error(b.comp->col, "cutter radius compensation is already on: program G40 before turning it on again");
      double radius = 0;
      const auto& d = w('D');
      if (c == 411 || c == 421) {  // G41.1/G42.1: D is the diameter
        if (!d) return error(b.comp->col, fmt::format("{} needs a D word: the tool diameter", g_code_name(c)));
        if (d->value < 0) return error(d->col, "tool diameter (D) must be 0 or more");
        radius = d->value * k() / 2;
      } else {
        int tool = st.current_tool;
        if (d) {
          if (d->value < 0 || d->value != std::floor(d->value)) return error(d->col, "D word must be a tool number");
          tool = static_cast<int>(d->value);
        }
        if (tool != 0) {
          const Tool* t = opt.tools ? opt.tools->find(tool) : nullptr;
          if (!t) return error(d ? d->col : b.comp->col, fmt::format("tool {} is not in the tool table", tool));
          radius = t->diameter_mm / 2;
        }
      }
      const auto pa = axes_of(st.plane);
      st.comp = (c == 410 || c == 411) ? Comp::Left : Comp::Right;
      st.comp_radius_mm = radius;
      st.comp_moved = false;
      out.comp = BlockOutput::CompChange{out.ops.size(), true, st.comp == Comp::Left ? CompSide::Left : CompSide::Right,
                                         radius, pa.a0, pa.a1};
    }
  }
  if (auto e = tool_length()) return e;
  if (auto e = coord_system()) return e;
  if (b.path) {
    PathMode pm;
    switch (b.path->value) {
      case 610: pm.kind = PathKind::ExactPath; break;
      case 611: pm.kind = PathKind::ExactStop; break;
      case 640:
        pm.kind = PathKind::Blend;
        if (const auto& p = w('P')) {
          if (p->value < 0) return error(p->col, "G64 path tolerance (P) must be 0 or more");
          pm.tolerance_mm = p->value * k();
          pm.naive_tolerance_mm = pm.tolerance_mm;  // LinuxCNC: Q defaults to P
        }
        if (const auto& q = w('Q')) {
          if (!b.has('P')) return error(q->col, "G64 Q needs a P word as well");
          if (q->value < 0) return error(q->col, "G64 naive CAM tolerance (Q) must be 0 or more");
          pm.naive_tolerance_mm = q->value * k();
        }
        break;
      case 230:
        pm.kind = PathKind::Blend;
        pm.tolerance_mm = pm.naive_tolerance_mm = opt.g23_tolerance_mm;
        pm.continuous = true;
        break;
      default: break;
    }
    // Until the program names a path mode the machine's configured default applies (planner.tolerance_mm),
    // so the first path word is always emitted, even when it equals the interpreter's initial state.
    const bool same = st.path_programmed && pm == st.path;
    st.path = pm;
    st.path_programmed = true;
    if (!same) emit(pm);
  }
  if (b.distance) st.distance = b.distance->value;
  if (b.arc_distance) st.arc_distance = b.arc_distance->value;
  if (b.retract) st.retract = b.retract->value;
  return std::nullopt;
}

std::optional<LineError> Exec::motion() {
  if (b.motion) {
    if (st.motion == Motion::Nurbs && b.motion->value != Motion::Nurbs)
      return error(b.motion->col, "a G5.2 NURBS block is open: close it with G5.3 first");
    if (is_cycle(b.motion->value) && st.comp != Comp::Off)
      return error(b.motion->col, "canned cycles cannot run with cutter radius compensation on (G40 first)");
    if (st.motion != Motion::CubicSpline || b.motion->value != Motion::CubicSpline) st.g5_continues = false;
  }
  if (b.nurbs_end) return nurbs_end(*b.nurbs_end);
  const int axis_user = b.axis_words_code();  // G10, G28, G30, G92, G43.1: the axis words are theirs
  if (b.motion && b.motion->value != Motion::None && axis_user) {
    return error(b.motion->col, fmt::format("{} and {} both use axis words: put them in separate blocks",
                                            g_code_name(axis_user),
                                            b.motion->value == Motion::Rapid ? "G0" : "the motion code"));
  }
  // Polar coordinates stand for X and Y words here (LinuxCNC's enhance_block counts them as axis words).
  const char* const what = b.has_axes() ? "axis words" : "polar coordinates (@ ^)";
  if (b.motion && b.motion->value == Motion::None && b.has_position() && !axis_user)
    return error(b.first_position_col(), fmt::format("{} with G80: G80 cancels the motion mode and cannot move", what));
  if (b.motion) {
    if (b.motion->value == Motion::Nurbs && st.motion == Motion::Nurbs)
      return error(b.motion->col, "G5.2 inside an open G5.2 block: close it with G5.3 first");
    if (is_cycle(b.motion->value) && b.motion->value != st.motion) st.cycle_r = NAN;  // R must be given again
    if (!is_cycle(b.motion->value)) st.cycle_il = NAN;  // a run of canned cycles ends
    st.motion = b.motion->value;
    if (st.motion == Motion::Nurbs) {
      st.nurbs_ctrl.assign(1, st.position);
      st.nurbs_weights.assign(1, 1.0);
      st.nurbs_order = 3;
    }
  }
  if (axis_user) return std::nullopt;  // their axis words were used by setup()/tool_length()
  // A motion word moves (or at least sets the mode); axis words alone move in the modal motion.
  const bool moves = b.has_position() || (b.motion && b.motion->value != Motion::None && !is_cycle(b.motion->value) &&
                                          b.motion->value != Motion::Nurbs);
  if (b.has_position() && st.motion == Motion::None && !st.motion_uncertain)
    return error(b.first_position_col(), fmt::format("{} with no motion mode: program G0, G1, G2 or G3 first", what));
  if (b.g53_col) {
    if (st.motion != Motion::Rapid && st.motion != Motion::Linear)
      return error(*b.g53_col, "G53 needs G0 or G1 in effect: it moves in machine coordinates");
    if (st.distance == Distance::Incremental) return error(*b.g53_col, "G53 cannot be used in incremental mode (G91)");
    if (st.comp != Comp::Off) return error(*b.g53_col, "G53 cannot be used with cutter radius compensation on");
  }
  if (!moves || st.motion == Motion::None) return std::nullopt;
  if (st.comp != Comp::Off) st.comp_moved = true;
  const std::uint32_t col = b.motion ? b.motion->col : b.first_position_col();
  // The feed is checked before the geometry: it is the first thing missing in a CAM-less program.
  if (is_feed_motion(st.motion) && st.motion != Motion::Nurbs && st.feed_mode == FeedMode::PerMinute)
    if (auto e = feed_missing(col)) return e;
  switch (st.motion) {
    case Motion::Rapid: return straight(true, col);
    case Motion::Linear: return straight(false, col);
    case Motion::ArcCw:
    case Motion::ArcCcw: return arc(col);
    case Motion::CubicSpline:
    case Motion::QuadSpline:
    case Motion::Nurbs:
      // LinuxCNC: "Cannot convert spline with cutter radius compensation". The compensation stage
      // offsets lines and arcs only; a spline would pass through it uncompensated.
      if (st.comp != Comp::Off)
        return error(col, "splines (G5, G5.1, G5.2) cannot run with cutter radius compensation on (G40 first)");
      return st.motion == Motion::Nurbs ? nurbs_point(col) : spline(col);
    default: return cycle(col);
  }
}

std::optional<LineError> Exec::straight(bool rapid, std::uint32_t col) {
  st.arc_not_allowed = false;  // LinuxCNC convert_straight
  std::uint16_t named = 0;
  core::Vec end;
  if (b.g53_col) {
    end = st.position;
    for (std::size_t a = 0; a < core::kMaxAxes; ++a)
      if (const auto& x = w(core::letter(a))) {
        end[a] = x->value * scale(a);
        named |= core::axis_bit(a);
      }
  } else {
    core::Vec target;
    if (auto e = program_target(target, named)) return e;
    end = machine_of(target, named);
  }
  if (rapid) {
    if (b.has_position()) emit(Rapid{end});
  } else {
    double lin = 0, rot = 0;
    for (std::size_t a = 0; a < core::kMaxAxes; ++a) {
      const double d = end[a] - st.position[a];
      (is_linear_axis(a) ? lin : rot) += d * d;
    }
    double feed = 0;
    if (auto e = feed_for(col, std::sqrt(lin), std::sqrt(rot), feed)) return e;
    if (b.has_position()) emit(Linear{end, feed});
  }
  st.position = end;
  return std::nullopt;
}

std::optional<LineError> Exec::arc(std::uint32_t col) {
  const PlaneAxes pa = axes_of(st.plane);
  static constexpr char kCentre[3] = {'I', 'J', 'K'};  // offsets along X, Y, Z
  const char l0 = core::letter(pa.a0), l1 = core::letter(pa.a1);
  const char c0 = kCentre[pa.a0], c1 = kCentre[pa.a1], cn = kCentre[pa.n];
  if (st.arc_not_allowed)
    return error(col, "the move just after G40 must be straight, not an arc: it starts where the tool is, not at "
                      "the programmed point (LinuxCNC)");
  if (st.rotation_deg != 0 && st.plane != Plane::XY)
    return error(col, "arcs in G18/G19 on a rotated coordinate system are not supported");
  if (b.has(cn)) return error(b.word(cn)->col, fmt::format("{} word in a {} arc: the centre is given by {} and {}", cn,
                                                            plane_code(st.plane), c0, c1));
  const bool r_format = b.has('R');
  // Without either plane word a centre-format arc ends where it starts: a full circle (LinuxCNC 2.9's
  // rs274 takes `G2 I5 J0` so, and CAM posts write full circles that way); an R-format arc cannot.
  // Polar coordinates (G17 only) give X and Y: LinuxCNC's convert_arc counts them as the plane words.
  if (!b.has(l0) && !b.has(l1) && !b.has_polar() && r_format)
    return error(col, fmt::format("{} and {} words both missing for an R-format arc", l0, l1));
  if (r_format && (b.has(c0) || b.has(c1)))
    return error(b.word('R')->col, "R word together with centre words: give the arc either a radius or a centre");
  if (!r_format && !b.has(c0) && !b.has(c1))
    return error(col, fmt::format("{} and {} words both missing: give the arc centre with {} and/or {}", c0, c1, c0, c1));
  int turns = 1;
  if (const auto& p = w('P')) {
    if (p->value < 1 || p->value != std::floor(p->value))
      return error(p->col, "arc turns (P) must be a whole number, 1 or more");
    turns = static_cast<int>(p->value);  // |P| <= 1e9 (lexer bound) fits an int
  }
  std::uint16_t named = 0;
  const core::Vec prog_start = program_position();
  core::Vec prog_end;
  if (auto e = program_target(prog_end, named)) return e;
  const core::Vec end = machine_of(prog_end, named);
  ArcRequest rq;
  rq.start = st.position;
  rq.end = end;
  rq.plane = pa;
  rq.clockwise = st.motion == Motion::ArcCw;
  rq.turns = turns;
  rq.units = st.units;
  if (r_format) {
    const auto& r = w('R');
    if (auto msg = centre_from_radius(st.position, end, pa, r->value * k(), rq.clockwise, rq.center0, rq.center1))
      return error(col, std::move(*msg));
  } else {
    // The centre as a program point, then through the offsets like any other point.
    core::Vec centre = prog_start;
    const double i0 = b.has(c0) ? w(c0)->value * k() : 0.0;
    const double i1 = b.has(c1) ? w(c1)->value * k() : 0.0;
    const bool incremental = st.arc_distance == Distance::Incremental;
    centre[pa.a0] = incremental ? prog_start[pa.a0] + i0 : i0;
    centre[pa.a1] = incremental ? prog_start[pa.a1] + i1 : i1;
    const core::Vec mc = to_machine(st, centre);
    rq.center0 = mc[pa.a0];
    rq.center1 = mc[pa.a1];
  }
  Arc a;
  if (auto msg = make_arc(rq, a)) return error(col, std::move(*msg));
  double rot = 0;
  for (std::size_t i = 3; i <= 5; ++i) rot += (end[i] - st.position[i]) * (end[i] - st.position[i]);
  if (auto e = feed_for(col, arc_length_mm(st.position, a), std::sqrt(rot), a.feed_mm_s)) return e;
  emit(a);
  st.position = end;
  return std::nullopt;
}

std::optional<LineError> Exec::stops() {
  for (std::size_t k = 0; k < b.m_count; ++k) {
    const auto& m = b.m[k];
    const auto group = static_cast<std::uint8_t>(m.group);
    switch (m.number) {
      case 0:
      case 1:
      case 60:
        emit(MFunction{m.number, group});
        emit(Pause{m.number == 1});
        break;
      case 2:
      case 30:
        if (st.motion == Motion::Nurbs && !st.nurbs_uncertain)
          return error(m.col, "program end inside an open G5.2 block: close it with G5.3");
        if (st.comp != Comp::Off) out.comp = BlockOutput::CompChange{out.ops.size(), false};
        emit(MFunction{m.number, group});
        emit(ProgramEnd{m.number == 30});
        st.ended = true;
        break;
      default: break;
    }
  }
  return std::nullopt;
}

std::optional<LineError> Exec::unused_words() {
  // Axis words nobody used: the motion-mode message of the foundation.
  for (char l : {'I', 'J', 'K', 'R', 'P', 'Q', 'L', 'E', 'D', 'H'}) {
    const auto& x = b.word(l);
    if (x && !(used & (1u << (l - 'A'))))
      return error(x->col, fmt::format("{} word with nothing to use it (it goes with {})", l, word_users(l)));
  }
  return std::nullopt;
}

}  // namespace detail

std::optional<LineError> execute(const Block& b, ModalState& state, const Parameters& params, const InterpOptions& opt,
                                 BlockOutput& out) {
  static const MTable kFixed;
  InterpOptions o = opt;
  if (!o.mtable) o.mtable = &kFixed;
  // The NURBS points collected so far (up to 10000) move into the working copy instead of being
  // copied with the state on every block; on error they move back without what the block added.
  std::vector<core::Vec> ctrl;
  std::vector<double> weights;
  ctrl.swap(state.nurbs_ctrl);
  weights.swap(state.nurbs_weights);
  const std::size_t n_ctrl = ctrl.size(), n_weights = weights.size();
  detail::Exec ex(b, state, params, o, out);
  ex.st.nurbs_ctrl.swap(ctrl);
  ex.st.nurbs_weights.swap(weights);
  if (auto e = ex.run()) {
    if (ex.st.nurbs_ctrl.size() >= n_ctrl && ex.st.nurbs_weights.size() >= n_weights) {
      ex.st.nurbs_ctrl.resize(n_ctrl);  // a point added by this block (or a G5.2 started on nothing)
      ex.st.nurbs_weights.resize(n_weights);
      state.nurbs_ctrl.swap(ex.st.nurbs_ctrl);
      state.nurbs_weights.swap(ex.st.nurbs_weights);
    } else {
      for (auto& op : out.ops)  // G5.3 moved them into its Nurbs before a later part of the block failed
        if (auto* nb = std::get_if<Nurbs>(&op); nb && nb->ctrl.size() == n_ctrl) {
          state.nurbs_ctrl.swap(nb->ctrl);
          state.nurbs_weights.swap(nb->weights);
        }
    }
    return e;
  }
  state = std::move(ex.st);
  return std::nullopt;
}

}  // namespace softmc::program::iso
