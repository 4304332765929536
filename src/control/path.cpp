// IR → geometry.
#include "control/path.hpp"

namespace softmc::control {

// rt-safe
std::optional<motion::Segment> to_segment(const program::Op& op, const core::Vec& from) {
  if (const auto* r = std::get_if<program::Rapid>(&op)) return motion::make_line(from, r->end);
  if (const auto* l = std::get_if<program::Linear>(&op)) return motion::make_line(from, l->end);
  if (const auto* a = std::get_if<program::Arc>(&op))
    return motion::make_arc(from, a->end, a->axis0, a->axis1, a->center0, a->center1, a->turns);
  return std::nullopt;
}

}  // namespace softmc::control
