// Blend-arc geometry in axis space.
#include "motion/planner/block.hpp"

#include <algorithm>
#include <cmath>

namespace softmc::motion {

BlendArc make_blend_arc(const Vec& p1, const Vec& t1, const Vec& t2, double r, double sweep) {
  // n: unit normal in the plane of t1, t2, pointing towards t2 (towards the arc's centre).
  Vec n = t2 - t1 * core::dot(t1, t2);
  n = n * (1.0 / core::norm(n));
  BlendArc b;
  b.radius = r;
  b.sweep = sweep;
  b.centre = p1 + n * r;
  b.start = p1;
  b.u = n * -1.0;  // centre → p1
  b.w = t1;        // direction of motion at φ = 0
  return b;
}

// rt-safe
Vec BlendArc::point(double s) const {
  // From the start point, with cos φ − 1 = −2 sin²(φ/2): blends of huge radius (nearly straight
  // corners) keep full precision instead of cancelling against the far-away centre.
  const double ph = std::clamp(s / radius, 0.0, sweep);
  const double h = std::sin(ph / 2);
  return start + (u * (-2 * h * h) + w * std::sin(ph)) * radius;
}

// rt-safe
Vec BlendArc::tangent(double s) const {
  const double ph = std::clamp(s / radius, 0.0, sweep);
  return u * -std::sin(ph) + w * std::cos(ph);
}

// rt-safe
Vec BlendArc::curvature(double s) const {
  const double ph = std::clamp(s / radius, 0.0, sweep);
  return (u * std::cos(ph) + w * std::sin(ph)) * (-1.0 / radius);
}

// rt-safe. The same three, from sin and cos of φ/2: sin φ = 2·sin(φ/2)·cos(φ/2), cos φ = 1 − 2·sin²(φ/2).
CurveFrame BlendArc::frame(double s) const {
  const double ph = std::clamp(s / radius, 0.0, sweep);
  const double h = std::sin(ph / 2), c = std::cos(ph / 2);
  const double sn = 2 * h * c, cs = 1 - 2 * h * h;
  const double pu = -2 * h * h * radius, pw = sn * radius, k = -1.0 / radius;
  CurveFrame f;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {  // one pass over the axes, no temporaries
    f.point[i] = start[i] + u[i] * pu + w[i] * pw;
    f.tangent[i] = w[i] * cs - u[i] * sn;
    f.curvature[i] = (u[i] * cs + w[i] * sn) * k;
  }
  return f;
}

}  // namespace softmc::motion
