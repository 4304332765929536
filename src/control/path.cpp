// IR → geometry.
#include "control/path.hpp"

#include <array>

#include "motion/geometry/bezier.hpp"
#include "motion/geometry/nurbs.hpp"

namespace softmc::control {

// rt-safe
std::optional<motion::Segment> to_segment(const program::Op& op, const core::Vec& from) {
  motion::Segment s;
  if (!to_segment(op, from, s)) return std::nullopt;
  return s;
}

bool to_segment(const program::Op& op, const core::Vec& from, motion::Segment& out) {
  if (const auto* r = std::get_if<program::Rapid>(&op)) {
    motion::set_line(out, from, r->end);
  } else if (const auto* l = std::get_if<program::Linear>(&op)) {
    motion::set_line(out, from, l->end);
  } else if (const auto* a = std::get_if<program::Arc>(&op)) {
    out = motion::make_arc(from, a->end, a->axis0, a->axis1, a->center0, a->center1, a->turns);
  } else {
    return false;
  }
  return true;
}

bool is_curve(const program::Op& op) {
  return program::op_holds<program::Bezier>(op) || std::holds_alternative<program::Nurbs>(op);
}

motion::CurveError append_curve_segments(const program::Op& op, const core::Vec& from,
                                         std::vector<motion::Segment>& out) {
  if (const auto* b = program::op_if<program::Bezier>(op)) {
    // G5 (cubic) or G5.1 (quadratic): the control polygon starts where the machine is.
    std::array<core::Vec, 4> ctrl{from, b->ctrl1, b->ctrl2, b->end};
    if (b->degree == 2) ctrl[2] = b->end;
    const std::size_t n = b->degree == 2 ? 3 : 4;
    const std::array<double, 4> w{1, 1, 1, 1};
    return motion::append_rational_bezier(out, std::span(ctrl.data(), n), std::span(w.data(), n));
  }
  if (const auto* nb = std::get_if<program::Nurbs>(&op)) {
    auto r = motion::nurbs_g5_2(nb->ctrl, nb->weights, nb->order);
    if (!r.ok()) return r.error;
    out.insert(out.end(), r.segments.begin(), r.segments.end());
  }
  return motion::CurveError::Ok;
}

std::pair<motion::CurveError, std::uint32_t> visit_program_geometry(
    const program::Program& prog, const std::function<void(std::uint32_t, const motion::Segment&)>& fn) {
  std::pair<motion::CurveError, std::uint32_t> error{motion::CurveError::Ok, 0};
  core::Vec at = prog.start;
  std::vector<motion::Segment> tmp;
  for (std::uint32_t i = 0; i < prog.instructions.size(); ++i) {
    const auto& op = prog.instructions[i].op;
    if (auto seg = to_segment(op, at)) {
      fn(i, *seg);
      at = seg->end;
    } else if (is_curve(op)) {
      tmp.clear();
      if (const auto e = append_curve_segments(op, at, tmp); e != motion::CurveError::Ok) {
        if (error.first == motion::CurveError::Ok) error = {e, i};
        continue;
      }
      for (const auto& s : tmp) fn(i, s);
      if (!tmp.empty()) at = tmp.back().end;
    }
  }
  return error;
}

}  // namespace softmc::control
