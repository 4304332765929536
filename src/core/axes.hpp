// Axis identities and the fixed-size axis vector every layer passes around (mm for linear axes).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

namespace softmc::core {

// RS274 axis letters in canonical order; SPC uses X Y Z U.
inline constexpr std::size_t kMaxAxes = 9;
enum class Axis : std::uint8_t { X, Y, Z, A, B, C, U, V, W };
inline constexpr std::array<char, kMaxAxes> kAxisLetters{'X', 'Y', 'Z', 'A', 'B', 'C', 'U', 'V', 'W'};

constexpr std::size_t index(Axis a) { return static_cast<std::size_t>(a); }
constexpr char letter(std::size_t i) { return kAxisLetters[i]; }

// Letter (either case) to axis index, or nothing.
constexpr std::optional<std::size_t> axis_from_letter(char c) {
  if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  for (std::size_t i = 0; i < kMaxAxes; ++i)
    if (kAxisLetters[i] == c) return i;
  return std::nullopt;
}

// A point or direction in axis space. Plain aggregate: copyable, no allocation, rt-safe.
struct Vec {
  std::array<double, kMaxAxes> v{};

  constexpr double& operator[](std::size_t i) { return v[i]; }
  constexpr double operator[](std::size_t i) const { return v[i]; }

  friend constexpr Vec operator+(Vec a, const Vec& b) {
    for (std::size_t i = 0; i < kMaxAxes; ++i) a.v[i] += b.v[i];
    return a;
  }
  friend constexpr Vec operator-(Vec a, const Vec& b) {
    for (std::size_t i = 0; i < kMaxAxes; ++i) a.v[i] -= b.v[i];
    return a;
  }
  friend constexpr Vec operator*(Vec a, double k) {
    for (auto& x : a.v) x *= k;
    return a;
  }
  friend constexpr Vec operator*(double k, Vec a) { return a * k; }
  friend constexpr bool operator==(const Vec&, const Vec&) = default;
};

constexpr double dot(const Vec& a, const Vec& b) {
  double s = 0;
  for (std::size_t i = 0; i < kMaxAxes; ++i) s += a.v[i] * b.v[i];
  return s;
}
inline double norm(const Vec& a) { return std::sqrt(dot(a, a)); }
inline double distance(const Vec& a, const Vec& b) { return norm(a - b); }

// Bit set of axes (bit i = axis i).
using AxisMask = std::uint16_t;
constexpr AxisMask axis_bit(std::size_t i) { return static_cast<AxisMask>(1u << i); }

}  // namespace softmc::core
