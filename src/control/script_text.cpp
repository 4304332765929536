// Shared reading of the timed script formats.
#include "control/script_text.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace softmc::control::script {

std::vector<Field> fields_of(std::string_view line) {
  std::vector<Field> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    if (i >= line.size() || line[i] == '#') break;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r' && line[i] != '#') ++i;
    out.push_back({line.substr(start, i - start), static_cast<std::uint32_t>(start + 1)});
  }
  return out;
}

bool iequal(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if ((a[i] | 0x20) != (b[i] | 0x20)) return false;
  return true;
}

bool to_int(std::string_view s, int& v) {
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc{} && r.ptr == s.data() + s.size();
}

std::optional<std::string> read_time(const Field& f, double& last_t, double& t) {
  const auto* b = f.text.data();
  const auto* e = b + f.text.size();
  const auto r = std::from_chars(b, e, t);
  if (r.ec != std::errc{} || r.ptr != e || !std::isfinite(t) || t < 0)
    return "expected a time in seconds (a number ≥ 0), got '" + std::string(f.text) + "'";
  if (t + kTimeEpsS < last_t)
    return "time goes backwards: " + std::string(f.text) + " s after " + std::to_string(last_t) + " s";
  last_t = t;
  return std::nullopt;
}

std::optional<std::string> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::optional<std::pair<std::uint32_t, std::string>> three_fields(const std::vector<Field>& f,
                                                                   std::string_view signal_words) {
  if (f.size() < 3) {
    const auto col = static_cast<std::uint32_t>(f.back().col + f.back().text.size());
    return std::pair{col, f.size() == 1 ? "expected " + std::string(signal_words) + " after the time"
                                        : std::string("expected a value after the signal")};
  }
  if (f.size() > 3) return std::pair{f[3].col, "unexpected text after the value: '" + std::string(f[3].text) + "'"};
  return std::nullopt;
}

}  // namespace softmc::control::script
