// Coordinate setup of the interpreter: G10 L1/L2/L20, G28/G30 and their stored positions, G92.x,
// G43/G43.1/G49 tool length and the G54…G59.3 coordinate systems (LinuxCNC's semantics).
#include <cmath>

#include "program/iso/exec.hpp"

namespace softmc::program::iso::detail {

std::optional<LineError> Exec::tool_length() {
  if (!b.tool_length) return std::nullopt;
  const int code = b.tool_length->value;
  if (st.comp != Comp::Off)  // LinuxCNC convert_tool_length_offset
    return error(b.tool_length->col, "cannot change the tool length offset with cutter radius compensation on (G40 first)");
  core::Vec t;
  if (code == 430) {
    int tool = st.current_tool;
    if (const auto& h = w('H')) {
      if (h->value < 0 || h->value != std::floor(h->value)) return error(h->col, "H word must be a tool number");
      tool = static_cast<int>(h->value);
    }
    if (tool != 0) {
      const Tool* tt = opt.tools ? opt.tools->find(tool) : nullptr;
      if (!tt) return error(b.has('H') ? b.word('H')->col : b.tool_length->col, fmt::format("tool {} is not in the tool table", tool));
      t = tt->offset;
    }
  } else if (code == 431) {
    // G43.1: the axis words are the offsets themselves (program units).
    if (!b.has_axes()) return error(b.tool_length->col, "G43.1 needs axis words: the tool length offsets");
    for (std::size_t a = 0; a < core::kMaxAxes; ++a)
      if (const auto& x = w(core::letter(a))) t[a] = x->value * scale(a);
  }
  st.tool_length_code = code;
  st.tool = t;
  emit_offsets();
  return std::nullopt;
}

std::optional<LineError> Exec::coord_system() {
  if (!b.coord_system) return std::nullopt;
  if (st.comp != Comp::Off)
    return error(b.coord_system->col, "cannot change the coordinate system with cutter radius compensation on");
  const int n = b.coord_system->value;
  st.coord_system = n;
  for (std::size_t a = 0; a < core::kMaxAxes; ++a) st.work[a] = param(coord_param(n, a));
  st.rotation_deg = param(rotation_param(n));
  write_param(kCoordSystem, n);
  emit_offsets();
  return std::nullopt;
}

namespace {

int whole(double v) { return static_cast<int>(std::llround(v)); }
bool is_whole(double v) { return v == std::floor(v); }

}  // namespace

std::optional<LineError> Exec::setup() {
  if (!b.non_modal) return std::nullopt;
  const int code = b.non_modal->value;
  const std::uint32_t col = b.non_modal->col;
  switch (code) {
    case 100: {
      const auto& l = w('L');
      if (!l) return error(col, "G10 needs an L word: L1 (tool table), L2 or L20 (coordinate system)");
      const auto& p = w('P');
      if (!p) return error(col, fmt::format("G10 L{} needs a P word", l->value));
      if (l->value == 2 || l->value == 20) {
        if (!is_whole(p->value) || p->value < 0 || p->value > 9)
          return error(p->col, "G10 coordinate system (P) must be 0 (the current one) … 9");
        const int n = p->value == 0 ? st.coord_system : whole(p->value);
        const bool current = n == st.coord_system;
        if (current && st.comp != Comp::Off)  // LinuxCNC convert_setup
          return error(col, "cannot change the active coordinate system with cutter radius compensation on (G40 first)");
        if (const auto& r = w('R')) {
          if (l->value == 20) return error(r->col, "R (rotation) only goes with G10 L2");
          write_param(rotation_param(n), r->value);
          if (current) st.rotation_deg = r->value;
        }
        // L20: offsets chosen so that the current position gets the given coordinates in system n
        // (machine = rotate(program + axis) + work + tool). In a rotated system X and Y go together:
        // the one not given keeps its current coordinate there (LinuxCNC convert_setup).
        const core::Vec here = st.position - st.tool;  // machine position of the program origin chain
        const double rot = current ? st.rotation_deg : param(rotation_param(n));
        core::Vec target = here;
        if (l->value == 20) {  // the current position in system n's program coordinates
          core::Vec work_n;
          for (std::size_t a = 0; a < core::kMaxAxes; ++a) work_n[a] = param(coord_param(n, a));
          target = to_program(st.position, st.tool, work_n, rot, st.axis);
        }
        bool xy = false;
        for (std::size_t a = 0; a < core::kMaxAxes; ++a) {
          const auto& x = w(core::letter(a));
          if (!x) continue;
          const double v = x->value * scale(a);
          if (l->value == 20 && a < 2 && rot != 0) {
            target[a] = v;
            xy = true;
            continue;
          }
          const double off = l->value == 2 ? v : here[a] - st.axis[a] - v;
          write_param(coord_param(n, a), off);
          if (current) st.work[a] = off;
        }
        if (xy) {
          core::Vec p = target + st.axis;
          rotate_xy(p, rot);
          for (std::size_t a = 0; a < 2; ++a) {
            const double off = here[a] - p[a];
            write_param(coord_param(n, a), off);
            if (current) st.work[a] = off;
          }
        }
        if (current) emit_offsets();
        return std::nullopt;
      }
      if (l->value == 1) {
        return error(l->col, "G10 L1 (tool table) is not supported: the tool table is read from its file");
      }
      return error(l->col, fmt::format("G10 L{} is not supported (L2 and L20 are)", l->value));
    }
    case 280:
    case 300: {
      if (st.comp != Comp::Off) return error(col, fmt::format("{} cannot be used with cutter radius compensation on", g_code_name(code)));
      const int base = code == 280 ? kG28Home : kG30Home;
      std::uint16_t named = 0;
      core::Vec via_prog;
      if (auto e = program_target(via_prog, named)) return e;
      core::Vec at = st.position;
      if (named) {
        at = machine_of(via_prog, named);
        emit(Rapid{at});
      }
      // Then the stored position ("absolute machine coordinates", LinuxCNC): named axes only, or all.
      for (std::size_t a = 0; a < core::kMaxAxes; ++a)
        if (!named || (named & core::axis_bit(a))) at[a] = param(base + static_cast<int>(a));
      emit(Rapid{at});
      st.position = at;
      return std::nullopt;
    }
    case 281:
    case 301: {
      if (b.has_axes()) return error(b.first_axis_col(), fmt::format("{} takes no axis words: it stores the current position",
                                                                     g_code_name(code)));
      const int base = code == 281 ? kG28Home : kG30Home;
      for (std::size_t a = 0; a < core::kMaxAxes; ++a) write_param(base + static_cast<int>(a), st.position[a]);
      return std::nullopt;
    }
    case 920: {
      if (st.comp != Comp::Off)  // LinuxCNC convert_axis_offsets (G92.1 … G92.3 are allowed there)
        return error(col, "G92 cannot change the axis offsets with cutter radius compensation on (G40 first)");
      if (!b.has_axes()) return error(col, "G92 needs axis words: the coordinates the current position gets");
      const core::Vec unshifted = to_program(st, st.position) + st.axis;  // program position without G92
      for (std::size_t a = 0; a < core::kMaxAxes; ++a) {
        const auto& x = w(core::letter(a));
        if (!x) continue;
        st.axis[a] = unshifted[a] - x->value * scale(a);
      }
      for (std::size_t a = 0; a < core::kMaxAxes; ++a) write_param(kG92Offset + static_cast<int>(a), st.axis[a]);
      write_param(kG92Enabled, 1);
      emit_offsets();
      return std::nullopt;
    }
    case 921:
    case 922:
      st.axis = core::Vec{};
      if (code == 921)
        for (std::size_t a = 0; a < core::kMaxAxes; ++a) write_param(kG92Offset + static_cast<int>(a), 0);
      write_param(kG92Enabled, 0);
      emit_offsets();
      return std::nullopt;
    case 923:
      for (std::size_t a = 0; a < core::kMaxAxes; ++a) st.axis[a] = param(kG92Offset + static_cast<int>(a));
      write_param(kG92Enabled, 1);
      emit_offsets();
      return std::nullopt;
    default: return std::nullopt;  // G4 was done in its step
  }
}

}  // namespace softmc::program::iso::detail
