// Parser and player for G-code run stimulus files (format in channel_stimulus.hpp and docs/cli.md).
#include "control/channel_stimulus.hpp"

#include <charconv>

#include "control/script_text.hpp"

namespace softmc::control {

using script::Field;
using script::iequal;

namespace {
struct SignalName {
  const char* name;
  MotionSignal signal;
  const char* unit;  // of a word (0..65535); nullptr: a bit (0/1)
};
constexpr SignalName kSignals[] = {
    {"feed_override_permille", MotionSignal::FeedOverride, "per mille"},
    {"feed_override_multiplier_permille", MotionSignal::FeedOverrideMultiplier, "per mille"},
    {"feed_limit_request", MotionSignal::FeedLimitRequest, nullptr},
    {"feed_limit_mm_min", MotionSignal::FeedLimit, "mm/min"},
    {"rapid_limit_request", MotionSignal::RapidLimitRequest, nullptr},
    {"rapid_limit_mm_min", MotionSignal::RapidLimit, "mm/min"},
    {"feed_hold", MotionSignal::FeedHold, nullptr},
    {"axis_enable", MotionSignal::AxisEnable, nullptr},
    {"stop_pulse", MotionSignal::StopPulse, nullptr},
    {"stop_request", MotionSignal::StopRequest, nullptr},
    {"emergency_stop_request", MotionSignal::EmergencyStopRequest, nullptr},
};

// "feed_override_permille, ..., axis_enable[L], ...": every name, for the unknown-signal message.
std::string signal_names() {
  std::string s;
  for (const auto& n : kSignals)
    s += std::string(s.empty() ? "" : ", ") + n.name + (n.signal == MotionSignal::AxisEnable ? "[L]" : "");
  return s;
}

std::string axis_letters(core::AxisMask axes) {
  std::string s;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (axes & core::axis_bit(i)) s += s.empty() ? std::string(1, core::letter(i)) : std::string(", ") + core::letter(i);
  return s;
}
}  // namespace

const char* to_string(MotionSignal s) {
  for (const auto& n : kSignals)
    if (n.signal == s) return n.name;
  return "?";
}

ChannelStimulusParseResult parse_channel_stimulus(std::string_view text, const std::string& file_name,
                                                  core::AxisMask axes) {
  ChannelStimulusParseResult res;
  ChannelStimulus st;
  auto error = [&](std::uint32_t line, std::uint32_t col, std::string msg) {
    res.diagnostics.push_back({file_name, line, col, core::Severity::Error, std::move(msg)});
  };
  double last_t = 0;
  script::for_each_line(text, [&](std::uint32_t line_no, const std::vector<Field>& f) {
    if (auto e = script::three_fields(f, "a signal name")) return error(line_no, e->first, std::move(e->second));
    ChannelStimulusEvent ev;
    ev.source_line = line_no;
    if (auto err = script::read_time(f[0], last_t, ev.t_s)) return error(line_no, f[0].col, std::move(*err));

    // signal: a name, or axis_enable[L]
    std::string_view name = f[1].text;
    std::optional<std::size_t> axis;
    if (const auto open = name.find('['); open != std::string_view::npos) {
      const auto inner = name.substr(open + 1);
      const auto a = inner.size() == 2 && inner[1] == ']' ? core::axis_from_letter(static_cast<char>(inner[0] & ~0x20))
                                                           : std::nullopt;
      if (!iequal(name.substr(0, open), "axis_enable") || !a || !(axes & core::axis_bit(*a))) {
        error(line_no, f[1].col,
              "expected axis_enable[L] with L one of the machine's axes (" + axis_letters(axes) + "), got '" +
                  std::string(name) + "'");
        return;
      }
      axis = a;
      name = name.substr(0, open);
    }
    const SignalName* sig = nullptr;
    for (const auto& n : kSignals)
      if (iequal(name, n.name)) sig = &n;
    if (!sig) {
      error(line_no, f[1].col,
            "unknown signal '" + std::string(f[1].text) + "' (" + signal_names() + ")");
      return;
    }
    if (sig->signal == MotionSignal::AxisEnable && !axis) {
      error(line_no, f[1].col, "axis_enable needs an axis: axis_enable[L] with L one of " + axis_letters(axes));
      return;
    }
    ev.signal = sig->signal;
    ev.axis = static_cast<std::uint8_t>(axis.value_or(0));

    // value
    int v = -1;
    const auto* b = f[2].text.data();
    const auto* e = b + f[2].text.size();
    const auto r = std::from_chars(b, e, v);
    const bool acknowledged = sig->signal == MotionSignal::StopRequest || sig->signal == MotionSignal::EmergencyStopRequest;
    if (r.ec != std::errc{} || r.ptr != e || v < (acknowledged ? 1 : 0) || v > (sig->unit ? 65535 : 1)) {
      error(line_no, f[2].col,
            (acknowledged ? std::string("expected 1 (the channel clears the request when it takes it)")
             : sig->unit  ? "expected a whole number of " + std::string(sig->unit) + " 0..65535"
                          : std::string("expected 0 or 1")) +
                ", got '" + std::string(f[2].text) + "'");
      return;
    }
    ev.value = static_cast<std::uint16_t>(v);
    st.events.push_back(ev);
  });
  if (!core::has_errors(res.diagnostics)) res.stimulus = std::move(st);
  return res;
}

ChannelStimulusParseResult load_channel_stimulus(const std::string& path, core::AxisMask axes) {
  return script::load<ChannelStimulusParseResult>(path, "stimulus file", [axes](std::string_view text, const std::string& p) {
    return parse_channel_stimulus(text, p, axes);
  });
}

std::string short_label(const ChannelStimulusEvent& e) {
  const auto permille = [](std::uint16_t v) {
    std::string s = std::to_string(v / 10);
    if (v % 10) s += "." + std::to_string(v % 10);
    return s;
  };
  switch (e.signal) {
    case MotionSignal::FeedOverride: return "%F " + permille(e.value);
    case MotionSignal::FeedOverrideMultiplier: return "x " + permille(e.value) + " %";
    case MotionSignal::FeedLimitRequest: return e.value ? "feed limit" : "feed limit off";
    case MotionSignal::FeedLimit: return "feed limit " + std::to_string(e.value) + " mm/min";
    case MotionSignal::RapidLimitRequest: return e.value ? "rapid limit" : "rapid limit off";
    case MotionSignal::RapidLimit: return "rapid limit " + std::to_string(e.value) + " mm/min";
    case MotionSignal::FeedHold: return e.value ? "hold" : "release";
    case MotionSignal::AxisEnable: return std::string(1, core::letter(e.axis)) + (e.value ? " on" : " off");
    case MotionSignal::StopPulse: return e.value ? "stop pulse" : "";
    case MotionSignal::StopRequest: return "stop";
    case MotionSignal::EmergencyStopRequest: return "e-stop";
  }
  return "";
}

// rt-safe
void apply(const ChannelStimulusEvent& e, MotionSignals& s) {
  const bool on = e.value != 0;
  switch (e.signal) {
    case MotionSignal::FeedOverride: s.feed_override_permille = e.value; break;
    case MotionSignal::FeedOverrideMultiplier: s.feed_override_multiplier_permille = e.value; break;
    case MotionSignal::FeedLimitRequest: s.feed_limit_request = on; break;
    case MotionSignal::FeedLimit: s.feed_limit_mm_min = e.value; break;
    case MotionSignal::RapidLimitRequest: s.rapid_limit_request = on; break;
    case MotionSignal::RapidLimit: s.rapid_limit_mm_min = e.value; break;
    case MotionSignal::FeedHold: s.feed_hold = on; break;
    case MotionSignal::AxisEnable: s.axis_enable[e.axis] = on; break;
    case MotionSignal::StopPulse: s.stop_pulse = on; break;
    case MotionSignal::StopRequest: s.stop_request = on; break;
    case MotionSignal::EmergencyStopRequest: s.emergency_stop_request = on; break;
  }
}

// rt-safe
int ChannelStimulusPlayer::apply(double now_s, MotionSignals& signals) {
  int n = 0;
  while (next_ < s_.events.size() && s_.events[next_].t_s <= now_s + script::kTimeEpsS) {
    control::apply(s_.events[next_++], signals);
    ++n;
  }
  return n;
}

}  // namespace softmc::control
