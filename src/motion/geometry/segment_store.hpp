// A compact, append-only store of Segments: the pieces the Channel builds at load (smoothed runs,
// arcs in pieces, curves), read back bit for bit.
//
//   push_back(seg) ──► [kind | axes | the fields its kind uses, its axes only] ──► get(i, out)
//                      (a Segment whose copy back differs in any bit is kept whole)
//
// A Segment holds every kind's fields, each point for all nine axes: a cubic piece of a smoothed
// three-axis run uses about a third of it. The store keeps a piece's kind, the number of axes up
// to its last non-zero coordinate, and the fields of its kind (a Bézier's control points up to its
// degree, its arc-length table, bounds and samples); get() writes them over a default Segment.
// A polynomial Bézier (a smoothed run's cubic: most of a CAM program's pieces) goes further: what
// follows from its control points (weights, ends, length, |C'|²) is derived when it is read, and its
// other doubles are kept as the bits in which they differ from a guess made from what was read
// before (its arc-length table, nearly linear, from the entries before it): about 160 bytes for a
// cubic on three axes instead of 590, about 0.1 µs more to read. Every piece is copied back once
// when stored and compared with the original bit for bit (every field, every axis): where the
// compact form differs the plain one is tried, and where that differs too it is stored whole, so
// get() always returns exactly what was stored.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "motion/geometry/segment.hpp"

namespace softmc::motion {

class SegmentStore {
 public:
  // Not rt: drops everything and frees the memory.
  void clear();
  // Not rt: room for `segments` pieces (their offsets; the pieces' bytes come a chunk at a time).
  void reserve(std::size_t segments);
  // Not rt: appends a copy of s.
  void push_back(const Segment& s);
  std::size_t size() const { return offset_.size(); }
  bool empty() const { return offset_.empty(); }
  // rt-safe: piece i, exactly as it was stored, written over `out` (every field).
  void get(std::size_t i, Segment& out) const;
  Segment operator[](std::size_t i) const {
    Segment s;
    get(i, s);
    return s;
  }
  // Bytes held for the pieces (not counting the per-piece offsets), the pieces kept whole, and the
  // polynomial Béziers kept in the compact form.
  std::size_t bytes() const { return bytes_; }
  std::size_t whole() const { return whole_; }
  std::size_t compact() const { return compact_; }

 private:
  // The pieces' bytes live in chunks of 1 MiB, filled in turn and never moved: a store grows without
  // a copy of itself (a vector grown by doubling holds both for a moment) and without an estimate
  // of its size set aside beforehand. A piece's offset is its chunk and its place in it.
  static constexpr std::size_t kChunkBits = 20;
  static constexpr std::size_t kChunk = std::size_t{1} << kChunkBits;
  static void decode(const std::byte* p, Segment& out);  // rt-safe
  std::vector<std::unique_ptr<std::byte[]>> chunks_;
  std::vector<std::uint64_t> offset_;  // (chunk << kChunkBits) | where the piece starts in it
  std::vector<std::byte> scratch_;     // a piece being encoded
  std::size_t used_ = 0;               // bytes used of the last chunk
  std::size_t bytes_ = 0;
  std::size_t whole_ = 0;
  std::size_t compact_ = 0;
};

// Every field of a and b the same, bit for bit (doubles compared as their bits, every axis, the
// Bézier or Newton data by the basis, arrays past their counts too).
bool same_bits(const Segment& a, const Segment& b);

}  // namespace softmc::motion
