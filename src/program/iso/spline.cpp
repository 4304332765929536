// Splines: G5 cubic and G5.1 quadratic Béziers, G5.2 … G5.3 NURBS blocks (LinuxCNC's words).
//
//   G5   X Y I J P Q   control points: start + (I, J), end + (P, Q); a G5 right after a G5 may leave
//                      out I and J: they continue the previous curve smoothly as -(previous P, Q)
//   G5.1 X Y I J       one control point: start + (I, J)
//   G5.2 X Y P L       opens a NURBS (current position = first control point; X Y = the next, P its
//   X Y P              weight, L the order) and each following line adds a control point;
//   G5.3               closes it: the curve is emitted then, located at the G5.3 line.
#include <cmath>

#include "program/iso/exec.hpp"

namespace softmc::program::iso::detail {

std::optional<LineError> Exec::spline(std::uint32_t col) {
  if (st.plane != Plane::XY) return error(col, fmt::format("{} only works in the XY plane (G17)",
                                                           st.motion == Motion::CubicSpline ? "G5" : "G5.1"));
  for (std::size_t a = 2; a < core::kMaxAxes; ++a)
    if (b.has(core::letter(a)))
      return error(b.word(core::letter(a))->col, "splines move X and Y only");
  if (b.has('K')) return error(b.word('K')->col, "K word in a spline: the control points are given by I J (and P Q)");
  const double kk = k();
  const core::Vec prog_start = program_position();
  std::uint16_t named = 0;
  core::Vec prog_end;
  if (auto e = program_target(prog_end, named)) return e;
  Bezier bz;
  bz.end = machine_of(prog_end, named);
  bz.axis0 = 0;
  bz.axis1 = 1;
  if (st.motion == Motion::CubicSpline) {
    bz.degree = 3;
    double i = 0, j = 0;
    if (b.has('I') || b.has('J')) {
      if (!b.has('I') || !b.has('J')) return error(col, "G5 needs I and J together (or neither, to continue the previous G5)");
      i = w('I')->value * kk;
      j = w('J')->value * kk;
    } else if (st.g5_continues) {
      i = -st.g5_p;
      j = -st.g5_q;
    } else {
      return error(col, "G5 needs I and J: only a G5 right after a G5 may leave them out");
    }
    if (!b.has('P') || !b.has('Q')) return error(col, "G5 needs P and Q: the second control point from the end point");
    const double p = w('P')->value * kk, q = w('Q')->value * kk;
    core::Vec c1 = prog_start, c2 = prog_end;
    c1[0] += i;
    c1[1] += j;
    c2[0] += p;
    c2[1] += q;
    bz.ctrl1 = to_machine(st, c1);
    bz.ctrl2 = to_machine(st, c2);
    st.g5_continues = true;
    st.g5_p = p;
    st.g5_q = q;
  } else {
    bz.degree = 2;
    if (!b.has('I') && !b.has('J')) return error(col, "G5.1 needs I and/or J: the control point from the start point");
    core::Vec c1 = prog_start;
    if (b.has('I')) c1[0] += w('I')->value * kk;
    if (b.has('J')) c1[1] += w('J')->value * kk;
    bz.ctrl1 = to_machine(st, c1);
  }
  if (bz.end == st.position && bz.ctrl1 == st.position) return error(col, "spline of zero length");
  double lin = 0;
  for (std::size_t a = 0; a < 3; ++a) lin += (bz.end[a] - st.position[a]) * (bz.end[a] - st.position[a]);
  if (auto e = feed_for(col, std::sqrt(lin), 0.0, bz.feed_mm_s)) return e;
  emit(bz);
  st.position = bz.end;
  return std::nullopt;
}

std::optional<LineError> Exec::nurbs_point(std::uint32_t col) {
  if (st.plane != Plane::XY) return error(col, "G5.2 only works in the XY plane (G17)");
  for (std::size_t a = 2; a < core::kMaxAxes; ++a)
    if (b.has(core::letter(a))) return error(b.word(core::letter(a))->col, "NURBS control points have X and Y only");
  if (st.nurbs_ctrl.size() >= 10000) return error(col, "more than 10000 NURBS control points");
  double weight = 1;
  if (const auto& p = w('P')) {
    if (!(p->value > 0)) return error(p->col, "NURBS weight (P) must be greater than zero");
    weight = p->value;
  }
  if (const auto& l = w('L')) {
    if (!b.motion) return error(l->col, "the NURBS order (L) goes on the G5.2 line");
    if (l->value < 2 || l->value > 10 || l->value != std::floor(l->value))
      return error(l->col, "NURBS order (L) must be a whole number 2 … 10");
    st.nurbs_order = static_cast<int>(l->value);
  }
  if (!b.has('X') && !b.has('Y')) return error(col, "NURBS control point without X or Y");
  std::uint16_t named = 0;
  core::Vec target;
  if (auto e = program_target(target, named)) return e;
  const core::Vec end = machine_of(target, named);
  st.nurbs_ctrl.push_back(end);
  st.nurbs_weights.push_back(weight);
  st.position = end;  // incremental points follow each other
  return std::nullopt;
}

std::optional<LineError> Exec::nurbs_end(std::uint32_t col) {
  if (st.motion != Motion::Nurbs) return error(col, "G5.3 without an open G5.2 block");
  if (b.has_axes()) return error(b.first_axis_col(), "G5.3 takes no axis words");
  const auto n = st.nurbs_ctrl.size();
  if (n < static_cast<std::size_t>(st.nurbs_order))
    return error(col, fmt::format("a NURBS of order {} needs at least {} control points (the start point counts), it has {}",
                                  st.nurbs_order, st.nurbs_order, n));
  Nurbs nb;
  nb.ctrl = std::move(st.nurbs_ctrl);
  nb.weights = std::move(st.nurbs_weights);
  nb.order = st.nurbs_order;
  double len = 0;
  for (std::size_t i = 1; i < nb.ctrl.size(); ++i) len += core::distance(nb.ctrl[i - 1], nb.ctrl[i]);
  if (auto e = feed_for(col, len, 0.0, nb.feed_mm_s)) return e;
  emit(std::move(nb));
  st.nurbs_ctrl.clear();
  st.nurbs_weights.clear();
  st.motion = Motion::None;  // LinuxCNC: a motion code must follow
  return std::nullopt;
}

}  // namespace softmc::program::iso::detail
