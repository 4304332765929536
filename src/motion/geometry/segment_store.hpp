// A compact, append-only store of Segments: the pieces the Channel builds at load (smoothed runs,
// arcs in pieces, curves), about a third of a Segment's 1.5 kB each, read back bit for bit.
//
//   push_back(seg) ──► [kind | axes | the fields its kind uses, its axes only] ──► get(i, out)
//                      (a Segment whose copy back differs in any bit is kept whole)
//
// A Segment holds every kind's fields, each point for all nine axes: a cubic piece of a smoothed
// three-axis run uses about a third of it. The store keeps a piece's kind, the number of axes up
// to its last non-zero coordinate, and the fields of its kind (a Bézier's control points up to its
// degree, its arc-length table, bounds and samples); get() writes them over a default Segment.
// Every piece is copied back once when stored and compared with the original bit for bit (every
// field, every axis): where anything differs it is stored whole, so get() always returns exactly
// what was stored.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "motion/geometry/segment.hpp"

namespace softmc::motion {

class SegmentStore {
 public:
  // Not rt: drops everything and frees the memory.
  void clear();
  // Not rt: room for `segments` pieces of about `bytes_each` bytes.
  void reserve(std::size_t segments, std::size_t bytes_each);
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
  // Bytes held for the pieces (not counting the per-piece offsets), and the pieces kept whole.
  std::size_t bytes() const { return data_.size(); }
  std::size_t whole() const { return whole_; }

 private:
  std::vector<std::byte> data_;
  std::vector<std::uint64_t> offset_;  // where each piece starts in data_
  std::size_t whole_ = 0;
};

// Every field of a and b the same, bit for bit (doubles compared as their bits, every axis, the
// Bézier or Newton data by the basis, arrays past their counts too).
bool same_bits(const Segment& a, const Segment& b);

}  // namespace softmc::motion
