// The block executor shared by interpreter.cpp, setup.cpp, canned.cpp and spline.cpp (internal).
#pragma once

#include <optional>
#include <string>

#include <fmt/format.h>

#include "program/iso/interpreter.hpp"

namespace softmc::program::iso::detail {

inline constexpr bool is_linear_axis(std::size_t a) { return a < 3 || a > 5; }

inline LineError error(std::uint32_t col, std::string message) { return LineError{col, std::move(message)}; }

// Polar coordinates (polar.cpp). An angle word in degrees to radians, as LinuxCNC's D2R.
double polar_radians(double deg);
// (x, y) moved to the radius r and the angle t (radians) about the origin, each kept from (x, y)
// where it is not given.
void polar_point(double& x, double& y, std::optional<double> r, std::optional<double> t);
enum class PolarStep : std::uint8_t { Ok, RadiusAtOrigin, AngleAtOrigin };
// G91 polar step about the origin (LinuxCNC find_ends, CYCLE_MACRO): the radius grows by dr along
// the current angle, then the angle by dt_rad at that radius; either is undefined at the origin.
PolarStep polar_increment(double& x, double& y, std::optional<double> dr, std::optional<double> dt_rad);

// One block's execution against a copy of the state: commit() is the only write to the caller.
struct Exec {
  const Block& b;
  ModalState st;
  const Parameters& params;
  const InterpOptions& opt;
  BlockOutput& out;
  std::uint32_t used = 0;  // bit (letter - 'A'): the word was used by something in the block

  Exec(const Block& blk, const ModalState& s, const Parameters& p, const InterpOptions& o, BlockOutput& ob)
      : b(blk), st(s), params(p), opt(o), out(ob), orig(s) {}

  // Value words, marking them used.
  const std::optional<At<double>>& w(char letter) {
    const auto& x = b.word(letter);
    if (x) used |= 1u << (letter - 'A');
    return x;
  }
  bool has(char letter) const { return b.has(letter); }
  void use_axes() {
    for (std::size_t a = 0; a < core::kMaxAxes; ++a) (void)w(core::letter(a));
  }

  double k() const { return mm_per_unit(st.units); }
  double scale(std::size_t axis) const { return is_linear_axis(axis) ? k() : 1.0; }

  // A numbered parameter as it will be after this block's earlier writes.
  double param(int n) const {
    for (auto it = out.param_writes.rbegin(); it != out.param_writes.rend(); ++it)
      if (it->first == n) return it->second;
    return params.get(n);
  }
  void write_param(int n, double v) { out.param_writes.emplace_back(n, v); }

  core::Vec program_position() const { return to_program(st, st.position); }

  // End point in program coordinates from the block's axis words (G90/G91) or polar coordinates
  // (X and Y), current position elsewhere; `named` gets the axes given.
  std::optional<LineError> program_target(core::Vec& p, std::uint16_t& named) {
    p = program_position();
    named = 0;
    for (std::size_t a = 0; a < core::kMaxAxes; ++a) {
      const auto& x = w(core::letter(a));
      if (!x) continue;
      named |= core::axis_bit(a);
      const double v = x->value * scale(a);
      p[a] = st.distance == Distance::Absolute ? v : p[a] + v;
    }
    if (b.has_polar()) {  // never with X or Y words (polar_words)
      if (auto e = polar_end(p[0], p[1])) return e;
      named |= core::axis_bit(0) | core::axis_bit(1);
    }
    return std::nullopt;
  }
  // Polar coordinates (polar.cpp): what the block may hold with them, and the end point they give
  // from the current program point (x, y).
  std::optional<LineError> polar_words();
  std::optional<LineError> polar_end(double& x, double& y);

  // Machine point of a program point; axes not named keep their machine position exactly (a
  // round trip through the offsets could add rounding noise).
  core::Vec machine_of(const core::Vec& prog, std::uint16_t named) const {
    core::Vec m = to_machine(st, prog);
    const bool xy_coupled = st.rotation_deg != 0 && (named & 0b11);
    for (std::size_t a = 0; a < core::kMaxAxes; ++a) {
      if (named & core::axis_bit(a)) continue;
      if (xy_coupled && a < 2) continue;
      m[a] = st.position[a];
    }
    return m;
  }

  void emit(Op op) { out.ops.push_back(std::move(op)); }
  // Offsets are reported only when they change (a preamble's G54 G49 says nothing new).
  void emit_offsets() {
    const OffsetsChanged now = offsets_of(st), was = offsets_of(orig);
    if (now.coord_system != was.coord_system || now.work != was.work || now.axis != was.axis || now.tool != was.tool ||
        now.rotation_deg != was.rotation_deg || offsets_emitted)
      emit(now);
    offsets_emitted = offsets_emitted || !(now.work == was.work && now.axis == was.axis && now.tool == was.tool &&
                                           now.coord_system == was.coord_system && now.rotation_deg == was.rotation_deg);
  }
  const ModalState& orig;
  bool offsets_emitted = false;

  // Feed of a feed move from st.position to `end` of the given path length (mm; 0 = rotary only).
  // A G94 feed move without a usable feed: missing, or 0 (not after an earlier error).
  std::optional<LineError> feed_missing(std::uint32_t col) const {
    if (st.feed_uncertain || st.feed_usable()) return std::nullopt;
    return error(col, st.feed_mm_s ? "feed rate is 0: a feed move needs an F greater than 0"
                                   : "feed rate missing: program an F word before the first feed move");
  }
  std::optional<LineError> feed_for(std::uint32_t col, double length_mm, double rotary_deg, double& feed);

  std::optional<LineError> run();
  std::optional<LineError> non_motion_m_and_words();
  std::optional<LineError> modes();
  std::optional<LineError> setup();        // G10, G28, G30, G92.x (setup.cpp)
  std::optional<LineError> tool_length();  // G43/G49 (setup.cpp)
  std::optional<LineError> coord_system(); // G54… (setup.cpp)
  std::optional<LineError> motion();
  std::optional<LineError> straight(bool rapid, std::uint32_t col);
  std::optional<LineError> arc(std::uint32_t col);
  std::optional<LineError> spline(std::uint32_t col);  // spline.cpp
  std::optional<LineError> nurbs_point(std::uint32_t col);
  std::optional<LineError> nurbs_end(std::uint32_t col);
  std::optional<LineError> cycle(std::uint32_t col);   // canned.cpp
  std::optional<LineError> stops();
  std::optional<LineError> unused_words();
};

}  // namespace softmc::program::iso::detail
