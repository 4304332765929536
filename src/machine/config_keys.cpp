// Rules of the configuration keys: single values, then the rules across keys, in one fixed order.
#include "machine/config_keys.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include <fmt/format.h>

#include "motion/limits.hpp"

namespace softmc::machine {

std::string axis_key(std::size_t index) {
  return std::string("axes.") + static_cast<char>(core::letter(index) - 'A' + 'a');
}

std::string_view home_side_name(HomeSide s) { return s == HomeSide::Negative ? "negative" : "positive"; }

std::optional<HomeSide> home_side_from(std::string_view s) {
  if (s == "negative") return HomeSide::Negative;
  if (s == "positive") return HomeSide::Positive;
  return std::nullopt;
}

// fmt's "{}" is the shortest text that parses back to the same double.
std::string format_number(double v) { return fmt::format("{}", v); }

std::optional<std::string> rule_violation(ConfigRule rule, double v) {
  const bool finite = std::isfinite(v);
  const std::string got = " (got " + format_number(v) + ")";
  switch (rule) {
    case ConfigRule::Finite:
      if (!finite) return "must be a finite number" + got;
      break;
    case ConfigRule::Positive:
      if (!(finite && v > 0)) return "must be > 0" + got;
      break;
    case ConfigRule::NonNegative:
      if (!(finite && v >= 0)) return "must be >= 0" + got;
      break;
    case ConfigRule::UnitInterval:
      if (!(v >= 0 && v <= 1)) return "must be between 0 and 1" + got;
      break;
    case ConfigRule::AtLeastOne:
      if (!(finite && v >= 1)) return "must be >= 1" + got;
      break;
    case ConfigRule::Period:
      if (!(v >= kMinPeriod_s && v <= kMaxPeriod_s))
        return fmt::format("must be between {} and {} s{}", kMinPeriod_s, kMaxPeriod_s, got);
      break;
    default:
      break;
  }
  return std::nullopt;
}

std::optional<std::string> rule_violation(ConfigRule rule, std::size_t v) {
  if (rule == ConfigRule::Queue && (v < kMinQueue || v > kMaxQueue))
    return fmt::format("must be an integer between {} and {} (got {})", kMinQueue, kMaxQueue, v);
  return std::nullopt;
}

std::optional<std::string> rule_violation(ConfigRule rule, const std::string& v) {
  if (rule == ConfigRule::NonEmpty && v.empty()) return std::string("must not be empty");
  if (rule == ConfigRule::SpcMode && v != "start-stop" && v != "record-select")
    return "must be \"start-stop\" or \"record-select\" (got \"" + v + "\")";
  return std::nullopt;
}

std::optional<std::string> rule_violation(ConfigRule rule, int v) {
  if (rule == ConfigRule::SpcProgram && (v < -1 || v > 99))
    return fmt::format("must be a program number 0..99, or -1 for none (got {})", v);
  if (rule == ConfigRule::MGroup && (v < 0 || v > 14))
    return fmt::format("must be an M function group 1..14, or 0 for the function's own (got {})", v);
  return std::nullopt;
}

namespace {

template <class Owner>
std::optional<std::string> key_violation(const ConfigKey<Owner>& key, const Owner& owner) {
  return std::visit(
      [&](auto member) -> std::optional<std::string> {
        using T = std::remove_cvref_t<decltype(owner.*member)>;
        if constexpr (std::is_same_v<T, double> || std::is_same_v<T, std::size_t> ||
                      std::is_same_v<T, std::string> || std::is_same_v<T, int>)
          return rule_violation(key.rule, owner.*member);
        else
          return std::nullopt;  // bool, HomeSide: every value the type holds is valid
      },
      key.field);
}

bool wanted(const std::vector<std::string>* only, const std::string& key) {
  return !only || std::find(only->begin(), only->end(), key) != only->end();
}

template <class Owner, std::size_t N>
std::optional<ConfigProblem> check_keys(const std::array<ConfigKey<Owner>, N>& keys, const Owner& owner,
                                        const std::string& prefix, const std::vector<std::string>* only) {
  for (const auto& k : keys) {
    const std::string full = prefix + std::string(k.name);
    if (!wanted(only, full)) continue;
    if (auto v = key_violation(k, owner)) return ConfigProblem{{full}, full + " " + *v};
  }
  return std::nullopt;
}

}  // namespace

std::optional<ConfigProblem> find_problem(const MachineConfig& cfg, const std::vector<std::string>* only) {
  if (auto p = check_keys(kMachineKeys, cfg, "", only)) return p;

  if (!only) {
    std::size_t prev = 0;
    for (std::size_t i = 0; i < cfg.axes.size(); ++i) {
      const auto& a = cfg.axes[i];
      if (a.index >= core::kMaxAxes)
        return ConfigProblem{{"axes"}, fmt::format("axes: axis index {} is out of range", a.index)};
      if (a.name != axis_key(a.index).substr(5))
        return ConfigProblem{{axis_key(a.index), "axes"},
                             fmt::format("{}: axis name \"{}\" does not match its index", axis_key(a.index), a.name)};
      if (i > 0 && a.index <= prev)
        return ConfigProblem{{axis_key(a.index), "axes"},
                             fmt::format("axes must be in axis order without duplicates ({} after {})",
                                         axis_key(a.index), axis_key(prev))};
      prev = a.index;
    }
    if (std::none_of(cfg.axes.begin(), cfg.axes.end(), [](const AxisConfig& a) { return a.enabled; }))
      return ConfigProblem{{"axes"}, "axes: at least one axis must be enabled"};
  }

  if (auto p = check_keys(kSpcKeys, cfg.spc, "spc.", only)) return p;
  if (auto p = check_keys(kPlannerKeys, cfg.planner, "planner.", only)) return p;
  // The simulated fallback brake accepts states with no feasible brake in short look-ahead windows
  // (stop 23's review: up to 680× an axis's jerk in windows of 5–8 blocks on an ordinary program;
  // docs/planner.md, "Blocks at rest"): not offered until it is mended. The certificate (false)
  // keeps every limit.
  if (cfg.planner.jerk_guard_simulate && wanted(only, "planner.jerk_guard_simulate"))
    return ConfigProblem{{"planner.jerk_guard_simulate"},
                         "planner.jerk_guard_simulate = true is not available: the simulated fallback brake broke axis "
                         "limits in short look-ahead windows (docs/planner.md, \"Blocks at rest\"); leave it false"};
  if (auto p = check_keys(kGcodeKeys, cfg.gcode, "gcode.", only)) return p;
  for (std::size_t i = 0; i < cfg.gcode.m.size(); ++i) {
    const auto& m = cfg.gcode.m[i];
    const std::string mk = fmt::format("gcode.m.{}", m.number);
    if (!only && (m.number < 0 || m.number > kMaxMFunction))
      return ConfigProblem{{mk, "gcode.m"}, fmt::format("{}: M functions are numbered 0..{}", mk, kMaxMFunction)};
    if (!only && i > 0 && m.number <= cfg.gcode.m[i - 1].number)
      return ConfigProblem{{mk, "gcode.m"}, fmt::format("gcode.m must be in number order without duplicates ({} after "
                                                        "gcode.m.{})", mk, cfg.gcode.m[i - 1].number)};
    if (auto p = check_keys(kMFunctionKeys, m, mk + ".", only)) return p;
  }

  for (const auto& a : cfg.axes) {
    if (!a.enabled) continue;  // a disabled axis takes no part in anything; checked once enabled
    const std::string ak = axis_key(a.index);
    if (auto p = check_keys(kAxisKeys, a, ak + ".", only)) return p;
    if (only) continue;
    if (!(a.min_mm < a.max_mm))
      return ConfigProblem{{ak + ".min_mm", ak + ".max_mm", ak},
                           fmt::format("{0}.min_mm must be < {0}.max_mm (got {1} >= {2})", ak,
                                       format_number(a.min_mm), format_number(a.max_mm))};
    if (const double step = a.max_jerk_mm_s3 * cfg.period_s * cfg.period_s * cfg.period_s;
        a.max_jerk_mm_s3 > 0 && step < motion::kMinJerkStep_mm)
      return ConfigProblem{{ak + ".max_jerk_mm_s3", "period_s", ak},
                           fmt::format("{}.max_jerk_mm_s3 {} mm/s³ moves {:.3g} mm in a cycle of {} s; the jerk "
                                       "follower needs at least {:g} mm (max_jerk_mm_s3 >= {:.4g}, a longer period_s, or 0 "
                                       "for no jerk limit)",
                                       ak, format_number(a.max_jerk_mm_s3), step, format_number(cfg.period_s),
                                       motion::kMinJerkStep_mm,
                                       motion::kMinJerkStep_mm / (cfg.period_s * cfg.period_s * cfg.period_s))};
    // Homing (T-4) ends home_backoff_mm from the switch, which sits switch_overtravel_mm beyond the
    // travel: inside the travel only when the back-off is the longer.
    if (a.limit_switches && !(a.home_backoff_mm > a.switch_overtravel_mm))
      return ConfigProblem{{ak + ".home_backoff_mm", ak + ".switch_overtravel_mm", ak},
                           fmt::format("{0}.home_backoff_mm must be > {0}.switch_overtravel_mm, so that homing ends "
                                       "inside the travel (got {1} <= {2})",
                                       ak, format_number(a.home_backoff_mm), format_number(a.switch_overtravel_mm))};
    if (!(a.home_backoff_mm < a.max_mm - a.min_mm))
      return ConfigProblem{{ak + ".home_backoff_mm", ak},
                           fmt::format("{}.home_backoff_mm must be < the travel max_mm - min_mm (got {} >= {})", ak,
                                       format_number(a.home_backoff_mm), format_number(a.max_mm - a.min_mm))};
  }
  return std::nullopt;
}

}  // namespace softmc::machine
