// Parser and player for SPC input stimulus files (format in stimulus.hpp and docs/spc.md).
#include "control/spc/stimulus.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace softmc::control::spc {

namespace {

constexpr double kTimeEpsS = 1e-9;

struct Field {
  std::string_view text;
  std::uint32_t col = 0;  // 1-based
};

// Splits a line into whitespace-separated fields, up to a '#' comment.
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

}  // namespace

StimulusParseResult parse_stimulus(std::string_view text, const std::string& file_name) {
  StimulusParseResult res;
  Stimulus st;
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
    if (f.size() < 3) {
      const auto col = static_cast<std::uint32_t>(f.back().col + f.back().text.size());
      error(line_no, col, f.size() == 1 ? "expected a signal name or input address after the time"
                                        : "expected a value after the signal");
      continue;
    }
    if (f.size() > 3) {
      error(line_no, f[3].col, "unexpected text after the value: '" + std::string(f[3].text) + "'");
      continue;
    }

    StimulusEvent ev;
    ev.source_line = line_no;
    // time
    {
      double t = 0;
      const auto* b = f[0].text.data();
      const auto* e = b + f[0].text.size();
      const auto r = std::from_chars(b, e, t);
      if (r.ec != std::errc{} || r.ptr != e || !std::isfinite(t) || t < 0) {
        error(line_no, f[0].col, "expected a time in seconds (a number ≥ 0), got '" + std::string(f[0].text) + "'");
        continue;
      }
      if (t + kTimeEpsS < last_t) {
        error(line_no, f[0].col, "time goes backwards: " + std::string(f[0].text) + " s after " +
                                     std::to_string(last_t) + " s");
        continue;
      }
      ev.t_s = t;
      last_t = t;  // the order of times is checked on the times alone, even when the rest of a line is wrong
    }
    // signal
    const bool is_line = iequal(f[1].text, "LINE");
    if (is_line) {
      ev.line = true;
      ev.addr = {false, 0, 0};
    } else {
      auto a = signal_address(f[1].text);
      if (!a) a = parse_address(f[1].text);
      if (!a) {
        error(line_no, f[1].col, "unknown signal or address '" + std::string(f[1].text) +
                                     "' (a name such as START, CLK_A, or an input I0.0..I5.9, I1.0..I1.15, I3.0..I3.15)");
        continue;
      }
      if (a->output) {
        error(line_no, f[1].col, "'" + std::string(f[1].text) + "' is an output of the controller; a stimulus writes inputs");
        continue;
      }
      ev.addr = *a;
    }
    // value
    {
      int v = -1;
      const auto* b = f[2].text.data();
      const auto* e = b + f[2].text.size();
      const auto r = std::from_chars(b, e, v);
      const int max = is_line ? 31 : 1;
      if (r.ec != std::errc{} || r.ptr != e || v < 0 || v > max) {
        error(line_no, f[2].col, std::string(is_line ? "expected a line number 0..31" : "expected 0 or 1") +
                                     ", got '" + std::string(f[2].text) + "'");
        continue;
      }
      ev.value = static_cast<std::uint8_t>(v);
    }
    st.events.push_back(ev);
  }
  if (!core::has_errors(res.diagnostics)) res.stimulus = std::move(st);
  return res;
}

StimulusParseResult load_stimulus(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    StimulusParseResult res;
    res.diagnostics.push_back({path, 0, 0, core::Severity::Error, "cannot read the stimulus file"});
    return res;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_stimulus(ss.str(), path);
}

// rt-safe
int StimulusPlayer::apply(double now_s, IoImage& terminals) {
  int n = 0;
  while (next_ < s_.events.size() && s_.events[next_].t_s <= now_s + kTimeEpsS) {
    const auto& e = s_.events[next_++];
    if (e.line)
      terminals.set_line_bits(e.value);
    else
      terminals.set(e.addr, e.value != 0);
    ++n;
  }
  return n;
}

}  // namespace softmc::control::spc
