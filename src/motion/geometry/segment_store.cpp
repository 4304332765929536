// A compact, append-only store of Segments (see the header).
#include "motion/geometry/segment_store.hpp"

#include <bit>
#include <cassert>
#include <cstring>
#include <type_traits>

namespace softmc::motion {

static_assert(std::is_trivially_copyable_v<Segment>, "pieces stored whole are copied as bytes");
// A field added to Segment or PolyCurve must be stored (fields) and compared (same_bits) too.
static_assert(sizeof(Segment) == 1528 && sizeof(PolyCurve) == 1160, "Segment changed: update segment_store.cpp");

namespace {

constexpr std::uint8_t kWhole = 0xFF;  // the kind byte of a piece stored whole

// The fields a piece of its kind uses, in the order they are stored; a count before what it counts.
// io.vec stores a point's first io.axes coordinates, io.item any other value as its bytes, io.count
// a count below 256 as one byte. One list for storing, reading back and scanning.
template <class IO, class S>
void fields(IO& io, S& s) {
  io.vec(s.start);
  io.vec(s.end);
  io.item(s.length);
  switch (s.kind) {
    case SegmentKind::Line: io.vec(s.dir); break;
    case SegmentKind::Arc:
      io.item(s.axis0);
      io.item(s.axis1);
      io.item(s.c0);
      io.item(s.c1);
      io.item(s.radius);
      io.item(s.theta0);
      io.item(s.sweep);
      io.item(s.dradius);
      io.item(s.plane_rate);
      io.vec(s.linear);
      break;
    case SegmentKind::Poly: {
      auto& p = s.poly;
      io.item(p.basis);
      io.item(p.degree);
      const std::size_t nd = std::size_t{p.degree} + 1;
      if (p.basis == PolyBasis::Bezier) {
        for (std::size_t i = 0; i < nd && i < p.bez.hctrl.size(); ++i) {
          io.vec(p.bez.hctrl[i]);
          io.item(p.bez.w[i]);
        }
      } else {
        io.newton(p);
        for (std::size_t i = 0; i < nd && i < p.newton.coef.size(); ++i) {
          io.item(p.newton.node_x[i]);
          io.item(p.newton.coef[i]);
        }
        io.item(p.newton.x_begin);
        io.item(p.newton.x_end);
        io.vec(p.newton.base);
        io.item(p.newton.x_axis);
        io.item(p.newton.y_axis);
      }
      io.item(p.s_at);
      io.vec(p.box_lo);
      io.vec(p.box_hi);
      io.vec(p.max_abs_tangent);
      io.item(p.max_curvature);
      io.item(p.max_dcurvature);
      io.item(p.has_speed2);
      io.item(p.speed2_degree);
      if (p.has_speed2)
        for (std::size_t i = 0; i <= p.speed2_degree && i < p.speed2.size(); ++i) io.item(p.speed2[i]);
      io.item(p.gl8_ok);
      io.count(p.n_moving);
      for (std::size_t k = 0; k < p.n_moving && k < p.moving.size(); ++k) io.count(p.moving[k]);
      io.item(p.n_poly_axes);
      if (p.n_poly_axes != PolyCurve::kAxesUnknown)
        for (std::size_t k = 0; k < p.n_poly_axes && k < p.poly_axes.size(); ++k) io.item(p.poly_axes[k]);
      break;
    }
  }
}

// The axes a piece needs: up to its last coordinate whose bits are not all zero; and whether its
// counts fit a byte.
struct Scan {
  std::size_t axes = 0;
  bool fits = true;
  void vec(const Vec& v) {
    for (std::size_t i = 0; i < core::kMaxAxes; ++i)
      if (std::bit_cast<std::uint64_t>(v[i]) != 0) axes = std::max(axes, i + 1);
  }
  template <class T>
  void item(const T&) {}
  void count(std::size_t n) { fits = fits && n < 256; }
  void newton(const PolyCurve&) {}
};

struct Writer {
  std::vector<std::byte>& out;
  std::size_t axes;
  void bytes(const void* p, std::size_t n) {
    const auto* b = static_cast<const std::byte*>(p);
    out.insert(out.end(), b, b + n);
  }
  void vec(const Vec& v) { bytes(v.v.data(), axes * sizeof(double)); }
  template <class T>
  void item(const T& x) {
    bytes(&x, sizeof x);
  }
  void count(std::size_t n) { out.push_back(static_cast<std::byte>(n)); }
  void newton(const PolyCurve&) {}
};

struct Reader {  // rt-safe
  const std::byte* at;
  std::size_t axes;
  void bytes(void* p, std::size_t n) {
    std::memcpy(p, at, n);
    at += n;
  }
  void vec(Vec& v) { bytes(v.v.data(), axes * sizeof(double)); }
  template <class T>
  void item(T& x) {
    bytes(&x, sizeof x);
  }
  void count(std::size_t& n) { n = static_cast<std::size_t>(*at++); }
  // A default Segment's union holds the Bézier data: a Newton graph's becomes the one in use.
  void newton(PolyCurve& p) { p.newton = PolyCurve::NewtonData{}; }
};

bool same(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
bool same(const Vec& a, const Vec& b) {
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (!same(a[i], b[i])) return false;
  return true;
}
template <class T>
  requires(std::is_integral_v<T> || std::is_enum_v<T>)
bool same(const T& a, const T& b) {
  // By their bytes, as the doubles: a bool or enum holding a value outside its type (a flipped byte)
  // is a difference, not undefined behaviour (UBSan on SegmentStore.SameBitsSeesEveryByteOfEveryField).
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}
template <class T, std::size_t N>
bool same(const std::array<T, N>& a, const std::array<T, N>& b) {
  for (std::size_t i = 0; i < N; ++i)
    if (!same(a[i], b[i])) return false;
  return true;
}

}  // namespace

bool same_bits(const Segment& a, const Segment& b) {
  if (!(same(a.kind, b.kind) && same(a.start, b.start) && same(a.end, b.end) && same(a.length, b.length) &&
        same(a.dir, b.dir) && same(a.axis0, b.axis0) && same(a.axis1, b.axis1) && same(a.c0, b.c0) &&
        same(a.c1, b.c1) && same(a.radius, b.radius) && same(a.theta0, b.theta0) && same(a.sweep, b.sweep) &&
        same(a.dradius, b.dradius) && same(a.plane_rate, b.plane_rate) && same(a.linear, b.linear)))
    return false;
  const PolyCurve &p = a.poly, &q = b.poly;
  if (!(same(p.basis, q.basis) && same(p.degree, q.degree))) return false;
  if (p.basis == PolyBasis::Bezier) {
    if (!(same(p.bez.hctrl, q.bez.hctrl) && same(p.bez.w, q.bez.w))) return false;
  } else {
    const auto &m = p.newton, &n = q.newton;
    if (!(same(m.node_x, n.node_x) && same(m.coef, n.coef) && same(m.x_begin, n.x_begin) && same(m.x_end, n.x_end) &&
          same(m.base, n.base) && same(m.x_axis, n.x_axis) && same(m.y_axis, n.y_axis)))
      return false;
  }
  return same(p.s_at, q.s_at) && same(p.box_lo, q.box_lo) && same(p.box_hi, q.box_hi) &&
         same(p.max_abs_tangent, q.max_abs_tangent) && same(p.max_curvature, q.max_curvature) &&
         same(p.max_dcurvature, q.max_dcurvature) && same(p.speed2, q.speed2) && same(p.speed2_degree, q.speed2_degree) &&
         same(p.has_speed2, q.has_speed2) && same(p.gl8_ok, q.gl8_ok) && same(p.moving, q.moving) &&
         same(p.n_moving, q.n_moving) && same(p.poly_axes, q.poly_axes) && same(p.n_poly_axes, q.n_poly_axes);
}

void SegmentStore::clear() {
  std::vector<std::byte>().swap(data_);
  std::vector<std::uint64_t>().swap(offset_);
  whole_ = 0;
}

void SegmentStore::reserve(std::size_t segments, std::size_t bytes_each) {
  offset_.reserve(segments);
  data_.reserve(segments * bytes_each);
}

void SegmentStore::push_back(const Segment& s) {
  const std::size_t at = data_.size();
  offset_.push_back(at);
  const auto kind = static_cast<std::uint8_t>(s.kind);
  Scan scan;
  const bool known = s.kind == SegmentKind::Line || s.kind == SegmentKind::Arc || s.kind == SegmentKind::Poly;
  if (known) fields(scan, s);
  if (known && scan.fits && kind != kWhole) {
    data_.push_back(static_cast<std::byte>(kind));
    data_.push_back(static_cast<std::byte>(scan.axes));
    Writer w{data_, scan.axes};
    fields(w, s);
    Segment back;
    get(offset_.size() - 1, back);
    if (same_bits(back, s)) return;
    data_.resize(at);  // something the kind does not use was set: kept whole
  }
  data_.push_back(static_cast<std::byte>(kWhole));
  const auto* b = reinterpret_cast<const std::byte*>(&s);
  data_.insert(data_.end(), b, b + sizeof(Segment));
  ++whole_;
}

// rt-safe
void SegmentStore::get(std::size_t i, Segment& out) const {
  const std::byte* p = data_.data() + offset_[i];
  const auto kind = static_cast<std::uint8_t>(p[0]);
  if (kind == kWhole) {
    std::memcpy(static_cast<void*>(&out), p + 1, sizeof(Segment));
    return;
  }
  out = Segment{};
  out.kind = static_cast<SegmentKind>(kind);
  Reader r{p + 2, static_cast<std::size_t>(p[1])};
  fields(r, out);
}

}  // namespace softmc::motion
