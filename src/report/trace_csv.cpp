// The trace as CSV: one line per cycle, formatted into a buffer (traces run to millions of rows).
#include <fmt/format.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "report/summary.hpp"

namespace softmc::report {

namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

void flush(fmt::memory_buffer& buf, std::FILE* f, const std::string& path) {
  if (buf.size() > 0 && std::fwrite(buf.data(), 1, buf.size(), f) != buf.size())
    throw std::runtime_error(fmt::format("cannot write trace CSV {}: {}", path, std::strerror(errno)));
  buf.clear();
}

}  // namespace

void write_trace_csv(const std::string& path, const Trace& trace) {
  std::unique_ptr<std::FILE, FileCloser> f(std::fopen(path.c_str(), "wb"));
  if (!f) throw std::runtime_error(fmt::format("cannot open trace CSV {}: {}", path, std::strerror(errno)));

  std::size_t axes[core::kMaxAxes];
  std::size_t n_axes = 0;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (trace.axes & core::axis_bit(i)) axes[n_axes++] = i;

  fmt::memory_buffer buf;
  auto out = std::back_inserter(buf);
  fmt::format_to(out, "t_s");
  for (std::size_t k = 0; k < n_axes; ++k) {
    const char a = static_cast<char>(std::tolower(static_cast<unsigned char>(core::letter(axes[k]))));
    fmt::format_to(out, ",{0}_cmd_mm,{0}_act_mm,{0}_vel_mm_s", a);
  }
  fmt::format_to(out, ",path_v_mm_s,tool\n");

  // 9 significant digits: a nanometre on a metre of travel; a tenth of a millisecond after a day.
  constexpr std::size_t kFlushBytes = 1 << 20;
  for (const TraceRow& r : trace.rows) {
    fmt::format_to(out, "{:.9g}", r.t_s);
    for (std::size_t k = 0; k < n_axes; ++k)
      fmt::format_to(out, ",{:.9g},{:.9g},{:.9g}", r.cmd[axes[k]], r.act[axes[k]], r.vel[axes[k]]);
    fmt::format_to(out, ",{:.9g},{}\n", r.path_v, r.tool_on ? 1 : 0);
    if (buf.size() >= kFlushBytes) flush(buf, f.get(), path);
  }
  flush(buf, f.get(), path);
  if (std::fclose(f.release()) != 0)
    throw std::runtime_error(fmt::format("cannot write trace CSV {}: {}", path, std::strerror(errno)));
}

}  // namespace softmc::report
