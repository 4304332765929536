// libFuzzer target: any bytes into the three timed script formats (a G-code run's stimulus, an SPC
// stimulus, the reference PLC's orders): no crash, a result exactly when there is no error, times
// in order, and every value within its signal's range.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "control/channel_stimulus.hpp"
#include "control/spc/plc_script.hpp"
#include "control/spc/stimulus.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace softmc;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  {
    const core::AxisMask xy = core::axis_bit(0) | core::axis_bit(1);
    const auto r = control::parse_channel_stimulus(text, "run.stim", xy);
    if (r.stimulus.has_value() == core::has_errors(r.diagnostics)) std::abort();
    for (const auto& d : r.diagnostics) (void)d.format();
    if (r.stimulus) {
      double t = 0;
      control::MotionSignals s;
      for (const auto& e : r.stimulus->events) {
        if (e.t_s + 1e-9 < t || !(e.t_s >= 0)) std::abort();
        t = e.t_s;
        if (e.signal == control::MotionSignal::AxisEnable && !(xy & core::axis_bit(e.axis))) std::abort();
        control::apply(e, s);
      }
      control::ChannelStimulusPlayer p(*r.stimulus);
      (void)p.apply(1e300, s);
      if (!p.finished()) std::abort();
    }
  }
  {
    const auto r = control::spc::parse_stimulus(text, "in.stim");
    if (r.stimulus.has_value() == core::has_errors(r.diagnostics)) std::abort();
    for (const auto& d : r.diagnostics) (void)d.format();
  }
  {
    const auto r = control::spc::parse_plc_script(text, "orders.plc");
    if (r.script.has_value() == core::has_errors(r.diagnostics)) std::abort();
    for (const auto& d : r.diagnostics) (void)d.format();
  }
  return 0;
}
