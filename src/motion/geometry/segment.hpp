// Geometric path segments parameterised by arc length s in [0, length]: lines, arcs/helices and
// parametric polynomial curves (Bézier/NURBS pieces, splines, Newton polynomials; poly_curve.hpp).
//
//        axis1
//          ^        end
//          |      .-'
//          |   .-'   <- arc: centre c, radius r, start angle th0, signed sweep
//          |  /          (positive = from axis0 towards axis1)
//          | c ----> axis0
//
// Axes outside the arc's plane move linearly with s (a helix when the normal axis moves).
// Every query is rt-safe: no allocation, bounded work. A Segment is a fixed-size value
// (sizeof ≈ 1.3 KB, asserted in segment.cpp) copied into the planner's queues.
#pragma once

#include <cstdint>
#include <utility>

#include "core/axes.hpp"
#include "motion/geometry/poly_curve.hpp"

namespace softmc::motion {

using core::Vec;

enum class SegmentKind : std::uint8_t { Line, Arc, Poly };

// Everything the interpolator needs at one arc length, from one s → u inversion.
struct CurveFrame {
  Vec point, tangent, curvature;
};

struct Segment {
  SegmentKind kind = SegmentKind::Line;
  Vec start;        // position at s = 0
  Vec end;          // position at s = length
  double length = 0;  // mm (path length in axis space)

  // Line: unit direction (start → end); zero for a zero-length line.
  Vec dir;

  // Arc: plane axes, centre, radius, start angle and signed sweep (radians); the linear part of
  // the motion (axes outside the plane) is `end - start` restricted to those axes.
  // The radius runs linearly with the angle from `radius` at the start to radius + dradius at the
  // end: a programmed end point off the circle by the interpreter's allowance is reached exactly (a
  // slight spiral, as LinuxCNC does), never by a jump at the arc's end. s is the arc length of the
  // spiral too (|tangent| = 1 to rounding): the angle at s is found from the spiral's closed-form
  // length (a Newton step or two; a circle's angle is linear in s).
  std::uint8_t axis0 = 0, axis1 = 1;
  double c0 = 0, c1 = 0, radius = 0, theta0 = 0, sweep = 0, dradius = 0;
  double plane_rate = 0;  // in-plane length per unit of s: 1 in the plane, less on a helix
  Vec linear;  // per unit of s: d(pos)/ds for the axes outside the plane

  // Poly: the curve C(u) with its arc-length table (constructors in bezier.hpp, cubic_spline.hpp,
  // newton_polynomial.hpp, nurbs.hpp).
  PolyCurve poly;

  // Path position at arc length s (clamped to [0, length]).
  Vec point(double s) const;
  // Unit tangent at s.
  Vec tangent(double s) const;
  // Curvature vector d(tangent)/ds at s (zero for lines); |k| = 1/R for a planar arc.
  Vec curvature(double s) const;
  // Distance of p from this segment's curve (for accuracy reports; not rt-critical). A caller that
  // only needs to know whether it exceeds `enough` (a largest deviation so far) gets some distance
  // to a point of the curve at or below `enough` as soon as one is found.
  double distance_to(const Vec& p, double enough = 0) const;
  // Axis-aligned bounding box of the whole curve (arcs: including their extreme points). rt-safe.
  void bounds(Vec& lo, Vec& hi) const;

  // Point, unit tangent and curvature at s together (one s → u inversion for Poly). rt-safe.
  CurveFrame frame(double s) const;
  // Largest |tangent_i| over the segment per axis, and the largest curvature |κ| (1/mm): what the
  // planner needs for per-axis speed and centripetal limits. Exact for lines and arcs, densely
  // sampled for Poly. rt-safe.
  Vec max_abs_tangent() const;
  // Arcs: the largest |share| of the centripetal direction (towards the centre) per in-plane axis
  // over the sweep (1 where the sweep passes the axis's direction): the planner's sweep bound.
  Vec max_abs_normal() const;
  double max_curvature() const;
  // Arcs: a range of angles holding the in-plane tangent's direction over the whole arc. rt-safe.
  std::pair<double, double> tangent_angles() const;

  // Arcs: bounds over the whole arc for the planner's limits. inplane = |in-plane part of
  // tangent(s)| (constant), kappa ≥ |curvature(s)|; tangent and curvature are orthogonal (s is the
  // arc length), so |a_t·tangent + w·curvature| = √(a_t² + w²·|curvature|²).
  struct ArcBounds {
    double inplane = 0, kappa = 0;
    double k_speed = 0;  // bound of |d³p/ds³| in the plane (plane_rate³/r² on a circle)
  };
  ArcBounds arc_bounds() const;
};

// Distance of p from the line start + dir·t, t ∈ [0, length] (dir a unit vector): Segment::distance_to
// of a line, also for holders of a line's ends that do not keep a whole Segment (report::ProgrammedMove).
// rt-safe.
double line_distance(const Vec& start, const Vec& dir, double length, const Vec& p);
// A line's unit direction from its ends and length (core::distance of them), as set_line sets it.
Vec line_direction(const Vec& start, const Vec& end, double length);
// The box of the line from a to b (Segment::bounds of a line, and of an arc before its in-plane
// extremes; also report::ProgrammedPath's lines, kept as their ends). rt-safe.
void line_bounds(const Vec& a, const Vec& b, Vec& lo, Vec& hi);

Segment make_line(const Vec& start, const Vec& end);
// The same line written into `s` in place, every field make_line sets; `s.poly` is left as it is (a
// line never reads it). For the Channel, which would otherwise build and copy a whole Segment
// (1.3 kB, most of it the Poly tables) for every programmed line. rt-safe.
void set_line(Segment& s, const Vec& start, const Vec& end);

// Arc from `start` about centre (c0, c1) in plane (axis0, axis1) to `end`, sweeping `turns`
// revolutions as the IR defines them (sign = direction). The radius is taken at the start point;
// the end point's angle sets the sweep; out-of-plane axes move linearly.
Segment make_arc(const Vec& start, const Vec& end, std::uint8_t axis0, std::uint8_t axis1, double c0, double c1,
                 int turns);

// The part s ∈ [s0, s1] of a line or arc/helix (0 ≤ s0 < s1 ≤ length), exact: an arc's radius runs
// linearly with its angle, so the piece is the same curve with its own start angle, sweep and
// radius (the planner trims arcs where it blends their ends). Poly curves are returned whole.
// rt-safe.
Segment trimmed(const Segment& g, double s0, double s1);

}  // namespace softmc::motion
