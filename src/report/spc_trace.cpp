// The SPC trace's signal list and its CSV form.
#include "report/spc_trace.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

namespace softmc::report {

namespace sig = control::spc::sig;

std::vector<SpcSignal> spc_signals(bool record_select) {
  if (record_select)
    return {{"READY", sig::kReady}, {"RC_A", sig::kRcA},   {"RC_B", sig::kRcB},     {"ACK_A", sig::kAckA},
            {"ACK_B", sig::kAckB},  {"STOP", sig::kStop},  {"RESET", sig::kReset}, {"ENABLE", sig::kEnable},
            {"CLK_A", sig::kClkA},  {"CLK_B", sig::kClkB}};
  return {{"READY", sig::kReady},     {"MC_A", sig::kMcA},      {"MC_B", sig::kMcB},
          {"SYNC_OA", sig::kSyncOA},  {"SYNC_OB", sig::kSyncOB}, {"STOP", sig::kStop},
          {"START", sig::kStart},     {"ENABLE", sig::kEnable}, {"SYNC_IA", sig::kSyncIA},
          {"SYNC_IB", sig::kSyncIB}};
}

namespace {
struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
bool bit_of(const SpcTraceRow& r, control::spc::IoAddress a) {
  const auto w = a.output ? r.out[a.module] : r.in[a.module];
  return (w >> a.bit) & 1u;
}
}  // namespace

void write_spc_trace_csv(const std::string& path, const SpcTrace& trace) {
  std::unique_ptr<std::FILE, FileCloser> f(std::fopen(path.c_str(), "wb"));
  if (!f) throw std::runtime_error(fmt::format("cannot open trace CSV {}: {}", path, std::strerror(errno)));
  const auto sigs = spc_signals(trace.record_select);
  fmt::memory_buffer buf;
  auto out = std::back_inserter(buf);
  auto flush = [&] {
    if (buf.size() > 0 && std::fwrite(buf.data(), 1, buf.size(), f.get()) != buf.size())
      throw std::runtime_error(fmt::format("cannot write trace CSV {}: {}", path, std::strerror(errno)));
    buf.clear();
  };
  fmt::format_to(out, "t_s");
  for (std::size_t a = 0; a < kSpcAxes; ++a)
    if (trace.axes & (1u << a))
      fmt::format_to(out, ",{0}_cmd,{0}_act", program::kSpcAxisLetters[a]);
  for (const auto& s : sigs) fmt::format_to(out, ",{}", s.name);
  fmt::format_to(out, ",LINE");
  for (int m = 0; m < control::spc::kIoModules; ++m) fmt::format_to(out, ",I{}", m);
  for (int m = 0; m < control::spc::kIoModules; ++m) fmt::format_to(out, ",Q{}", m);
  fmt::format_to(out, "\n");
  for (const auto& r : trace.rows) {
    fmt::format_to(out, "{:.6f}", r.t_s);
    for (std::size_t a = 0; a < kSpcAxes; ++a)
      if (trace.axes & (1u << a)) fmt::format_to(out, ",{:.4f},{:.4f}", r.cmd[a], r.act[a]);
    for (const auto& s : sigs) fmt::format_to(out, ",{}", bit_of(r, s.addr) ? 1 : 0);
    fmt::format_to(out, ",{}", r.in[0] & 0x1F);
    for (auto w : r.in) fmt::format_to(out, ",{:04x}", w);
    for (auto w : r.out) fmt::format_to(out, ",{:04x}", w);
    fmt::format_to(out, "\n");
    if (buf.size() > (1u << 16)) flush();
  }
  flush();
}

}  // namespace softmc::report
