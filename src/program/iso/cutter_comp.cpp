// Cutter radius compensation: offset moves, corner arcs at outside corners, cut-backs at inside ones.
#include "program/iso/cutter_comp.hpp"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

namespace softmc::program::iso {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

struct P2 {
  double x = 0, y = 0;
};
P2 operator+(P2 a, P2 b) { return {a.x + b.x, a.y + b.y}; }
P2 operator-(P2 a, P2 b) { return {a.x - b.x, a.y - b.y}; }
P2 operator*(P2 a, double k) { return {a.x * k, a.y * k}; }
double cross(P2 a, P2 b) { return a.x * b.y - a.y * b.x; }
double dot(P2 a, P2 b) { return a.x * b.x + a.y * b.y; }
double len(P2 a) { return std::hypot(a.x, a.y); }

// Angle swept going from a to b about c in direction dir (+1 ccw, -1 cw), in [0, 2π).
double sweep(P2 a, P2 b, P2 c, int dir) {
  const P2 ra = a - c, rb = b - c;
  double ang = std::atan2(cross(ra, rb), dot(ra, rb));  // (-π, π], ccw positive
  if (dir < 0) ang = -ang;
  if (ang < 0) ang += kTwoPi;
  return ang;
}

// Unit tangent of an arc about c at point p, travelling in direction dir.
P2 arc_tangent(P2 p, P2 c, int dir) {
  const P2 r = p - c;
  const double l = len(r);
  return P2{-r.y / l, r.x / l} * static_cast<double>(dir);
}

// Offset geometry of a move: a line through `p` with direction `d`, or a circle (c, r).
struct Offset {
  bool circle = false;
  P2 p, d;
  P2 c;
  double r = 0;
};

// Intersections of two offset geometries (0, 1 or 2 points).
int intersect(const Offset& a, const Offset& b, P2 out[2]) {
  if (!a.circle && !b.circle) {
    const double den = cross(a.d, b.d);
    if (std::fabs(den) < 1e-12) return 0;
    const double t = cross(b.p - a.p, b.d) / den;
    out[0] = a.p + a.d * t;
    return 1;
  }
  if (a.circle != b.circle) {
    const Offset& l = a.circle ? b : a;
    const Offset& c = a.circle ? a : b;
    // |l.p + t d - c|^2 = r^2 with |d| = 1
    const P2 f = l.p - c.c;
    const double bq = dot(f, l.d);
    const double cq = dot(f, f) - c.r * c.r;
    const double disc = bq * bq - cq;
    if (disc < 0) return 0;
    const double s = std::sqrt(disc);
    out[0] = l.p + l.d * (-bq - s);
    out[1] = l.p + l.d * (-bq + s);
    return 2;
  }
  const P2 dc = b.c - a.c;
  const double d = len(dc);
  if (d < 1e-12) return 0;
  const double x = (d * d + a.r * a.r - b.r * b.r) / (2 * d);
  const double h2 = a.r * a.r - x * x;
  if (h2 < 0) return 0;
  const double h = std::sqrt(h2);
  const P2 u = dc * (1.0 / d);
  const P2 n{-u.y, u.x};
  out[0] = a.c + u * x + n * h;
  out[1] = a.c + u * x - n * h;
  return 2;
}

// The move's end point (every motion op has one).
core::Vec end_of(const Op& op) {
  if (const auto* r = std::get_if<Rapid>(&op)) return r->end;
  if (const auto* l = std::get_if<Linear>(&op)) return l->end;
  return std::get<Arc>(op).end;
}

void set_end(Op& op, const core::Vec& e) {
  if (auto* r = std::get_if<Rapid>(&op)) r->end = e;
  if (auto* l = std::get_if<Linear>(&op)) l->end = e;
  if (auto* a = std::get_if<Arc>(&op)) a->end = e;
}

double feed_of(const Op& op) {
  if (const auto* l = std::get_if<Linear>(&op)) return l->feed_mm_s;
  if (const auto* a = std::get_if<Arc>(&op)) return a->feed_mm_s;
  return 0;
}

std::string radius_text(double r) { return fmt::format("{:g}", r); }

}  // namespace

std::optional<std::string> CutterComp::start(CompSide side, double radius_mm, std::uint8_t axis0,
                                             std::uint8_t axis1, const core::Vec& position) {
  if (active_) return "cutter compensation is already on: program G40 before turning it on again";
  if (!std::isfinite(radius_mm) || radius_mm < 0) return "cutter compensation radius must be 0 or more";
  if (axis0 >= core::kMaxAxes || axis1 >= core::kMaxAxes || axis0 == axis1) return "invalid compensation plane";
  active_ = true;
  first_move_ = true;
  side_ = side;
  radius_mm_ = radius_mm;
  a0_ = axis0;
  a1_ = axis1;
  programmed_ = position;
  tool_ = position;
  held_.reset();
  after_.clear();
  return std::nullopt;
}

void CutterComp::release(std::vector<Instruction>& out) {
  if (held_) out.push_back(held_->ins);
  held_.reset();
  for (auto& i : after_) out.push_back(std::move(i));
  after_.clear();
}

void CutterComp::stop(std::vector<Instruction>& out) {
  release(out);
  active_ = false;
}

std::optional<CompError> CutterComp::push(const Instruction& in, std::vector<Instruction>& out) {
  if (!active_ || !is_motion(in.op)) {
    if (active_ && held_) {
      after_.push_back(in);
    } else {
      out.push_back(in);
    }
    if (!active_ && is_motion(in.op)) tool_ = programmed_ = end_of(in.op);
    return std::nullopt;
  }
  return push_motion(in, out);
}

// The state is changed only once every check has passed, so an error leaves the stage as it was.
std::optional<CompError> CutterComp::push_motion(const Instruction& in, std::vector<Instruction>& out) {
  auto fail = [&](std::string msg) { return CompError{in.loc, std::move(msg)}; };
  const core::Vec pe = end_of(in.op);
  const P2 S{programmed_[a0_], programmed_[a1_]};
  const P2 P{pe[a0_], pe[a1_]};
  const P2 T{tool_[a0_], tool_[a1_]};
  const double r = radius_mm_;
  const double side_sign = side_ == CompSide::Left ? 1.0 : -1.0;  // left normal = tangent turned +90°
  const Arc* arc = std::get_if<Arc>(&in.op);
  const bool rapid = std::holds_alternative<Rapid>(in.op);
  if (arc && (arc->axis0 != a0_ || arc->axis1 != a1_))
    return fail("arc outside the plane cutter compensation was turned on in: program G40 before changing plane");

  // No motion in the plane (a plunge or lift): the tool stays at its offset point.
  if (!arc && P.x == S.x && P.y == S.y) {
    Instruction c = in;
    core::Vec e = pe;
    e[a0_] = T.x;
    e[a1_] = T.y;
    set_end(c.op, e);
    programmed_ = pe;
    tool_ = e;
    if (held_) {
      after_.push_back(std::move(c));
    } else {
      out.push_back(std::move(c));
    }
    return std::nullopt;
  }

  Held nh;
  nh.ins = in;
  nh.is_rapid = rapid;
  P2 t_start, t_end;   // programmed unit tangents at the start and end of the new move
  P2 start_off, end_off;
  Offset geo;
  if (!arc) {
    const P2 d = P - S;
    const P2 t = d * (1.0 / len(d));
    const P2 n = P2{-t.y, t.x} * side_sign;
    t_start = t_end = t;
    start_off = S + n * r;
    end_off = P + n * r;
    nh.dx = t.x;
    nh.dy = t.y;
    geo.p = start_off;
    geo.d = t;
  } else {
    const P2 C{arc->center0, arc->center1};
    const int dir = arc->turns >= 0 ? 1 : -1;
    const double rs = len(S - C), re = len(P - C);
    if (rs == 0 || re == 0) return fail("arc of zero radius under cutter compensation");
    const bool inside = (side_ == CompSide::Left) == (dir > 0);  // tool towards the centre
    if (inside && re <= r)
      return fail(fmt::format("tool radius {} mm is not less than the arc radius {} mm with cutter compensation",
                              radius_text(r), radius_text(re)));
    const double k = inside ? -1.0 : 1.0;
    t_start = arc_tangent(S, C, dir);
    t_end = arc_tangent(P, C, dir);
    start_off = C + (S - C) * ((rs + k * r) / rs);
    end_off = C + (P - C) * ((re + k * r) / re);
    nh.is_arc = true;
    nh.cx = C.x;
    nh.cy = C.y;
    nh.r = re + k * r;
    nh.dir = dir;
    geo.circle = true;
    geo.c = C;
    geo.r = nh.r;
  }

  std::vector<Instruction> emit;  // what this push releases, in order
  P2 new_start = T;
  bool cut_back = false;  // an inside corner moved the held move's end

  if (first_move_ && arc) {
    // Entry arc (LinuxCNC 2.9 convert_arc_comp1): it ends at the programmed end point moved by the
    // tool radius along the radius (towards the centre when the tool is inside the arc: end_off
    // above). A true arc from the tool to there needs a new centre: on the line from end_off
    // towards the programmed centre, as far from the tool as from end_off.
    //      tool T ·───────╮            A = end_off, B = new centre, M = midpoint of T and A:
    //                  ·   ╲ end_off   |AB| = (|TA| / 2) / cos(angle TAB)
    //        centre C ·─ B ─·
    if (len(P - T) <= r)
      return fail(fmt::format("cutter compensation entry arc is not longer than the tool radius ({} mm)",
                              radius_text(r)));
    const P2 C{arc->center0, arc->center1};
    const double half = len(T - end_off) / 2.0;
    const double ab = std::atan2(C.y - end_off.y, C.x - end_off.x);
    const double a_ang = std::atan2(T.y - end_off.y, T.x - end_off.x) - ab;
    if (std::abs(std::cos(a_ang)) < 0.0001)  // LinuxCNC TOLERANCE_EQUAL
      return fail(fmt::format("tool radius {} mm is not less than the entry arc radius with cutter compensation",
                              radius_text(r)));
    const double c_len = half / std::cos(a_ang);
    const P2 B{end_off.x + c_len * std::cos(ab), end_off.y + c_len * std::sin(ab)};
    auto& na = std::get<Arc>(nh.ins.op);
    na.center0 = B.x;
    na.center1 = B.y;
    nh.cx = B.x;
    nh.cy = B.y;
    nh.r = len(end_off - B);  // the corner after it still turns by the programmed tangent at P
  } else if (first_move_) {
    // Entry move (LinuxCNC convert_straight_comp1): from the tool to the end point offset
    // perpendicular to the entry move itself.
    if (len(P - T) <= r)
      return fail(fmt::format("cutter compensation entry move is not longer than the tool radius ({} mm)",
                              radius_text(r)));
    const P2 d = (P - T) * (1.0 / len(P - T));
    const P2 n = P2{-d.y, d.x} * side_sign;
    end_off = P + n * r;
    nh.dx = d.x;
    nh.dy = d.y;
    t_end = d;
  } else {
    const P2 t1{end_tx_, end_ty_};
    const double phi = std::atan2(cross(t1, t_start), dot(t1, t_start));  // turn at the corner, ccw positive
    const double s = phi * side_sign;  // > 0: turning towards the tool side, an inside corner
    if (s < -kCompTangentTolerance) {
      // Outside corner: an arc of the tool radius about the programmed corner (a straight
      // traverse for rapids, since there is no rapid arc).
      new_start = start_off;
      Instruction corner{in.loc, Rapid{}};
      core::Vec e = tool_;
      e[a0_] = start_off.x;
      e[a1_] = start_off.y;
      if (rapid) {
        corner.op = Rapid{e};
      } else {
        Arc a;
        a.end = e;
        a.center0 = S.x;
        a.center1 = S.y;
        a.axis0 = a0_;
        a.axis1 = a1_;
        a.normal = arc ? arc->normal : static_cast<std::uint8_t>(a0_ < 3 && a1_ < 3 ? 3 - a0_ - a1_ : 2);
        a.turns = side_ == CompSide::Left ? -1 : 1;
        a.feed_mm_s = feed_of(in.op);
        corner.op = a;
      }
      if (held_) emit.push_back(held_->ins);
      emit.push_back(std::move(corner));
    } else if (s > kCompTangentTolerance && held_) {
      // Inside corner: cut both offset moves back to where they meet.
      const Held& h = *held_;
      Offset hg;
      if (h.is_arc) {
        hg.circle = true;
        hg.c = P2{h.cx, h.cy};
        hg.r = h.r;
      } else {
        hg.p = T;
        hg.d = P2{h.dx, h.dy};
      }
      P2 cand[2];
      const int n = intersect(hg, geo, cand);
      if (n == 0)
        return fail(fmt::format("inside corner too tight for the tool (radius {} mm): the compensated moves do not "
                                "meet, the tool would gouge the part",
                                radius_text(r)));
      P2 X = cand[0];
      if (n == 2 && len(cand[1] - S) < len(cand[0] - S)) X = cand[1];
      // The held move must not reverse (LinuxCNC move_endpoint_and_flush) and neither may the new one.
      const P2 hs{h.start[a0_], h.start[a1_]};
      bool reversed = false;
      if (h.is_arc) {
        reversed = sweep(hs, X, P2{h.cx, h.cy}, h.dir) > h.sweep + 1e-9;
      } else {
        reversed = dot(X - hs, P2{h.dx, h.dy}) < 0;
      }
      if (!reversed) {
        if (arc) {
          reversed = sweep(X, end_off, geo.c, nh.dir) > sweep(start_off, end_off, geo.c, nh.dir) + 1e-9 &&
                     std::abs(arc->turns) <= 1;
        } else {
          reversed = dot(end_off - X, t_start) < 0;
        }
      }
      if (reversed)
        return fail(fmt::format("inside corner too tight for the tool (radius {} mm): the compensated path would "
                                "reverse, the tool would gouge the part",
                                radius_text(r)));
      new_start = X;
      cut_back = true;
      Instruction hi = h.ins;
      core::Vec he = end_of(hi.op);
      he[a0_] = X.x;
      he[a1_] = X.y;
      set_end(hi.op, he);
      emit.push_back(std::move(hi));
    } else if (held_) {
      emit.push_back(held_->ins);  // tangent: the new move starts where the tool is
    }
  }

  // Every check passed: commit.
  for (auto& i : after_) {
    if (!cut_back || !is_motion(i.op)) continue;
    // Plunges held after the moved corner go where the tool now is.
    core::Vec e = end_of(i.op);
    e[a0_] = new_start.x;
    e[a1_] = new_start.y;
    set_end(i.op, e);
  }
  // The corner (if any) goes after the plunges that followed the held move: insert order is
  // held move, plunges and other held instructions, then the corner arc.
  if (!emit.empty()) {
    const bool has_held = held_.has_value() && !first_move_;
    std::vector<Instruction> ordered;
    ordered.reserve(emit.size() + after_.size());
    std::size_t k = 0;
    if (has_held) ordered.push_back(std::move(emit[k++]));
    for (auto& i : after_) ordered.push_back(std::move(i));
    for (; k < emit.size(); ++k) ordered.push_back(std::move(emit[k]));
    for (auto& i : ordered) out.push_back(std::move(i));
  } else {
    for (auto& i : after_) out.push_back(std::move(i));
  }
  after_.clear();

  core::Vec te = pe;
  te[a0_] = end_off.x;
  te[a1_] = end_off.y;
  set_end(nh.ins.op, te);
  nh.start = tool_;
  nh.start[a0_] = new_start.x;
  nh.start[a1_] = new_start.y;
  if (nh.is_arc) {
    const int turns = std::abs(std::get<Arc>(nh.ins.op).turns);
    nh.sweep = sweep(new_start, end_off, P2{nh.cx, nh.cy}, nh.dir) + (turns > 1 ? (turns - 1) * kTwoPi : 0.0);
    if (P.x == S.x && P.y == S.y) nh.sweep += kTwoPi;  // a full circle
  }
  held_ = std::move(nh);
  first_move_ = false;
  programmed_ = pe;
  tool_ = te;
  end_tx_ = t_end.x;
  end_ty_ = t_end.y;
  return std::nullopt;
}

}  // namespace softmc::program::iso
