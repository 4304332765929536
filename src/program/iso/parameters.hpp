// Parameters of RS274/NGC as LinuxCNC has them: numbered #1…#5602, named locals #<x> and globals #<_x>.
//
// #1…#30 and named locals live in the frame of the current subroutine call (a call gets fresh
// ones: its arguments in #1…#n); every other numbered parameter and every global is shared. Values
// of lengths are in machine units (mm), as LinuxCNC keeps them in its "user" units, but for the
// current position (#5420…, #<_x>…), which is in the program's units as LinuxCNC gives it.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

namespace softmc::program::iso {

inline constexpr int kMaxParameter = 5602;  // LinuxCNC RS274NGC_MAX_PARAMETERS - 1
inline constexpr int kLocalParameters = 30; // #1…#30
inline constexpr int kM66Result = 5399;

// Standard numbered parameters (LinuxCNC "Numbered Parameters"); axis i adds i (X=0 … W=8).
inline constexpr int kG28Home = 5161;
inline constexpr int kG30Home = 5181;
inline constexpr int kG92Enabled = 5210;
inline constexpr int kG92Offset = 5211;
inline constexpr int kCoordSystem = 5220;         // 1 = G54 … 9 = G59.3
inline constexpr int kCoordSystemBase = 5221;     // G54 X; G55 X is 5241, … (20 apart); +9 = R
inline constexpr int kToolNumber = 5400;
inline constexpr int kToolOffset = 5401;          // 5401…5409
inline constexpr int kToolDiameter = 5410;
inline constexpr int kCurrentPosition = 5420;     // 5420…5428, program coordinates
inline constexpr int kToolLast = 5413;            // the last of the loaded tool's read-only parameters
// #5599: DEBUG messages are shown while it is not 0 (LinuxCNC; 1 at start).
inline constexpr int kDebugOutput = 5599;

// LinuxCNC's predefined named parameters (read-only: #<_x>, #<_motion_mode>, …; docs/gcode.md), in
// the order of kPredefinedNames. The parser sets them from its state before a line that may read one.
enum class Predefined : std::uint8_t {
  X, Y, Z, A, B, C, U, V, W,                          // current position, program coordinates and units
  AbsX, AbsY, AbsZ, AbsA, AbsB, AbsC, AbsU, AbsV, AbsW,  // machine coordinates, program units
  MotionMode, Plane, Ccomp, Metric, Imperial, Absolute, Incremental, InverseTime, UnitsPerMinute, UnitsPerRev,
  CoordSystem, ToolOffset, RetractRPlane, RetractOldZ, SpindleRpmMode, SpindleCssMode, IjkAbsoluteMode,
  LatheDiameterMode, LatheRadiusMode, SpindleOn, SpindleCw, Mist, Flood, SpeedOverride, FeedOverride, Feed, Rpm,
  CurrentTool, SelectedTool, CallLevel, RemapLevel, Line, Task, Count
};
// The name of each (without '#<' '>'), as LinuxCNC spells it.
std::string_view predefined_name(Predefined p);
// The predefined parameter a (lower-case) name is, if any.
std::optional<Predefined> predefined_of(std::string_view name);

constexpr int coord_param(int system, std::size_t axis) { return kCoordSystemBase + 20 * (system - 1) + static_cast<int>(axis); }
constexpr int rotation_param(int system) { return kCoordSystemBase + 20 * (system - 1) + 9; }

class Parameters {
 public:
  Parameters();

  // Numbered read/write with LinuxCNC's range check; the message says why a read or write fails.
  std::optional<std::string> read(long long n, double& out) const;
  std::optional<std::string> write(long long n, double v);
  // Direct access for the interpreter's own bookkeeping (n in range).
  double get(int n) const { return n <= kLocalParameters ? numbered_locals()[n] : numbered_[n]; }
  void set(int n, double v) {
    if (n <= kLocalParameters) numbered_locals()[n] = v;
    else numbered_[n] = v;
  }

  // Named parameters; `name` is lower case without spaces or brackets. Names starting with '_'
  // are global, others local to the current call.
  std::optional<std::string> read_named(std::string_view name, double& out) const;
  // Refused (the message says why) for a predefined name: those are read-only.
  std::optional<std::string> write_named(std::string_view name, double v);
  // The interpreter's own: a predefined parameter's value.
  void set_predefined(Predefined p, double v) { predefined_[static_cast<std::size_t>(p)] = v; }
  bool exists(std::string_view name) const;

  // Subroutine calls: a fresh frame with args in #1…#n, dropped on return. An M98 subprogram's
  // frame (`numbered_shared`) has named locals of its own but the caller's #1…#30 (LinuxCNC).
  void push_frame(const double* args, std::size_t n, bool numbered_shared = false);
  void pop_frame();
  std::size_t depth() const { return frames_.size() - 1; }

  // After M66 the result #5399 is only known at run time: reading it is refused from then on.
  void set_runtime_only(int n) { runtime_only_ = n; }

 private:
  struct Frame {
    std::array<double, kLocalParameters + 1> local{};
    std::vector<std::pair<std::string, double>> named;
    std::size_t numbered_owner = 0;  // the frame whose #1…#30 this one uses (itself but in M98 frames)
  };
  const std::array<double, kLocalParameters + 1>& numbered_locals() const { return frames_[frames_.back().numbered_owner].local; }
  std::array<double, kLocalParameters + 1>& numbered_locals() { return frames_[frames_.back().numbered_owner].local; }
  std::vector<double> numbered_;
  std::vector<Frame> frames_;
  std::unordered_map<std::string, double> globals_;
  std::array<double, static_cast<std::size_t>(Predefined::Count)> predefined_{};
  int runtime_only_ = 0;
};

}  // namespace softmc::program::iso
