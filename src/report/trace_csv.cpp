// The trace as CSV: one line per cycle, formatted into a buffer (traces run to millions of rows).
#include <fmt/format.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "report/summary.hpp"

namespace softmc::report {

TraceCsvWriter::TraceCsvWriter(const std::string& path, core::AxisMask axes, SourceLocations loc)
    : path_(path), loc_(loc ? std::move(loc) : source_locations(nullptr)) {
  f_ = std::fopen(path.c_str(), "wb");
  if (!f_) throw std::runtime_error(fmt::format("cannot open trace CSV {}: {}", path, std::strerror(errno)));
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (axes & core::axis_bit(i)) axes_[n_axes_++] = i;
  auto out = std::back_inserter(buf_);
  fmt::format_to(out, "t_s");
  for (std::size_t k = 0; k < n_axes_; ++k) {
    const char a = static_cast<char>(std::tolower(static_cast<unsigned char>(core::letter(axes_[k]))));
    fmt::format_to(out, ",{0}_cmd_mm,{0}_act_mm,{0}_vel_mm_s", a);
  }
  fmt::format_to(out, ",path_v_mm_s,tool,line,dout");
  for (int k = 0; k < program::kAnalogOutputs; ++k) fmt::format_to(out, ",aout{}", k);
  fmt::format_to(out, "\n");
}

TraceCsvWriter::~TraceCsvWriter() {
  if (f_) std::fclose(f_);
}

void TraceCsvWriter::flush() {
  if (buf_.size() > 0 && std::fwrite(buf_.data(), 1, buf_.size(), f_) != buf_.size())
    throw std::runtime_error(fmt::format("cannot write trace CSV {}: {}", path_, std::strerror(errno)));
  buf_.clear();
}

void TraceCsvWriter::add(const TraceRow& r) {
  // 9 significant digits: a nanometre on a metre of travel; a tenth of a millisecond after a day.
  constexpr std::size_t kFlushBytes = 1 << 20;
  auto out = std::back_inserter(buf_);
  fmt::format_to(out, "{:.9g}", r.t_s);
  for (std::size_t k = 0; k < n_axes_; ++k)
    fmt::format_to(out, ",{:.9g},{:.9g},{:.9g}", r.cmd[axes_[k]], r.act[axes_[k]], r.vel[axes_[k]]);
  fmt::format_to(out, ",{:.9g},{},{},{}", r.path_v, r.tool_on ? 1 : 0, r.tag < loc_->size() ? (*loc_)[r.tag].line : 0u,
                 r.dout);
  for (const double a : r.aout) fmt::format_to(out, ",{:.9g}", a);
  fmt::format_to(out, "\n");
  if (buf_.size() >= kFlushBytes) flush();
}

void TraceCsvWriter::close() {
  flush();
  std::FILE* f = f_;
  f_ = nullptr;
  if (std::fclose(f) != 0)
    throw std::runtime_error(fmt::format("cannot write trace CSV {}: {}", path_, std::strerror(errno)));
}

void write_trace_csv(const std::string& path, const Trace& trace, const program::Program* prog) {
  TraceCsvWriter w(path, trace.axes, source_locations(prog));
  for (const TraceRow& r : trace.rows) w.add(r);
  w.close();
}

}  // namespace softmc::report
