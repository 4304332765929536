// Axes, ticks, text and series envelopes drawn with Cairo.
#include "report/plot_canvas.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace softmc::report {

namespace {
constexpr Rgb kGrid{0.88, 0.88, 0.88};
constexpr Rgb kInk{0.15, 0.15, 0.15};
constexpr double kTickFont = 11;
constexpr double kLabelFont = 12.5;
}  // namespace

std::vector<double> nice_ticks(PlotRange r, int target, double& step) {
  // The 1-2-5 step whose tick count comes closest to the target.
  const double raw = r.span() / std::max(1, target);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  step = mag;
  double best = std::numeric_limits<double>::infinity();
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    const double miss = std::abs(r.span() / (m * mag) - target);
    if (miss < best) {
      best = miss;
      step = m * mag;
    }
  }
  std::vector<double> ticks;
  for (double k = std::ceil(r.lo / step - 1e-9); k * step <= r.hi + step * 1e-9; k += 1) {
    const double v = k * step;
    ticks.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);  // no "-0"
  }
  return ticks;
}

std::string tick_label(double v, double step) {
  const int decimals = std::clamp(static_cast<int>(std::ceil(-std::log10(step) - 1e-9)), 0, 9);
  return fmt::format("{:.{}f}", v, decimals);
}

PlotRange padded(PlotRange r, double fraction) {
  if (!(r.span() > 0)) {
    const double half = std::max(std::abs(r.lo) * 0.1, 0.5);
    return {r.lo - half, r.hi + half};
  }
  const double m = r.span() * fraction;
  return {r.lo - m, r.hi + m};
}

void set_color(cairo_t* cr, Rgb c, double alpha) { cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha); }

void draw_text(cairo_t* cr, double x, double y, std::string_view s, double size, Align h, Align v, bool bold) {
  const std::string str(s);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t e;
  cairo_text_extents(cr, str.c_str(), &e);
  double dx = -e.x_bearing;
  if (h == Align::Middle) dx = -e.x_bearing - e.width / 2;
  if (h == Align::End) dx = -e.x_bearing - e.width;
  // Vertical placement uses the capital height (not this string's ink) so labels of one row align.
  const double cap = 0.72 * size;
  double dy = 0;
  if (v == Align::Middle) dy = cap / 2;
  if (v == Align::Start) dy = cap;
  cairo_move_to(cr, x + dx, y + dy);
  cairo_show_text(cr, str.c_str());
}

void draw_text_vertical(cairo_t* cr, double x, double y, std::string_view s, double size) {
  cairo_save(cr);
  cairo_translate(cr, x, y);
  cairo_rotate(cr, -std::numbers::pi / 2);
  draw_text(cr, 0, 0, s, size, Align::Middle, Align::Middle);
  cairo_restore(cr);
}

void draw_axes(cairo_t* cr, const PlotFrame& f, std::string_view x_label, std::string_view y_label) {
  const PlotRect& p = f.px;
  cairo_save(cr);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_rectangle(cr, p.x, p.y, p.w, p.h);
  cairo_fill(cr);

  double xs = 0, ys = 0;
  const auto xt = nice_ticks(f.x, std::max(2, static_cast<int>(p.w / 80)), xs);
  const auto yt = nice_ticks(f.y, std::max(4, static_cast<int>(p.h / 45)), ys);
  cairo_set_line_width(cr, 1);
  set_color(cr, kGrid);
  for (double v : xt) {
    const double x = std::round(f.to_px_x(v)) + 0.5;
    cairo_move_to(cr, x, p.y);
    cairo_line_to(cr, x, p.y + p.h);
  }
  for (double v : yt) {
    const double y = std::round(f.to_px_y(v)) + 0.5;
    cairo_move_to(cr, p.x, y);
    cairo_line_to(cr, p.x + p.w, y);
  }
  cairo_stroke(cr);

  set_color(cr, kInk);
  for (double v : xt) {
    const double x = f.to_px_x(v);
    cairo_move_to(cr, x, p.y + p.h);
    cairo_line_to(cr, x, p.y + p.h + 4);
    cairo_stroke(cr);
    draw_text(cr, x, p.y + p.h + 7, tick_label(v, xs), kTickFont, Align::Middle, Align::Start);
  }
  double widest = 0;
  for (double v : yt) {
    const double y = f.to_px_y(v);
    cairo_move_to(cr, p.x - 4, y);
    cairo_line_to(cr, p.x, y);
    cairo_stroke(cr);
    const std::string lbl = tick_label(v, ys);
    draw_text(cr, p.x - 7, y, lbl, kTickFont, Align::End, Align::Middle);
    cairo_text_extents_t e;
    cairo_text_extents(cr, lbl.c_str(), &e);
    widest = std::max(widest, e.x_advance);
  }
  draw_text(cr, p.x + p.w / 2, p.y + p.h + 34, x_label, kLabelFont, Align::Middle, Align::End);
  draw_text_vertical(cr, p.x - 14 - widest - kLabelFont / 2, p.y + p.h / 2, y_label, kLabelFont);

  cairo_set_line_width(cr, 1);
  cairo_rectangle(cr, std::round(p.x) + 0.5, std::round(p.y) + 0.5, std::round(p.w), std::round(p.h));
  cairo_stroke(cr);
  cairo_restore(cr);
}

SeriesEnvelope::SeriesEnvelope(const PlotFrame& f)
    : f_(f), cols_(static_cast<std::size_t>(std::max(1.0, std::ceil(f.px.w)))) {}

void SeriesEnvelope::add(double t, double v) {
  if (!std::isfinite(v)) return;
  const double c = (t - f_.x.lo) / f_.x.span() * static_cast<double>(cols_.size());
  if (!(c >= 0) || c > static_cast<double>(cols_.size())) return;
  Column& col = cols_[std::min(cols_.size() - 1, static_cast<std::size_t>(c))];
  if (!col.used) {
    col = {v, v, v, v, true};
    return;
  }
  col.last = v;
  col.lo = std::min(col.lo, v);
  col.hi = std::max(col.hi, v);
}

void SeriesEnvelope::stroke(cairo_t* cr) const {
  bool started = false;
  for (std::size_t i = 0; i < cols_.size(); ++i) {
    const Column& c = cols_[i];
    if (!c.used) continue;
    const double x = f_.px.x + static_cast<double>(i) + 0.5;
    auto to = [&](double v) {
      if (started) {
        cairo_line_to(cr, x, f_.to_px_y(v));
      } else {
        cairo_move_to(cr, x, f_.to_px_y(v));
        started = true;
      }
    };
    to(c.first);
    if (c.lo != c.hi) {
      to(c.first - c.lo < c.hi - c.first ? c.lo : c.hi);
      to(c.first - c.lo < c.hi - c.first ? c.hi : c.lo);
    }
    to(c.last);
  }
  if (started) cairo_stroke(cr);
}

}  // namespace softmc::report
