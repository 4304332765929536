// Parser and player of the reference PLC's orders files (format in plc_script.hpp and docs/spc.md).
#include "control/spc/plc_script.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "control/spc/task.hpp"

namespace softmc::control::spc {

namespace {

constexpr double kTimeEpsS = 1e-9;

struct Field {
  std::string_view text;
  std::uint32_t col = 0;  // 1-based
};

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

}  // namespace

PlcScriptParseResult parse_plc_script(std::string_view text, const std::string& file_name) {
  PlcScriptParseResult res;
  PlcScript sc;
  auto error = [&](std::uint32_t line, std::uint32_t col, std::string msg) {
    res.diagnostics.push_back({file_name, line, col, core::Severity::Error, std::move(msg)});
  };
  double last_t = 0;
  std::uint32_t line_no = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t eol = text.find('\n', pos);
    const std::string_view line = text.substr(pos, eol == std::string_view::npos ? text.size() - pos : eol - pos);
    pos = eol == std::string_view::npos ? text.size() + 1 : eol + 1;
    ++line_no;
    const auto f = fields_of(line);
    if (f.empty()) continue;
    PlcScriptEntry e;
    e.source_line = line_no;
    double t = 0;
    const auto r = std::from_chars(f[0].text.data(), f[0].text.data() + f[0].text.size(), t);
    if (r.ec != std::errc{} || r.ptr != f[0].text.data() + f[0].text.size() || !std::isfinite(t) || t < 0) {
      error(line_no, f[0].col, "expected a time in seconds (a number ≥ 0), got '" + std::string(f[0].text) + "'");
      continue;
    }
    if (t + kTimeEpsS < last_t) {
      error(line_no, f[0].col, "time goes backwards: " + std::string(f[0].text) + " s after " + std::to_string(last_t) + " s");
      continue;
    }
    last_t = e.t_s = t;
    if (f.size() < 2) {
      error(line_no, static_cast<std::uint32_t>(f[0].col + f[0].text.size()), "expected A, B, STOP or ENABLE after the time");
      continue;
    }
    const auto& what = f[1].text;
    std::size_t want = 3;
    if (iequal(what, "STOP")) {
      e.kind = PlcScriptEntry::Kind::Stop;
      want = 2;
    } else if (iequal(what, "ENABLE")) {
      e.kind = PlcScriptEntry::Kind::Enable;
    } else if (iequal(what, "A") || iequal(what, "B")) {
      e.kind = PlcScriptEntry::Kind::Order;
      e.task = iequal(what, "A") ? 0 : 1;
    } else {
      error(line_no, f[1].col, "expected A, B, STOP or ENABLE, got '" + std::string(what) + "'");
      continue;
    }
    if (f.size() < want) {
      error(line_no, static_cast<std::uint32_t>(f[1].col + what.size()),
            e.kind == PlcScriptEntry::Kind::Order ? "expected a line number 0..31" : "expected 0 or 1");
      continue;
    }
    if (f.size() > want) {
      error(line_no, f[want].col, "unexpected text: '" + std::string(f[want].text) + "'");
      continue;
    }
    if (want == 3) {
      int v = -1;
      const int max = e.kind == PlcScriptEntry::Kind::Order ? 31 : 1;
      if (!to_int(f[2].text, v) || v < 0 || v > max) {
        error(line_no, f[2].col, std::string(max == 31 ? "expected a line number 0..31" : "expected 0 or 1") +
                                     ", got '" + std::string(f[2].text) + "'");
        continue;
      }
      e.value = static_cast<std::uint8_t>(v);
    }
    sc.entries.push_back(e);
  }
  if (!core::has_errors(res.diagnostics)) res.script = std::move(sc);
  return res;
}

PlcScriptParseResult load_plc_script(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    PlcScriptParseResult res;
    res.diagnostics.push_back({path, 0, 0, core::Severity::Error, "cannot read the PLC orders file"});
    return res;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_plc_script(ss.str(), path);
}

// rt-safe
int PlcScriptPlayer::apply(double now_s, PlcClient& plc) {
  int refused = 0;
  while (next_ < s_.entries.size() && s_.entries[next_].t_s <= now_s + kTimeEpsS) {
    const auto& e = s_.entries[next_++];
    switch (e.kind) {
      case PlcScriptEntry::Kind::Order:
        if (!plc.order(e.task == 0 ? TaskId::A : TaskId::B, e.value)) ++refused;
        break;
      case PlcScriptEntry::Kind::Stop: plc.request_stop(); break;
      case PlcScriptEntry::Kind::Enable: plc.set_enable(e.value != 0); break;
    }
  }
  return refused;
}

}  // namespace softmc::control::spc
