// Parser and player of the reference PLC's orders files (format in plc_script.hpp and docs/spc.md).
#include "control/spc/plc_script.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "control/script_text.hpp"
#include "control/spc/task.hpp"

namespace softmc::control::spc {

using script::Field;
using script::iequal;
using script::to_int;
using script::kTimeEpsS;

PlcScriptParseResult parse_plc_script(std::string_view text, const std::string& file_name) {
  PlcScriptParseResult res;
  PlcScript sc;
  auto error = [&](std::uint32_t line, std::uint32_t col, std::string msg) {
    res.diagnostics.push_back({file_name, line, col, core::Severity::Error, std::move(msg)});
  };
  double last_t = 0;
  script::for_each_line(text, [&](std::uint32_t line_no, const std::vector<Field>& f) {
    PlcScriptEntry e;
    e.source_line = line_no;
    if (auto err = script::read_time(f[0], last_t, e.t_s)) return error(line_no, f[0].col, std::move(*err));
    if (f.size() < 2) {
      error(line_no, static_cast<std::uint32_t>(f[0].col + f[0].text.size()), "expected A, B, STOP or ENABLE after the time");
      return;
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
      return;
    }
    if (f.size() < want) {
      error(line_no, static_cast<std::uint32_t>(f[1].col + what.size()),
            e.kind == PlcScriptEntry::Kind::Order ? "expected a line number 0..31" : "expected 0 or 1");
      return;
    }
    if (f.size() > want) {
      error(line_no, f[want].col, "unexpected text: '" + std::string(f[want].text) + "'");
      return;
    }
    if (want == 3) {
      int v = -1;
      const int max = e.kind == PlcScriptEntry::Kind::Order ? 31 : 1;
      if (!to_int(f[2].text, v) || v < 0 || v > max) {
        error(line_no, f[2].col, std::string(max == 31 ? "expected a line number 0..31" : "expected 0 or 1") +
                                     ", got '" + std::string(f[2].text) + "'");
        return;
      }
      e.value = static_cast<std::uint8_t>(v);
    }
    sc.entries.push_back(e);
  });
  if (!core::has_errors(res.diagnostics)) res.script = std::move(sc);
  return res;
}

PlcScriptParseResult load_plc_script(const std::string& path) {
  return script::load<PlcScriptParseResult>(path, "PLC orders file", parse_plc_script);
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
