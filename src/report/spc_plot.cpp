// The SPC run plot: axis setpoints over time above a digital timing diagram of the system signals.
//
//   +------------------------------------------------+
//   | title: store, mode, machine                     |
//   | position [mm] over t: X Y Z U (setpoints)       |
//   | READY  ‾‾‾‾‾‾‾‾‾‾|___|‾‾‾‾‾‾                     |  one row per signal, outputs first,
//   | RC_A   ‾‾‾|__|‾‾‾‾‾‾‾‾‾‾‾‾‾                     |  drawn high where the terminal is 1
//   | ...                                             |
//   | LINE   (B0..B4 as a number where it changes)    |
//   +------------------------------------------------+
#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "report/plot_canvas.hpp"
#include "report/plot_output.hpp"
#include "report/spc_trace.hpp"

namespace softmc::report {

namespace {

constexpr double kWidth = 1100;
constexpr double kLeft = 100, kPlotW = 960;
constexpr double kPosTop = 60, kPosH = 330;
constexpr double kSigTop = 450, kRowH = 30, kRowPitch = 38;
constexpr Rgb kInk{0.15, 0.15, 0.15};
constexpr std::array<Rgb, kSpcAxes> kAxisColors{{{0.12, 0.47, 0.71}, {0.90, 0.45, 0.05}, {0.17, 0.63, 0.17}, {0.58, 0.40, 0.74}}};
constexpr Rgb kOutColor{0.80, 0.12, 0.08};
constexpr Rgb kInColor{0.10, 0.30, 0.75};

bool bit_of(const SpcTraceRow& r, control::spc::IoAddress a) {
  const auto w = a.output ? r.out[a.module] : r.in[a.module];
  return (w >> a.bit) & 1u;
}

// Draws one digital row as a step line, merging runs of equal values (millions of rows stay cheap).
template <class Get>
void draw_row(cairo_t* cr, const SpcTrace& tr, const PlotFrame& f, double y_lo, double y_hi, Get get) {
  if (tr.rows.empty()) return;
  bool v = get(tr.rows.front());
  cairo_move_to(cr, f.to_px_x(0), v ? y_hi : y_lo);
  for (const auto& r : tr.rows) {
    const bool nv = get(r);
    if (nv == v) continue;
    const double x = f.to_px_x(r.t_s);
    cairo_line_to(cr, x, v ? y_hi : y_lo);
    cairo_line_to(cr, x, nv ? y_hi : y_lo);
    v = nv;
  }
  cairo_line_to(cr, f.to_px_x(tr.rows.back().t_s), v ? y_hi : y_lo);
  cairo_stroke(cr);
}

}  // namespace

void write_spc_plot(const std::string& path, const SpcTrace& tr, const std::string& title) {
  const auto sigs = spc_signals(tr.record_select);
  const int rows = static_cast<int>(sigs.size()) + (tr.record_select ? 1 : 0);
  const double height = kSigTop + rows * kRowPitch + 60;
  const double t_end = tr.rows.empty() ? 1.0 : std::max(tr.rows.back().t_s, 1e-3);

  render_to_file(path, kWidth, height, [&](cairo_t* cr) {
    set_color(cr, {1, 1, 1});
    cairo_paint(cr);
    set_color(cr, kInk);
    draw_text(cr, kLeft, 30, title, 16, Align::Start, Align::End, true);

    // Positions.
    PlotRange pr{INFINITY, -INFINITY};
    for (const auto& r : tr.rows)
      for (std::size_t a = 0; a < kSpcAxes; ++a)
        if (tr.axes & (1u << a)) {
          pr.lo = std::min(pr.lo, r.cmd[a]);
          pr.hi = std::max(pr.hi, r.cmd[a]);
        }
    if (!(pr.lo <= pr.hi)) pr = {0, 1};
    const PlotFrame pos{{kLeft, kPosTop, kPlotW, kPosH}, {0, t_end}, padded(pr, 0.05)};
    draw_axes(cr, pos, "t [s]", "position [mm]");
    cairo_save(cr);
    cairo_rectangle(cr, pos.px.x, pos.px.y, pos.px.w, pos.px.h);
    cairo_clip(cr);
    cairo_set_line_width(cr, 1.6);
    for (std::size_t a = 0; a < kSpcAxes; ++a) {
      if (!(tr.axes & (1u << a))) continue;
      SeriesEnvelope env(pos);
      for (const auto& r : tr.rows) env.add(r.t_s, r.cmd[a]);
      set_color(cr, kAxisColors[a]);
      env.stroke(cr);
    }
    cairo_restore(cr);
    double lx = kLeft + 10;
    for (std::size_t a = 0; a < kSpcAxes; ++a) {
      if (!(tr.axes & (1u << a))) continue;
      set_color(cr, kAxisColors[a]);
      cairo_rectangle(cr, lx, kPosTop + 8, 14, 4);
      cairo_fill(cr);
      set_color(cr, kInk);
      draw_text(cr, lx + 18, kPosTop + 14, std::string(1, program::kSpcAxisLetters[a]), 12);
      lx += 50;
    }

    // Signals: a common time axis, one row each.
    const PlotFrame sf{{kLeft, kSigTop, kPlotW, rows * kRowPitch}, {0, t_end}, {0, 1}};
    double step = 0;
    set_color(cr, {0.85, 0.85, 0.85});
    cairo_set_line_width(cr, 1);
    for (double t : nice_ticks(sf.x, 10, step)) {
      cairo_move_to(cr, sf.to_px_x(t), kSigTop - 6);
      cairo_line_to(cr, sf.to_px_x(t), kSigTop + rows * kRowPitch);
      cairo_stroke(cr);
      set_color(cr, kInk);
      draw_text(cr, sf.to_px_x(t), kSigTop + rows * kRowPitch + 16, tick_label(t, step), 11, Align::Middle);
      set_color(cr, {0.85, 0.85, 0.85});
    }
    set_color(cr, kInk);
    draw_text(cr, kLeft + kPlotW / 2, kSigTop + rows * kRowPitch + 36, "t [s]", 12, Align::Middle);
    cairo_set_line_width(cr, 1.5);
    int i = 0;
    for (const auto& s : sigs) {
      const double y0 = kSigTop + i * kRowPitch;
      set_color(cr, kInk);
      draw_text(cr, kLeft - 8, y0 + kRowH / 2, s.name, 12, Align::End, Align::Middle, s.addr.output);
      set_color(cr, s.addr.output ? kOutColor : kInColor);
      draw_row(cr, tr, sf, y0 + kRowH, y0 + 4, [&](const SpcTraceRow& r) { return bit_of(r, s.addr); });
      ++i;
    }
    if (tr.record_select) {  // the line bits B0..B4 as a number where they change
      const double y0 = kSigTop + i * kRowPitch;
      set_color(cr, kInk);
      draw_text(cr, kLeft - 8, y0 + kRowH / 2, "LINE", 12, Align::End, Align::Middle);
      set_color(cr, kInColor);
      draw_row(cr, tr, sf, y0 + kRowH, y0 + 4, [](const SpcTraceRow& r) { return (r.in[0] & 0x1F) != 0; });
      int prev = -1;
      double last_x = -1e9;
      for (const auto& r : tr.rows) {
        const int line = r.in[0] & 0x1F;
        if (line == prev) continue;
        prev = line;
        const double x = sf.to_px_x(r.t_s);
        if (x - last_x < 18) continue;  // labels would overlap
        last_x = x;
        set_color(cr, kInk);
        draw_text(cr, x + 2, y0 + kRowH - 2, fmt::format("{}", line), 10);
      }
    }
  });
}

}  // namespace softmc::report
