// The configuration's TOML edge: load a file, apply --set overrides, write the effective configuration.
//
// One code path sets keys: the file loader and apply_override() both hand toml++ nodes to Setter,
// which knows every key, its type and where it came from; so the two can never disagree.
//   file ──toml::parse──► table ──┐
//                                 ├─► Setter::apply(path, node) ─► MachineConfig ─► find_problem()
//   "k.e.y=value" ─► node ────────┘
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <type_traits>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "machine/config.hpp"
#include "machine/config_keys.hpp"

namespace softmc::machine {
namespace {

[[noreturn]] void fail(const std::string& where, const std::string& message) {
  throw ConfigError(where + ": error: " + message);
}

// "file:line:col", or just the file where toml++ has no position.
std::string position(const toml::source_region& r, const std::string& fallback) {
  const std::string file = r.path && !r.path->empty() ? *r.path : fallback;
  if (r.begin.line == 0) return file;
  return fmt::format("{}:{}:{}", file, r.begin.line, r.begin.column);
}

// What a wrong value was, for the error message: `string "fast"`, `integer 5`, `a table`.
std::string describe(const toml::node& n) {
  if (auto s = n.value_exact<std::string>()) return fmt::format("string \"{}\"", *s);
  if (auto i = n.value_exact<std::int64_t>()) return fmt::format("integer {}", *i);
  if (auto d = n.value_exact<double>()) return fmt::format("float {}", format_number(*d));
  if (auto b = n.value_exact<bool>()) return fmt::format("boolean {}", *b ? "true" : "false");
  if (n.is_table()) return "a table";
  if (n.is_array()) return "an array";
  return "a date/time";
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// " (did you mean max_vel_mm_s?)" when a known key is near the unknown one: a couple of edits away,
// or sharing a long beginning with it (max_velocity → max_vel_mm_s) that no other key shares.
template <class Names>
std::string suggestion(std::string_view unknown, const Names& names) {
  std::string best;
  std::size_t best_d = 3;  // farther than 2 edits is a different word
  for (std::string_view n : names) {
    const bool prefix = n.starts_with(unknown) || unknown.starts_with(n);
    const std::size_t d = prefix ? 1 : edit_distance(unknown, n);
    if (d < best_d) best_d = d, best = std::string(n);
  }
  if (best.empty()) {
    std::size_t best_len = 5, ties = 0;  // "max_" alone names nothing
    for (std::string_view n : names) {
      const auto m = std::mismatch(n.begin(), n.end(), unknown.begin(), unknown.end());
      const auto len = static_cast<std::size_t>(m.first - n.begin());
      if (len > best_len) best_len = len, best = std::string(n), ties = 0;
      else if (len == best_len && !best.empty()) ++ties;
    }
    if (ties) best.clear();
  }
  return best.empty() ? std::string() : " (did you mean " + best + "?)";
}

std::string join(const std::vector<std::string>& path) {
  std::string s;
  for (const auto& p : path) s += (s.empty() ? "" : ".") + p;
  return s;
}

// Sets keys of a configuration from toml++ nodes and remembers where each key was set.
class Setter {
 public:
  // With use_sources, errors point at the node's file:line:col; else at `fallback` (a --set argument).
  Setter(MachineConfig& cfg, std::string fallback, bool use_sources)
      : cfg_(cfg), fallback_(std::move(fallback)), use_sources_(use_sources) {}

  void apply_table(std::vector<std::string> path, const toml::table& t) {
    for (auto&& [k, v] : t) {
      path.emplace_back(k.str());
      apply(path, v, where(k.source(), v.source()));
      path.pop_back();
    }
  }

  // `path` is the dotted key of `node`; `loc` where it was written.
  void apply(const std::vector<std::string>& path, const toml::node& node, const std::string& loc) {
    const std::string key = join(path);
    locations_[key] = loc;
    if (path.empty()) return apply_table_node(path, node, key, loc);
    if (path[0] == "axes") return apply_axes(path, node, key, loc);
    if (path[0] == "spc") return apply_spc(path, node, key, loc);
    if (path[0] == "planner") return apply_planner(path, node, key, loc);
    if (path[0] == "gcode") return apply_gcode(path, node, key, loc);
    if (path.size() == 1)
      for (const auto& k : kMachineKeys)
        if (k.name == path[0]) return set_field(cfg_, k, node, key, loc);
    std::vector<std::string_view> names{"axes", "spc", "planner", "gcode"};
    for (const auto& k : kMachineKeys) names.push_back(k.name);
    fail(loc, "unknown key " + key + suggestion(path.back(), names));
  }

  const std::map<std::string, std::string>& locations() const { return locations_; }
  const std::vector<std::string>& touched() const { return touched_; }

 private:
  std::string where(const toml::source_region& key_src, const toml::source_region& value_src) const {
    if (!use_sources_) return fallback_;
    return position(key_src.begin.line ? key_src : value_src, fallback_);
  }

  void apply_table_node(const std::vector<std::string>& path, const toml::node& node, const std::string& key,
                        const std::string& loc) {
    const auto* t = node.as_table();
    const std::string what = key.empty() ? std::string("the document") : key;
    if (!t) fail(loc, what + " must be a table (got " + describe(node) + ")");
    apply_table(path, *t);
  }

  void apply_axes(const std::vector<std::string>& path, const toml::node& node, const std::string& key,
                  const std::string& loc) {
    if (path.size() == 1) return apply_table_node(path, node, key, loc);
    const std::string& letter = path[1];
    const auto index = letter.size() == 1 && letter[0] >= 'a' && letter[0] <= 'z'
                           ? core::axis_from_letter(letter[0])
                           : std::nullopt;
    if (!index)
      fail(loc, "unknown axis axes." + letter + " (axes are x y z a b c u v w, lower case)");
    AxisConfig& axis = ensure_axis(*index);
    if (path.size() == 2) return apply_table_node(path, node, key, loc);
    if (path.size() == 3)
      for (const auto& k : kAxisKeys)
        if (k.name == path[2]) return set_field(axis, k, node, key, loc);
    std::vector<std::string_view> names;
    for (const auto& k : kAxisKeys) names.push_back(k.name);
    fail(loc, "unknown key " + key + suggestion(path.back(), names));
  }

  void apply_spc(const std::vector<std::string>& path, const toml::node& node, const std::string& key,
                 const std::string& loc) {
    if (path.size() == 1) return apply_table_node(path, node, key, loc);
    if (path.size() == 2)
      for (const auto& k : kSpcKeys)
        if (k.name == path[1]) return set_field(cfg_.spc, k, node, key, loc);
    std::vector<std::string_view> names;
    for (const auto& k : kSpcKeys) names.push_back(k.name);
    fail(loc, "unknown key " + key + suggestion(path.back(), names));
  }

  void apply_planner(const std::vector<std::string>& path, const toml::node& node, const std::string& key,
                     const std::string& loc) {
    if (path.size() == 1) return apply_table_node(path, node, key, loc);
    if (path.size() == 2)
      for (const auto& k : kPlannerKeys)
        if (k.name == path[1]) return set_field(cfg_.planner, k, node, key, loc);
    std::vector<std::string_view> names;
    for (const auto& k : kPlannerKeys) names.push_back(k.name);
    fail(loc, "unknown key " + key + suggestion(path.back(), names));
  }

  // [gcode] and its [gcode.m.<n>] tables (P-10 M functions).
  void apply_gcode(const std::vector<std::string>& path, const toml::node& node, const std::string& key,
                   const std::string& loc) {
    if (path.size() == 1) return apply_table_node(path, node, key, loc);
    if (path[1] == "m") {
      if (path.size() == 2) return apply_table_node(path, node, key, loc);
      const std::string& n = path[2];
      const bool digits = !n.empty() && n.size() <= 3 && n.find_first_not_of("0123456789") == std::string::npos;
      if (!digits || std::stoi(n) > kMaxMFunction)
        fail(loc, fmt::format("unknown M function gcode.m.{} (M functions are numbered 0..{})", n, kMaxMFunction));
      MFunctionConfig& m = ensure_m(std::stoi(n));
      if (path.size() == 3) return apply_table_node(path, node, key, loc);
      if (path.size() == 4)
        for (const auto& k : kMFunctionKeys)
          if (k.name == path[3]) return set_field(m, k, node, key, loc);
      std::vector<std::string_view> names;
      for (const auto& k : kMFunctionKeys) names.push_back(k.name);
      fail(loc, "unknown key " + key + suggestion(path.back(), names));
    }
    if (path.size() == 2)
      for (const auto& k : kGcodeKeys)
        if (k.name == path[1]) return set_field(cfg_.gcode, k, node, key, loc);
    std::vector<std::string_view> names{"m"};
    for (const auto& k : kGcodeKeys) names.push_back(k.name);
    fail(loc, "unknown key " + key + suggestion(path.back(), names));
  }

  MFunctionConfig& ensure_m(int number) {
    auto& v = cfg_.gcode.m;
    auto it = std::find_if(v.begin(), v.end(), [&](const MFunctionConfig& m) { return m.number >= number; });
    if (it != v.end() && it->number == number) return *it;
    MFunctionConfig m;
    m.number = number;
    return *v.insert(it, m);
  }

  // An axis not configured yet starts from the AxisConfig defaults (no travel, no speed: they must be given).
  AxisConfig& ensure_axis(std::size_t index) {
    auto it = std::find_if(cfg_.axes.begin(), cfg_.axes.end(), [&](const AxisConfig& a) { return a.index >= index; });
    if (it != cfg_.axes.end() && it->index == index) return *it;
    AxisConfig a;
    a.index = index;
    a.name = axis_key(index).substr(5);
    return *cfg_.axes.insert(it, std::move(a));
  }

  template <class Owner>
  void set_field(Owner& owner, const ConfigKey<Owner>& k, const toml::node& node, const std::string& key,
                 const std::string& loc) {
    touched_.push_back(key);
    std::visit(
        [&](auto member) {
          auto& field = owner.*member;
          using T = std::remove_cvref_t<decltype(field)>;
          if constexpr (std::is_same_v<T, double>) {
            // Integers are numbers too: `max_vel_mm_s = 250` means 250.0.
            if (auto d = node.value<double>(); d && (node.is_floating_point() || node.is_integer())) {
              field = *d;
              return;
            }
            fail(loc, key + " must be a number (got " + describe(node) + ")");
          } else if constexpr (std::is_same_v<T, bool>) {
            if (auto b = node.value_exact<bool>()) return void(field = *b);
            fail(loc, key + " must be true or false (got " + describe(node) + ")");
          } else if constexpr (std::is_same_v<T, std::string>) {
            if (auto s = node.value_exact<std::string>()) return void(field = *s);
            fail(loc, key + " must be a string (got " + describe(node) + ")");
          } else if constexpr (std::is_same_v<T, std::size_t>) {
            auto i = node.value_exact<std::int64_t>();
            if (!i) fail(loc, key + " must be an integer (got " + describe(node) + ")");
            if (*i < 0) fail(loc, key + " must be >= 0 (got " + std::to_string(*i) + ")");
            field = static_cast<std::size_t>(*i);
          } else if constexpr (std::is_same_v<T, int>) {
            auto i = node.value_exact<std::int64_t>();
            if (!i) fail(loc, key + " must be an integer (got " + describe(node) + ")");
            if (*i < -1000000 || *i > 1000000) fail(loc, key + " is out of range (got " + std::to_string(*i) + ")");
            field = static_cast<int>(*i);
          } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
            const auto* arr = node.as_array();
            if (!arr) fail(loc, key + " must be an array of strings (got " + describe(node) + ")");
            std::vector<std::string> items;
            for (const auto& e : *arr) {
              auto s = e.value_exact<std::string>();
              if (!s) fail(loc, key + " must be an array of strings (got " + describe(e) + " in it)");
              items.push_back(*s);
            }
            field = std::move(items);
          } else if constexpr (std::is_same_v<T, HomeSide>) {
            if (auto s = node.value_exact<std::string>())
              if (auto side = home_side_from(*s)) return void(field = *side);
            fail(loc, key + " must be \"negative\" or \"positive\" (got " + describe(node) + ")");
          }
        },
        k.field);
  }

  MachineConfig& cfg_;
  std::string fallback_;
  bool use_sources_;
  std::map<std::string, std::string> locations_;  // dotted key → where it was set
  std::vector<std::string> touched_;              // leaf keys set, in order
};

std::string_view trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::string quoted(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
          out += fmt::format("\\u{:04X}", static_cast<unsigned>(static_cast<unsigned char>(c)));
        else
          out += c;
    }
  }
  return out + "\"";
}

// A TOML float: "600.0" rather than "600", which would read back as an integer.
std::string toml_float(double v) {
  std::string s = format_number(v);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // 'n': inf, nan
  return s;
}

template <class Owner, std::size_t N>
void write_keys(std::string& out, const std::array<ConfigKey<Owner>, N>& keys, const Owner& owner) {
  for (const auto& k : keys) {
    out += std::string(k.name) + " = ";
    std::visit(
        [&](auto member) {
          const auto& v = owner.*member;
          using T = std::remove_cvref_t<decltype(v)>;
          if constexpr (std::is_same_v<T, double>) out += toml_float(v);
          else if constexpr (std::is_same_v<T, bool>) out += v ? "true" : "false";
          else if constexpr (std::is_same_v<T, std::string>) out += quoted(std::string_view(v));  // not std::quoted
          else if constexpr (std::is_same_v<T, std::size_t> || std::is_same_v<T, int>) out += std::to_string(v);
          else if constexpr (std::is_same_v<T, HomeSide>) out += quoted(home_side_name(v));
          else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
            out += '[';
            for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + quoted(std::string_view(v[i]));
            out += ']';
          }
        },
        k.field);
    out += '\n';
  }
}

}  // namespace

MachineConfig parse_machine(const std::string& toml_text, const std::string& source_name) {
  toml::table doc;
  try {
    doc = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    fail(position(e.source(), source_name), std::string(e.description()));
  }
  MachineConfig cfg = default_machine();
  Setter setter(cfg, source_name, true);
  setter.apply_table({}, doc);
  if (auto p = find_problem(cfg)) {
    // Point at the line that set the offending key, or the nearest table that holds it.
    std::string loc = source_name;
    for (const auto& k : p->keys)
      if (auto it = setter.locations().find(k); it != setter.locations().end()) {
        loc = it->second;
        break;
      }
    fail(loc, p->message);
  }
  return cfg;
}

MachineConfig load_machine(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open machine configuration");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) fail(path, "cannot read machine configuration");
  MachineConfig cfg = parse_machine(text.str(), path);
  // [gcode] paths written relative to the configuration file mean its folder, wherever softmc runs.
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  auto resolve = [&](std::string& p) {
    if (!p.empty() && std::filesystem::path(p).is_relative())
      p = std::filesystem::absolute(dir / p).lexically_normal().string();
  };
  resolve(cfg.gcode.tool_table);
  for (auto& folder : cfg.gcode.subroutine_path) resolve(folder);
  return cfg;
}

void apply_override(MachineConfig& cfg, const std::string& assignment) {
  const std::string loc = "--set " + assignment;
  const auto eq = assignment.find('=');
  if (eq == std::string::npos) fail(loc, "expected KEY=VALUE, e.g. axes.x.max_vel_mm_s=100");
  const std::string_view key = trim(std::string_view(assignment).substr(0, eq));
  const std::string_view value = trim(std::string_view(assignment).substr(eq + 1));

  std::vector<std::string> path;
  for (std::size_t b = 0;;) {
    const auto e = key.find('.', b);
    path.emplace_back(trim(key.substr(b, e == std::string_view::npos ? std::string_view::npos : e - b)));
    if (path.back().empty()) fail(loc, "bad key \"" + std::string(key) + "\"");
    if (e == std::string_view::npos) break;
    b = e + 1;
  }

  // The value is TOML (100, 1e-3, false, "text", {…}); anything TOML cannot read is taken as a
  // bare string, so `--set tool_output=spindle` needs no shell-quoted quotes.
  toml::table holder;
  try {
    holder = toml::parse("v = " + std::string(value));
    if (holder.size() != 1) throw std::runtime_error("not one value");
  } catch (const std::exception&) {
    holder = toml::table{{"v", std::string(value)}};
  }

  MachineConfig next = cfg;  // all or nothing: a failed override leaves cfg unchanged
  Setter setter(next, loc, false);
  setter.apply(path, *holder.get("v"), loc);
  if (auto p = find_problem(next, &setter.touched())) fail(loc, p->message);
  cfg = std::move(next);
}

std::string to_toml(const MachineConfig& cfg) {
  std::string out = "# softmc machine configuration, every key with its effective value (docs/configuration.md)\n";
  write_keys(out, kMachineKeys, cfg);
  for (const auto& a : cfg.axes) {
    out += "\n[" + axis_key(a.index) + "]\n";
    write_keys(out, kAxisKeys, a);
  }
  out += "\n[spc]\n";
  write_keys(out, kSpcKeys, cfg.spc);
  out += "\n[planner]\n";
  write_keys(out, kPlannerKeys, cfg.planner);
  out += "\n[gcode]\n";
  write_keys(out, kGcodeKeys, cfg.gcode);
  for (const auto& m : cfg.gcode.m) {
    out += fmt::format("\n[gcode.m.{}]\n", m.number);
    write_keys(out, kMFunctionKeys, m);
  }
  return out;
}

}  // namespace softmc::machine
