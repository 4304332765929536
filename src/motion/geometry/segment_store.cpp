// A compact, append-only store of Segments (see the header).
#include "motion/geometry/segment_store.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstring>
#include <type_traits>

namespace softmc::motion {

static_assert(std::is_trivially_copyable_v<Segment>, "pieces stored whole are copied as bytes");
// A field added to Segment or PolyCurve must be stored (fields) and compared (same_bits) too.
static_assert(sizeof(Segment) == 1528 && sizeof(PolyCurve) == 1160, "Segment changed: update segment_store.cpp");

namespace {

constexpr std::uint8_t kWhole = 0xFF;  // the kind byte of a piece stored whole
constexpr std::size_t kSlack = 8;      // readable bytes after a piece's last (Reader::diff)

// A Poly piece's last fields, the same in the plain and the compact form: which axes move and
// which carry the polynomial.
template <class IO, class P>
void axes_fields(IO& io, P& p) {
  io.item(p.gl8_ok);
  io.count(p.n_moving);
  for (std::size_t k = 0; k < p.n_moving && k < p.moving.size(); ++k) io.count(p.moving[k]);
  io.item(p.n_poly_axes);
  if (p.n_poly_axes != PolyCurve::kAxesUnknown)
    for (std::size_t k = 0; k < p.n_poly_axes && k < p.poly_axes.size(); ++k) io.item(p.poly_axes[k]);
}

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
      axes_fields(io, p);
      break;
    }
  }
}

static_assert(std::endian::native == std::endian::little, "a difference's low bytes are written first");

// What the compact form's reader predicts a value from (one compiled copy each, for writer and
// reader alike: the same bits whatever the compiler would make of two inlined copies). A piece's
// arc-length table is nearly linear in u: the next entry from the three before it (a quadratic's
// extrapolation), the first from the chord.
inline double table_guess(const PolyCurve& p, std::size_t k) {
  const auto& t = p.s_at;
  if (k == 1) return core::distance(p.bez.hctrl[0], p.bez.hctrl[p.degree]) / static_cast<double>(kArcTableIntervals);
  if (k == 2) return 2 * t[1];
  if (k == 3) return 2 * t[2] - t[1];
  if (k == 4) return 3 * (t[3] - t[2]) + t[1];
  if (k == 5) return 4 * (t[4] + t[2]) - 6 * t[3] - t[1];
  return 5 * (t[k - 1] - t[k - 4]) + 10 * (t[k - 3] - t[k - 2]) + t[k - 5];
}
// An inner control point as a line's: evenly along the chord.
inline double control_guess(const PolyCurve& p, std::size_t i, std::size_t a) {
  const double c0 = p.bez.hctrl[0][a], cn = p.bez.hctrl[p.degree][a];
  return c0 + (cn - c0) * static_cast<double>(i) / static_cast<double>(p.degree);
}
// Largest |dC_a/ds| as a line's: the axis's share of the chord.
inline double tangent_guess(const PolyCurve& p, std::size_t a) {
  return std::abs(p.bez.hctrl[p.degree][a] - p.bez.hctrl[0][a]) / p.s_at[kArcTableIntervals];
}

// The compact form of a polynomial Bézier piece (a smoothed run's cubics, G5, G5.1): its weights
// (all 1), its ends (its first and last control points), its length (the table's last entry) and
// its |C'|² (speed2_from_controls) are not kept but derived as it is read, and every other double
// after the first control point is kept as the bits in which it differs from a guess the reader
// makes from what it has read (io.diff: a count of the bytes up to the highest differing one, two
// to a byte, and those bytes): the last control point from the first, the inner ones from the chord,
// a table entry from the entries before (table_guess), a bound from the ends. About a third of the
// plain form.
template <class IO, class S>
void bezier_fields(IO& io, S& s) {
  auto& p = s.poly;
  io.item(p.degree);
  const std::size_t n = std::min<std::size_t>(p.degree, kMaxBezierDegree);
  io.vec(p.bez.hctrl[0]);
  for (std::size_t a = 0; a < io.axes && n > 0; ++a) io.diff(p.bez.hctrl[n][a], p.bez.hctrl[0][a]);
  for (std::size_t i = 1; i < n; ++i)
    for (std::size_t a = 0; a < io.axes; ++a) io.diff(p.bez.hctrl[i][a], control_guess(p, i, a));
  for (std::size_t k = 1; k <= kArcTableIntervals; ++k) io.diff(p.s_at[k], table_guess(p, k));
  for (std::size_t a = 0; a < io.axes; ++a) {
    const double c0 = p.bez.hctrl[0][a], cn = p.bez.hctrl[n][a];
    io.diff(p.box_lo[a], std::min(c0, cn));
    io.diff(p.box_hi[a], std::max(c0, cn));
    io.diff(p.max_abs_tangent[a], tangent_guess(p, a));
  }
  io.item(p.max_curvature);
  io.item(p.max_dcurvature);
  axes_fields(io, p);
  io.derive(s);
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
  // x as its difference from the guess g: a count of bytes (half a byte, two to a byte), the bytes.
  void diff(double x, double g) {
    const std::uint64_t r = std::bit_cast<std::uint64_t>(x) ^ std::bit_cast<std::uint64_t>(g);
    const auto nb = static_cast<unsigned>(r == 0 ? 0 : 8 - std::countl_zero(r) / 8);
    if (half == kNone) {
      half = out.size();
      out.push_back(static_cast<std::byte>(nb));
    } else {
      out[half] |= static_cast<std::byte>(nb << 4);
      half = kNone;
    }
    bytes(&r, nb);
  }
  void derive(const Segment&) {}
  static constexpr std::size_t kNone = ~std::size_t{0};
  std::size_t half = kNone;  // the count byte whose upper half is free
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
  void diff(double& x, double g) {
    unsigned nb;
    if (!half) {
      held = static_cast<unsigned>(*at++);
      nb = held & 15u;
      half = true;
    } else {
      nb = held >> 4;
      half = false;
    }
    // Eight bytes read and the ones past the count masked off (every piece is followed by at least
    // kSlack bytes: SegmentStore::push_back): one load instead of a copy of a variable length.
    std::uint64_t r;
    std::memcpy(&r, at, sizeof r);
    r &= nb == 8 ? ~std::uint64_t{0} : (std::uint64_t{1} << (8 * nb)) - 1;
    at += nb;
    x = std::bit_cast<double>(std::bit_cast<std::uint64_t>(g) ^ r);
  }
  // What the compact form leaves out, from what it kept.
  void derive(Segment& s) {
    auto& p = s.poly;
    const std::size_t n = std::min<std::size_t>(p.degree, kMaxBezierDegree);
    for (std::size_t i = 0; i <= n; ++i) p.bez.w[i] = 1;
    s.start = p.bez.hctrl[0];
    s.end = p.bez.hctrl[n];
    s.length = p.s_at[kArcTableIntervals];
    // Over the axes the piece moves (poly_axes), as finalize derived it: checked with the rest of
    // the piece as it is stored (a difference keeps it in the plain form).
    if (p.n_poly_axes != PolyCurve::kAxesUnknown) speed2_over_axes(p, p.poly_axes.data(), p.n_poly_axes, 1.0);
    else speed2_from_controls(p);
  }
  unsigned held = 0;  // the count byte read last
  bool half = false;  // its upper half not yet used
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
  std::vector<std::unique_ptr<std::byte[]>>().swap(chunks_);
  std::vector<std::uint64_t>().swap(offset_);
  std::vector<std::byte>().swap(scratch_);
  used_ = bytes_ = whole_ = compact_ = 0;
}

void SegmentStore::reserve(std::size_t segments) {
  offset_.reserve(segments);
}

namespace {
constexpr std::uint8_t kCompactBezier = 0xFE;  // the kind byte of a polynomial Bézier in the compact form
}  // namespace

// rt-safe: the piece encoded at p.
void SegmentStore::decode(const std::byte* p, Segment& out) {
  const auto kind = static_cast<std::uint8_t>(p[0]);
  if (kind == kWhole) {
    std::memcpy(static_cast<void*>(&out), p + 1, sizeof(Segment));
    return;
  }
  out = Segment{};
  Reader r{p + 2, static_cast<std::size_t>(p[1])};
  if (kind == kCompactBezier) {
    out.kind = SegmentKind::Poly;
    bezier_fields(r, out);
    return;
  }
  out.kind = static_cast<SegmentKind>(kind);
  fields(r, out);
}

void SegmentStore::push_back(const Segment& s) {
  auto& buf = scratch_;
  Segment back;
  const auto kind = static_cast<std::uint8_t>(s.kind);
  Scan scan;
  const bool known = s.kind == SegmentKind::Line || s.kind == SegmentKind::Arc || s.kind == SegmentKind::Poly;
  if (known) fields(scan, s);
  bool done = false;
  if (known && scan.fits && s.kind == SegmentKind::Poly && s.poly.basis == PolyBasis::Bezier && s.poly.has_speed2) {
    buf.assign({static_cast<std::byte>(kCompactBezier), static_cast<std::byte>(scan.axes)});
    Writer w{buf, scan.axes};
    bezier_fields(w, s);
    const std::size_t size = buf.size();
    buf.resize(size + kSlack);
    decode(buf.data(), back);
    buf.resize(size);
    done = same_bits(back, s);
    compact_ += done;
  }
  if (!done && known && scan.fits && kind != kWhole && kind != kCompactBezier) {
    buf.assign({static_cast<std::byte>(kind), static_cast<std::byte>(scan.axes)});
    Writer w{buf, scan.axes};
    fields(w, s);
    decode(buf.data(), back);
    done = same_bits(back, s);
  }
  if (!done) {  // something the kind does not use was set: kept whole
    const auto* b = reinterpret_cast<const std::byte*>(&s);
    buf.assign(1, static_cast<std::byte>(kWhole));
    buf.insert(buf.end(), b, b + sizeof(Segment));
    ++whole_;
  }
  // Appended to the last chunk, or a new one: never moved, never more than a chunk set aside.
  if (chunks_.empty() || used_ + buf.size() + kSlack > kChunk) {
    chunks_.push_back(std::make_unique<std::byte[]>(kChunk));  // zeroed: the slack reads no garbage
    used_ = 0;
  }
  offset_.push_back(((chunks_.size() - 1) << kChunkBits) | used_);
  std::memcpy(chunks_.back().get() + used_, buf.data(), buf.size());
  used_ += buf.size();
  bytes_ += buf.size();
}

// rt-safe
void SegmentStore::get(std::size_t i, Segment& out) const {
  const std::uint64_t at = offset_[i];
  decode(chunks_[at >> kChunkBits].get() + (at & (kChunk - 1)), out);
}

}  // namespace softmc::motion
