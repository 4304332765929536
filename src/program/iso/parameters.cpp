// Parameters of RS274/NGC as LinuxCNC has them: numbered #1…#5602, named locals #<x> and globals #<_x>.
#include "program/iso/parameters.hpp"

#include <iterator>

#include <fmt/format.h>

namespace softmc::program::iso {

Parameters::Parameters() : numbered_(kMaxParameter + 1, 0.0), frames_(1) {
  numbered_[kDebugOutput] = 1.0;  // DEBUG output on (LinuxCNC's start value)
}

std::optional<std::string> Parameters::read(long long n, double& out) const {
  if (n < 1 || n > kMaxParameter) return fmt::format("parameter #{} does not exist (#1 … #{})", n, kMaxParameter);
  if (n == runtime_only_)
    return fmt::format("branching on M66 results is not supported: #{} is only known when the program runs", n);
  out = get(static_cast<int>(n));
  return std::nullopt;
}

std::optional<std::string> Parameters::write(long long n, double v) {
  if (n < 1 || n > kMaxParameter) return fmt::format("parameter #{} does not exist (#1 … #{})", n, kMaxParameter);
  // LinuxCNC's read-only ones: the tool (#5400…#5413) and the current position (#5420…#5428).
  if ((n >= kToolNumber && n <= kToolLast) || (n >= kCurrentPosition && n <= kCurrentPosition + 8))
    return fmt::format("parameter #{} is read-only", n);
  set(static_cast<int>(n), v);
  return std::nullopt;
}

namespace {
constexpr std::string_view kPredefinedNames[] = {
    "_x", "_y", "_z", "_a", "_b", "_c", "_u", "_v", "_w",
    "_abs_x", "_abs_y", "_abs_z", "_abs_a", "_abs_b", "_abs_c", "_abs_u", "_abs_v", "_abs_w",
    "_motion_mode", "_plane", "_ccomp", "_metric", "_imperial", "_absolute", "_incremental", "_inverse_time",
    "_units_per_minute", "_units_per_rev", "_coord_system", "_tool_offset", "_retract_r_plane", "_retract_old_z",
    "_spindle_rpm_mode", "_spindle_css_mode", "_ijk_absolute_mode", "_lathe_diameter_mode", "_lathe_radius_mode",
    "_spindle_on", "_spindle_cw", "_mist", "_flood", "_speed_override", "_feed_override", "_feed", "_rpm",
    "_current_tool", "_selected_tool", "_call_level", "_remap_level", "_line", "_task"};
static_assert(std::size(kPredefinedNames) == static_cast<std::size_t>(Predefined::Count));
}  // namespace

std::string_view predefined_name(Predefined p) { return kPredefinedNames[static_cast<std::size_t>(p)]; }

std::optional<Predefined> predefined_of(std::string_view name) {
  if (name.size() < 2 || name[0] != '_') return std::nullopt;
  static const std::unordered_map<std::string_view, Predefined> kByName = [] {
    std::unordered_map<std::string_view, Predefined> m;
    for (std::size_t i = 0; i < std::size(kPredefinedNames); ++i) m.emplace(kPredefinedNames[i], static_cast<Predefined>(i));
    return m;
  }();
  const auto it = kByName.find(name);
  return it == kByName.end() ? std::nullopt : std::optional<Predefined>(it->second);
}

std::optional<std::string> Parameters::read_named(std::string_view name, double& out) const {
  if (const auto p = predefined_of(name)) {
    const auto k = static_cast<std::size_t>(*p), x = static_cast<std::size_t>(Predefined::X);
    if (k >= x && k < x + 9) out = numbered_[kCurrentPosition + static_cast<int>(k - x)];  // #<_x>… is #5420…
    else if (*p == Predefined::CallLevel) out = static_cast<double>(depth());
    else out = predefined_[k];
    return std::nullopt;
  }
  if (!name.empty() && name[0] == '_') {
    const auto it = globals_.find(std::string(name));
    if (it == globals_.end()) return fmt::format("named parameter #<{}> is not defined", name);
    out = it->second;
    return std::nullopt;
  }
  for (const auto& [k, v] : frames_.back().named)
    if (k == name) {
      out = v;
      return std::nullopt;
    }
  return fmt::format("named parameter #<{}> is not defined", name);
}

std::optional<std::string> Parameters::write_named(std::string_view name, double v) {
  if (predefined_of(name)) return fmt::format("named parameter #<{}> is read-only", name);
  if (!name.empty() && name[0] == '_') {
    globals_[std::string(name)] = v;
    return std::nullopt;
  }
  auto& named = frames_.back().named;
  for (auto& [k, old] : named)
    if (k == name) {
      old = v;
      return std::nullopt;
    }
  named.emplace_back(std::string(name), v);
  return std::nullopt;
}

bool Parameters::exists(std::string_view name) const {
  double ignored = 0;
  return !read_named(name, ignored);
}

void Parameters::push_frame(const double* args, std::size_t n, bool numbered_shared) {
  const std::size_t owner = numbered_shared ? frames_.back().numbered_owner : frames_.size();
  frames_.emplace_back();
  frames_.back().numbered_owner = owner;
  for (std::size_t i = 0; i < n && i < kLocalParameters; ++i) frames_.back().local[i + 1] = args[i];
}

void Parameters::pop_frame() {
  if (frames_.size() > 1) frames_.pop_back();
}

}  // namespace softmc::program::iso
