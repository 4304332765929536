// Parser and player for SPC input stimulus files (format in stimulus.hpp and docs/spc.md).
#include "control/spc/stimulus.hpp"

#include "control/script_text.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace softmc::control::spc {

using script::Field;
using script::iequal;
using script::kTimeEpsS;

StimulusParseResult parse_stimulus(std::string_view text, const std::string& file_name) {
  StimulusParseResult res;
  Stimulus st;
  auto error = [&](std::uint32_t line, std::uint32_t col, std::string msg) {
    res.diagnostics.push_back({file_name, line, col, core::Severity::Error, std::move(msg)});
  };

  double last_t = 0;
  script::for_each_line(text, [&](std::uint32_t line_no, const std::vector<Field>& f) {
    if (auto e = script::three_fields(f, "a signal name or input address")) return error(line_no, e->first, std::move(e->second));

    StimulusEvent ev;
    ev.source_line = line_no;
    // time
    // The order of times is checked on the times alone, even when the rest of a line is wrong.
    if (auto err = script::read_time(f[0], last_t, ev.t_s)) return error(line_no, f[0].col, std::move(*err));
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
        return;
      }
      if (a->output) {
        error(line_no, f[1].col, "'" + std::string(f[1].text) + "' is an output of the controller; a stimulus writes inputs");
        return;
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
        return;
      }
      ev.value = static_cast<std::uint8_t>(v);
    }
    st.events.push_back(ev);
  });
  if (!core::has_errors(res.diagnostics)) res.stimulus = std::move(st);
  return res;
}

StimulusParseResult load_stimulus(const std::string& path) {
  return script::load<StimulusParseResult>(path, "stimulus file", parse_stimulus);
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
