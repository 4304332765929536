// The run plot (T-6): the table with programmed and executed paths, then speed, acceleration and
// following error over time.
//
//   +--------------------------------------------+
//   | title: program, machine, cycle time, view  |
//   | +------------------------+  legend         |
//   | |  X-Y: travel outline,  |                 |
//   | |  cut / feed / rapid    |  overview of    |
//   | |  (equal aspect)        |  the table      |
//   | +------------------------+  (when zoomed)  |
//   | path speed over time                       |
//   | axis acceleration over time                |
//   | following error over time                  |
//   +--------------------------------------------+
#include "report/plot.hpp"

#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "report/plot_canvas.hpp"
#include "report/plot_output.hpp"
#include "report/programmed_path.hpp"

namespace softmc::report {

namespace {

constexpr double kWidth = 1000, kHeight = 1390;
constexpr PlotRect kXyArea{90, 78, 670, 620};  // the X-Y panel's plot area
constexpr double kSideX = 790, kSideW = 190;   // legend and overview column
constexpr double kTimeX = 90, kTimeW = 880, kTimeH = 150;
constexpr double kTimeTop = 770, kTimePitch = 205;  // first time panel, distance between panels
// Below this share of the table (larger of width and height fractions) the view zooms onto the part.
constexpr double kZoomBelow = 0.4;

constexpr Rgb kInk{0.15, 0.15, 0.15};
constexpr Rgb kTable{0.35, 0.35, 0.35};
constexpr Rgb kTableFill{0.965, 0.965, 0.95};
constexpr Rgb kProgrammed{0.70, 0.85, 1.0};
constexpr Rgb kCut{0.80, 0.12, 0.08};
constexpr Rgb kFeed{0.45, 0.45, 0.45};
constexpr Rgb kRapid{0.10, 0.30, 0.75};
constexpr Rgb kStart{0.10, 0.65, 0.20};
constexpr Rgb kEnd{0.85, 0.10, 0.10};
constexpr Rgb kSpeed{0.10, 0.10, 0.10};
constexpr Rgb kToolBand{1.0, 0.80, 0.55};
constexpr Rgb kEvent{0.55, 0.20, 0.65};
constexpr std::array<Rgb, core::kMaxAxes> kAxisColors{{{0.12, 0.47, 0.71},
                                                       {0.90, 0.45, 0.05},
                                                       {0.17, 0.63, 0.17},
                                                       {0.58, 0.40, 0.74},
                                                       {0.55, 0.34, 0.29},
                                                       {0.89, 0.47, 0.76},
                                                       {0.50, 0.50, 0.50},
                                                       {0.74, 0.74, 0.13},
                                                       {0.09, 0.75, 0.81}}};

struct Box {  // an axis-aligned box in the X-Y plane, mm; empty until a point is added
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0;
  double x1 = -x0, y1 = -x0;
  bool empty() const { return !(x0 <= x1 && y0 <= y1); }
  void add(double x, double y) {
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
  void add(const Box& b) {
    if (b.empty()) return;
    add(b.x0, b.y0);
    add(b.x1, b.y1);
  }
  double w() const { return x1 - x0; }
  double h() const { return y1 - y0; }
};

// Everything the panels share: inputs, the two plotted axes, the programmed path.
struct Scene {
  const program::Program& prog;
  const machine::MachineConfig& cfg;
  const Trace& trace;
  ProgrammedPath path;
  std::size_t ax0 = 0, ax1 = 1;  // horizontal and vertical axis of the X-Y panel
  Box travel;                    // the table's travel; empty if not configured
  Box all;                       // start, programmed path and commanded positions
  Box part;                      // feed moves only (programmed and commanded): the part itself
  bool zoomed = false;           // the view is the part, not the table
  bool rapids_cut_off = false;   // ... and leaves out the rapids to and from it
  double t_end_s = 0;
};

const machine::AxisConfig* axis_config(const machine::MachineConfig& cfg, std::size_t index) {
  for (const auto& a : cfg.axes)
    if (a.index == index) return &a;
  return nullptr;
}

std::vector<std::size_t> plotted_axes(const Trace& t) {
  std::vector<std::size_t> axes;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i)
    if (t.axes & core::axis_bit(i)) axes.push_back(i);
  return axes;
}

// The axes whose command changes during the run (all of them if none does): an axis standing
// still would only add a flat line and its limit marks to the time panels.
std::vector<std::size_t> moving_axes(const Trace& t) {
  std::vector<std::size_t> moved;
  for (std::size_t i : plotted_axes(t))
    if (std::any_of(t.rows.begin(), t.rows.end(), [&](const TraceRow& r) { return r.cmd[i] != t.rows[0].cmd[i]; }))
      moved.push_back(i);
  return moved.empty() ? plotted_axes(t) : moved;
}

Scene make_scene(const program::Program& prog, const machine::MachineConfig& cfg, const Trace& trace) {
  Scene s{prog, cfg, trace, programmed_path(prog)};
  // X and Y when the machine has them, else its first two axes.
  const auto axes = plotted_axes(trace);
  const bool has_xy = (trace.axes & core::axis_bit(0)) && (trace.axes & core::axis_bit(1));
  if (!has_xy && axes.size() >= 2) {
    s.ax0 = axes[0];
    s.ax1 = axes[1];
  } else if (!has_xy && axes.size() == 1) {
    s.ax0 = axes[0];
    s.ax1 = axes[0] == 1 ? 0 : 1;
  }
  const auto* a0 = axis_config(cfg, s.ax0);
  const auto* a1 = axis_config(cfg, s.ax1);
  if (a0 && a1 && a0->max_mm > a0->min_mm && a1->max_mm > a1->min_mm) {
    s.travel.add(a0->min_mm, a1->min_mm);
    s.travel.add(a0->max_mm, a1->max_mm);
  }
  s.all.add(prog.start[s.ax0], prog.start[s.ax1]);
  for (const auto& m : s.path.moves) {
    Box& b = m.kind == MoveKind::Rapid ? s.all : s.part;
    core::Vec lo, hi;
    s.path.box(m, lo, hi);
    b.add(lo[s.ax0], lo[s.ax1]);
    b.add(hi[s.ax0], hi[s.ax1]);
  }
  for (const auto& r : trace.rows) (r.moving && !r.rapid ? s.part : s.all).add(r.cmd[s.ax0], r.cmd[s.ax1]);
  s.all.add(s.part);
  if (s.part.empty()) s.part = s.all;
  s.t_end_s = trace.rows.empty() ? 0.0 : trace.rows.back().t_s;
  return s;
}

// Largest share of `full` that `b` covers along either axis.
double share(const Box& b, const Box& full) {
  return std::max(b.w() / std::max(full.w(), 1e-9), b.h() / std::max(full.h(), 1e-9));
}

// The X-Y view: the whole table, or the part with a margin when it would be lost on the table
// (a 40 mm part on a 600 × 400 table). Rapids from a distant start are left out of a zoomed view
// when they would shrink the part to less than half of it; the overview still shows them.
PlotFrame xy_frame(Scene& s) {
  Box full = s.travel;
  full.add(s.all);
  const bool part_only = share(s.part, s.all) < 0.5;
  const Box& focus = part_only ? s.part : s.all;
  PlotRange x{full.x0, full.x1}, y{full.y0, full.y1};
  if (s.travel.empty() || share(focus, full) < kZoomBelow) {
    s.zoomed = !s.travel.empty();
    s.rapids_cut_off = s.zoomed && part_only;
    // The margin scales with the part but never collapses: a point-like part still gets 2 mm around it.
    const double m = std::max(0.08 * std::max(focus.w(), focus.h()), 2.0);
    x = {focus.x0 - m, focus.x1 + m};
    y = {focus.y0 - m, focus.y1 + m};
  } else {
    x = padded(x, 0.03);
    y = padded(y, 0.03);
  }
  // Equal aspect: one mm is the same number of pixels both ways; the looser range grows about its middle.
  const PlotRect& a = kXyArea;
  const double scale = std::min(a.w / x.span(), a.h / y.span());
  const double xc = (x.lo + x.hi) / 2, yc = (y.lo + y.hi) / 2;
  x = {xc - a.w / scale / 2, xc + a.w / scale / 2};
  y = {yc - a.h / scale / 2, yc + a.h / scale / 2};
  return {a, x, y};
}

enum class StepKind { Cut, Feed, Rapid };

StepKind step_kind(const TraceRow& r) {
  if (r.moving && r.rapid) return StepKind::Rapid;
  if (r.moving && r.tool_on) return StepKind::Cut;
  return StepKind::Feed;  // includes any standstill drift, drawn thin
}

void set_step_style(cairo_t* cr, StepKind k, double scale = 1.0) {
  static const double kDash[] = {8, 6};
  cairo_set_dash(cr, nullptr, 0, 0);
  switch (k) {
    case StepKind::Cut:
      set_color(cr, kCut);
      cairo_set_line_width(cr, 2.6 * scale);
      break;
    case StepKind::Feed:
      set_color(cr, kFeed);
      cairo_set_line_width(cr, 1.0 * scale);
      break;
    case StepKind::Rapid:
      set_color(cr, kRapid);
      cairo_set_line_width(cr, 1.3 * scale);
      cairo_set_dash(cr, kDash, 2, 0);
      break;
  }
}

// Commanded positions of one kind of step, as polylines with points at least `min_px` apart: a
// million cycles become as many points as the picture can show.
void stroke_trace(cairo_t* cr, const Scene& s, const PlotFrame& f, StepKind kind, double min_px) {
  const auto& rows = s.trace.rows;
  bool open = false;
  double lx = 0, ly = 0, px = 0, py = 0;  // last emitted point, last seen point
  auto flush = [&] {
    if (!open) return;
    if (px != lx || py != ly) cairo_line_to(cr, px, py);
    cairo_stroke(cr);
    open = false;
  };
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const TraceRow& r = rows[i];
    const TraceRow& p = rows[i - 1];
    const bool moved = r.cmd[s.ax0] != p.cmd[s.ax0] || r.cmd[s.ax1] != p.cmd[s.ax1];
    if (!moved || step_kind(r) != kind) {
      flush();
      continue;
    }
    const double x = f.to_px_x(r.cmd[s.ax0]), y = f.to_px_y(r.cmd[s.ax1]);
    if (!open) {
      lx = f.to_px_x(p.cmd[s.ax0]);
      ly = f.to_px_y(p.cmd[s.ax1]);
      cairo_move_to(cr, lx, ly);
      open = true;
    }
    px = x;
    py = y;
    if (std::hypot(x - lx, y - ly) >= min_px) {
      cairo_line_to(cr, x, y);
      lx = x;
      ly = y;
    }
  }
  flush();
}

// The programmed feed moves, sampled finely enough that an arc looks round at this scale.
void stroke_programmed(cairo_t* cr, const Scene& s, const PlotFrame& f) {
  const double mm_per_px = f.x.span() / f.px.w;
  for (const auto& m : s.path.moves) {
    if (m.kind == MoveKind::Rapid) continue;
    const motion::Segment seg = s.path.segment(m);
    int n = 1;
    if (seg.kind != motion::SegmentKind::Line)  // arcs and curves (Bézier, NURBS) are sampled finely
      n = std::clamp(static_cast<int>(std::ceil(seg.length / (2 * mm_per_px))), 8, 20000);
    for (int k = 0; k <= n; ++k) {
      const core::Vec p = seg.point(seg.length * k / n);
      if (k == 0)
        cairo_move_to(cr, f.to_px_x(p[s.ax0]), f.to_px_y(p[s.ax1]));
      else
        cairo_line_to(cr, f.to_px_x(p[s.ax0]), f.to_px_y(p[s.ax1]));
    }
  }
  cairo_stroke(cr);
}

void draw_travel(cairo_t* cr, const Scene& s, const PlotFrame& f, bool fill) {
  if (s.travel.empty()) return;
  const double x0 = f.to_px_x(s.travel.x0), x1 = f.to_px_x(s.travel.x1);
  const double y0 = f.to_px_y(s.travel.y1), y1 = f.to_px_y(s.travel.y0);
  cairo_rectangle(cr, x0, y0, x1 - x0, y1 - y0);
  if (fill) {
    set_color(cr, kTableFill);
    cairo_fill_preserve(cr);
  }
  set_color(cr, kTable);
  cairo_set_line_width(cr, 1.6);
  cairo_stroke(cr);
}

core::Vec start_position(const Scene& s) { return s.trace.rows.empty() ? s.prog.start : s.trace.rows.front().cmd; }
core::Vec end_position(const Scene& s) { return s.trace.rows.empty() ? s.path.end : s.trace.rows.back().cmd; }

void draw_start_marker(cairo_t* cr, double x, double y, double r) {
  cairo_new_sub_path(cr);
  cairo_arc(cr, x, y, r, 0, 2 * std::numbers::pi);
  set_color(cr, kStart);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_set_line_width(cr, 1.2);
  cairo_stroke(cr);
}

void draw_end_marker(cairo_t* cr, double x, double y, double half) {
  cairo_rectangle(cr, x - half, y - half, 2 * half, 2 * half);
  set_color(cr, kEnd);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_set_line_width(cr, 1.2);
  cairo_stroke(cr);
}

std::string axis_name(std::size_t i) { return std::string(1, core::letter(i)); }

void draw_xy_panel(cairo_t* cr, const Scene& s, const PlotFrame& f) {
  draw_axes(cr, f, axis_name(s.ax0) + " (mm)", axis_name(s.ax1) + " (mm)");
  cairo_save(cr);
  cairo_rectangle(cr, f.px.x, f.px.y, f.px.w, f.px.h);
  cairo_clip(cr);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  draw_travel(cr, s, f, true);

  set_color(cr, kProgrammed);
  cairo_set_line_width(cr, 7);
  stroke_programmed(cr, s, f);

  for (StepKind k : {StepKind::Rapid, StepKind::Feed, StepKind::Cut}) {
    set_step_style(cr, k);
    stroke_trace(cr, s, f, k, 0.7);
  }
  cairo_set_dash(cr, nullptr, 0, 0);
  const core::Vec a = start_position(s), b = end_position(s);
  draw_start_marker(cr, f.to_px_x(a[s.ax0]), f.to_px_y(a[s.ax1]), 7);  // larger: visible around an end on it
  draw_end_marker(cr, f.to_px_x(b[s.ax0]), f.to_px_y(b[s.ax1]), 4.5);
  cairo_restore(cr);
}

void draw_legend(cairo_t* cr, double x, double y) {
  set_color(cr, kInk);
  draw_text(cr, x, y, "Legend", 13, Align::Start, Align::End, true);
  const double sample = 34;
  auto entry = [&](double row_y, const std::string& label) {
    set_color(cr, kInk);
    draw_text(cr, x + sample + 10, row_y, label, 12, Align::Start, Align::Middle);
  };
  auto line_entry = [&](double row_y, const std::string& label, auto style) {
    cairo_save(cr);
    style();
    cairo_move_to(cr, x, row_y);
    cairo_line_to(cr, x + sample, row_y);
    cairo_stroke(cr);
    cairo_restore(cr);
    entry(row_y, label);
  };
  double yy = y + 22;
  line_entry(yy, "cut (tool on)", [&] { set_step_style(cr, StepKind::Cut); });
  yy += 22;
  line_entry(yy, "feed, tool off", [&] { set_step_style(cr, StepKind::Feed); });
  yy += 22;
  line_entry(yy, "rapid", [&] { set_step_style(cr, StepKind::Rapid); });
  yy += 22;
  line_entry(yy, "programmed path", [&] {
    set_color(cr, kProgrammed);
    cairo_set_line_width(cr, 7);
  });
  yy += 22;
  line_entry(yy, "table travel", [&] {
    set_color(cr, kTable);
    cairo_set_line_width(cr, 1.6);
  });
  yy += 24;
  draw_start_marker(cr, x + sample / 2, yy, 7);
  entry(yy, "start");
  yy += 22;
  draw_end_marker(cr, x + sample / 2, yy, 4.5);
  entry(yy, "end");
}

// A small picture of the whole table with the zoomed view marked, so the part's place is not lost.
void draw_overview(cairo_t* cr, const Scene& s, const PlotFrame& view, double top) {
  Box full = s.travel;
  full.add(s.all);
  const double pad = 0.04 * std::max(full.w(), full.h());
  const PlotRange x{full.x0 - pad, full.x1 + pad}, y{full.y0 - pad, full.y1 + pad};
  const double scale = std::min(kSideW / x.span(), 170.0 / y.span());
  const PlotRect r{kSideX, top + 10, x.span() * scale, y.span() * scale};
  const PlotFrame f{r, x, y};
  set_color(cr, kInk);
  draw_text(cr, kSideX, top, "Overview (whole table)", 13, Align::Start, Align::End, true);
  cairo_save(cr);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_rectangle(cr, r.x, r.y, r.w, r.h);
  cairo_fill(cr);
  draw_travel(cr, s, f, true);
  for (StepKind k : {StepKind::Rapid, StepKind::Feed, StepKind::Cut}) {
    set_step_style(cr, k, 0.6);
    stroke_trace(cr, s, f, k, 0.7);
  }
  cairo_set_dash(cr, nullptr, 0, 0);
  // The zoomed view's extent, at least a few pixels so that it stays visible.
  const double vx0 = f.to_px_x(view.x.lo), vx1 = f.to_px_x(view.x.hi);
  const double vy0 = f.to_px_y(view.y.hi), vy1 = f.to_px_y(view.y.lo);
  const double cx = (vx0 + vx1) / 2, cy = (vy0 + vy1) / 2;
  const double w = std::max(vx1 - vx0, 6.0), h = std::max(vy1 - vy0, 6.0);
  cairo_rectangle(cr, cx - w / 2, cy - h / 2, w, h);
  set_color(cr, kEnd);
  cairo_set_line_width(cr, 1.5);
  cairo_stroke(cr);
  cairo_restore(cr);
  set_color(cr, kInk);
  draw_text(cr, kSideX, r.y + r.h + 16, fmt::format("table {:g} × {:g} mm", s.travel.w(), s.travel.h()), 11);
  set_color(cr, kEnd);
  draw_text(cr, kSideX, r.y + r.h + 32, "red: area shown left", 11);
}

PlotFrame time_frame(const Scene& s, int panel, PlotRange y) {
  const PlotRect r{kTimeX, kTimeTop + panel * kTimePitch, kTimeW, kTimeH};
  return {r, {0.0, s.t_end_s > 0 ? s.t_end_s : 1.0}, y};
}

void panel_title(cairo_t* cr, const PlotFrame& f, const std::string& title) {
  set_color(cr, kInk);
  draw_text(cr, f.px.x, f.px.y - 8, title, 13, Align::Start, Align::End, true);
}

// Coloured axis letters at the top right of a panel.
void axis_key(cairo_t* cr, const PlotFrame& f, const std::vector<std::size_t>& axes) {
  double x = f.px.x + f.px.w;
  for (auto it = axes.rbegin(); it != axes.rend(); ++it) {
    const double w = 34;
    x -= w;
    cairo_move_to(cr, x, f.px.y - 12);
    cairo_line_to(cr, x + 14, f.px.y - 12);
    set_color(cr, kAxisColors[*it]);
    cairo_set_line_width(cr, 2.5);
    cairo_stroke(cr);
    set_color(cr, kInk);
    draw_text(cr, x + 17, f.px.y - 12, axis_name(*it), 12, Align::Start, Align::Middle);
  }
}

void clip_to(cairo_t* cr, const PlotFrame& f) {
  cairo_rectangle(cr, f.px.x, f.px.y, f.px.w, f.px.h);
  cairo_clip(cr);
}

void draw_speed_panel(cairo_t* cr, const Scene& s) {
  double v_max = 0, v_feed = 0;
  for (const auto& r : s.trace.rows) {
    v_max = std::max(v_max, r.path_v);
    if (r.moving && !r.rapid) v_feed = std::max(v_feed, r.path_v);
  }
  // Rapids often run ten times faster than the cut; the cut's profile is what the plot is for.
  const bool clipped = v_feed > 0 && v_feed < 0.25 * v_max;
  const double top = clipped ? v_feed * 1.6 : (v_max > 0 ? v_max * 1.08 : 1.0);
  const PlotFrame f = time_frame(s, 0, {0.0, top});
  draw_axes(cr, f, "time (s)", "path speed (mm/s)");
  panel_title(cr, f,
              clipped ? fmt::format("Path speed (scale fits the feed moves; rapids up to {:.1f} mm/s clipped)", v_max)
                      : std::string("Path speed"));
  cairo_save(cr);
  clip_to(cr, f);
  // Where the tool is on, as light bands behind the curve.
  set_color(cr, kToolBand, 0.55);
  const auto& rows = s.trace.rows;
  for (std::size_t i = 0; i < rows.size();) {
    if (!rows[i].tool_on) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j + 1 < rows.size() && rows[j + 1].tool_on) ++j;
    const double t0 = i == 0 ? 0.0 : rows[i - 1].t_s;
    const double x0 = f.to_px_x(t0), x1 = f.to_px_x(rows[j].t_s);
    cairo_rectangle(cr, x0, f.px.y, std::max(x1 - x0, 0.5), f.px.h);
    i = j + 1;
  }
  cairo_fill(cr);
  SeriesEnvelope env(f);
  for (const auto& r : rows) env.add(r.t_s, r.path_v);
  set_color(cr, kSpeed);
  cairo_set_line_width(cr, 1.4);
  env.stroke(cr);
  cairo_restore(cr);
  // Key, top right.
  const double ky = f.px.y - 12, kx = f.px.x + f.px.w;
  cairo_rectangle(cr, kx - 90, ky - 6, 14, 12);
  set_color(cr, kToolBand);
  cairo_fill(cr);
  set_color(cr, kInk);
  draw_text(cr, kx - 72, ky, "tool on", 12, Align::Start, Align::Middle);
  cairo_move_to(cr, kx - 210, ky);
  cairo_line_to(cr, kx - 196, ky);
  set_color(cr, kSpeed);
  cairo_set_line_width(cr, 1.6);
  cairo_stroke(cr);
  set_color(cr, kInk);
  draw_text(cr, kx - 192, ky, "commanded", 12, Align::Start, Align::Middle);
}

// The signal writes of the run (--stimulus) as dashed lines across the speed panel, each labelled
// at its top; labels step down in three rows so that writes close in time stay readable.
void draw_events(cairo_t* cr, const Scene& s, const std::vector<PlotEvent>& events) {
  if (events.empty()) return;
  const PlotFrame f = time_frame(s, 0, {0.0, 1.0});
  cairo_save(cr);
  clip_to(cr, f);
  const double dashes[] = {4.0, 3.0};
  int row = 0;
  for (const auto& e : events) {
    const double x = std::floor(f.to_px_x(e.t_s)) + 0.5;  // on a pixel's centre: one crisp pixel wide
    set_color(cr, kEvent);
    cairo_set_dash(cr, dashes, 2, 0);
    cairo_set_line_width(cr, 1.0);
    cairo_move_to(cr, x, f.px.y);
    cairo_line_to(cr, x, f.px.y + f.px.h);
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
    const bool right = x > f.px.x + f.px.w - 80;  // near the end: the label left of its line
    draw_text(cr, right ? x - 3 : x + 3, f.px.y + 12 + 14 * row, e.label, 11, right ? Align::End : Align::Start,
              Align::Middle);
    row = (row + 1) % 3;
  }
  cairo_restore(cr);
}

// Per-axis acceleration from second differences of the setpoints, as the trace checker sees it;
// dashed lines mark each axis's configured limit.
void draw_acc_panel(cairo_t* cr, const Scene& s, const std::vector<std::size_t>& axes) {
  const auto& rows = s.trace.rows;
  const double dt = s.trace.period_s;
  auto acc = [&](std::size_t r, std::size_t i) {
    return (rows[r + 1].cmd[i] - 2 * rows[r].cmd[i] + rows[r - 1].cmd[i]) / (dt * dt);
  };
  double a_max = 0, a_limit = 0;
  for (std::size_t i : axes)
    if (const auto* a = axis_config(s.cfg, i)) a_limit = std::max(a_limit, a->max_acc_mm_s2);
  if (dt > 0)
    for (std::size_t r = 1; r + 1 < rows.size(); ++r)
      for (std::size_t i : axes) a_max = std::max(a_max, std::abs(acc(r, i)));
  // A single spike (a velocity step at a junction) would flatten every profile: clip the scale and say so.
  const bool clipped = a_limit > 0 && a_max > 3 * a_limit;
  const double top = clipped ? 1.5 * a_limit : std::max({a_max, a_limit, 1e-9}) * 1.1;
  const PlotFrame f = time_frame(s, 1, {-top, top});
  draw_axes(cr, f, "time (s)", "acceleration (mm/s²)");
  panel_title(cr, f,
              clipped ? fmt::format("Axis acceleration (scale clipped; peak {:.0f} mm/s²)", a_max)
                      : std::string("Axis acceleration (second difference of the setpoints)"));
  axis_key(cr, f, axes);
  cairo_save(cr);
  clip_to(cr, f);
  static const double kDash[] = {4, 4};
  for (std::size_t i : axes) {
    const auto* a = axis_config(s.cfg, i);
    if (!a || a->max_acc_mm_s2 <= 0) continue;
    set_color(cr, kAxisColors[i], 0.8);
    cairo_set_line_width(cr, 1);
    cairo_set_dash(cr, kDash, 2, 0);
    for (double v : {a->max_acc_mm_s2, -a->max_acc_mm_s2}) {
      cairo_move_to(cr, f.px.x, f.to_px_y(v));
      cairo_line_to(cr, f.px.x + f.px.w, f.to_px_y(v));
    }
    cairo_stroke(cr);
  }
  cairo_set_dash(cr, nullptr, 0, 0);
  if (dt > 0) {
    for (std::size_t i : axes) {
      SeriesEnvelope env(f);
      for (std::size_t r = 1; r + 1 < rows.size(); ++r) env.add(rows[r].t_s, acc(r, i));
      set_color(cr, kAxisColors[i]);
      cairo_set_line_width(cr, 1.3);
      env.stroke(cr);
    }
  }
  cairo_restore(cr);
}

void draw_ferr_panel(cairo_t* cr, const Scene& s, const std::vector<std::size_t>& axes) {
  const auto& rows = s.trace.rows;
  double e_max = 0;
  for (const auto& r : rows)
    for (std::size_t i : axes) e_max = std::max(e_max, std::abs(r.cmd[i] - r.act[i]));
  const double top = e_max > 0 ? e_max * 1.1 : 0.01;
  const PlotFrame f = time_frame(s, 2, {-top, top});
  draw_axes(cr, f, "time (s)", "following error (mm)");
  panel_title(cr, f, "Following error (setpoint − encoder position)");
  axis_key(cr, f, axes);
  cairo_save(cr);
  clip_to(cr, f);
  for (std::size_t i : axes) {
    SeriesEnvelope env(f);
    for (const auto& r : rows) env.add(r.t_s, r.cmd[i] - r.act[i]);
    set_color(cr, kAxisColors[i]);
    cairo_set_line_width(cr, 1.3);
    env.stroke(cr);
  }
  cairo_restore(cr);
}

void draw_title(cairo_t* cr, const Scene& s) {
  const std::string program = s.prog.files.empty() ? std::string("(program)") : s.prog.files[0];
  set_color(cr, kInk);
  draw_text(cr, kXyArea.x - 60, 26, fmt::format("{}  ·  {}  ·  cycle time {:.3f} s", program, s.cfg.name, s.t_end_s),
            17, Align::Start, Align::End, true);
  const std::string view = !s.zoomed          ? "view: whole table"
                           : s.rapids_cut_off ? "view: part (table outline and rapids partly shown; overview right)"
                                              : "view: part (table outline partly shown; overview right)";
  // As in the summary: a row at t = 0 is the state before the first cycle.
  const auto cycles =
      std::count_if(s.trace.rows.begin(), s.trace.rows.end(), [](const TraceRow& r) { return r.t_s > 0; });
  draw_text(cr, kXyArea.x - 60, 48, fmt::format("{}   ·   {} cycles of {:g} ms", view, cycles, s.trace.period_s * 1e3),
            12.5);
}

void draw(cairo_t* cr, const program::Program& prog, const machine::MachineConfig& cfg, const Trace& trace,
          const std::vector<PlotEvent>& events) {
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  Scene s = make_scene(prog, cfg, trace);
  const PlotFrame xy = xy_frame(s);
  draw_title(cr, s);
  draw_xy_panel(cr, s, xy);
  draw_legend(cr, kSideX, kXyArea.y + 12);
  if (s.zoomed) draw_overview(cr, s, xy, kXyArea.y + 250);
  const auto axes = moving_axes(trace);
  draw_speed_panel(cr, s);
  draw_events(cr, s, events);
  draw_acc_panel(cr, s, axes);
  draw_ferr_panel(cr, s, axes);
}

}  // namespace

void write_plot(const std::string& path, const program::Program& prog, const machine::MachineConfig& cfg,
                const Trace& trace, const std::vector<PlotEvent>& events) {
  render_to_file(path, kWidth, kHeight, [&](cairo_t* cr) { draw(cr, prog, cfg, trace, events); });
}

}  // namespace softmc::report
