// Drawing helpers for the run plots: data-to-pixel frames, nice ticks, labelled axes, text, envelopes.
#pragma once

#include <cairo.h>

#include <string>
#include <string_view>
#include <vector>

namespace softmc::report {

struct Rgb {
  double r = 0, g = 0, b = 0;
};

struct PlotRect {  // pixels, y down
  double x = 0, y = 0, w = 0, h = 0;
};

struct PlotRange {
  double lo = 0, hi = 1;
  double span() const { return hi - lo; }
};

// Maps data coordinates to a pixel rectangle (y up in data, down in pixels).
struct PlotFrame {
  PlotRect px;
  PlotRange x, y;
  double to_px_x(double v) const { return px.x + (v - x.lo) / x.span() * px.w; }
  double to_px_y(double v) const { return px.y + px.h - (v - y.lo) / y.span() * px.h; }
};

// Tick positions at 1, 2 or 5 × 10^k inside r, about `target` of them; `step` receives the spacing.
std::vector<double> nice_ticks(PlotRange r, int target, double& step);
// A tick label with as many decimals as the step needs ("0", "2.5", "0.01").
std::string tick_label(double v, double step);
// r widened by `fraction` of its span on both sides; a degenerate range gets a unit span.
PlotRange padded(PlotRange r, double fraction);

enum class Align { Start, Middle, End };

void set_color(cairo_t* cr, Rgb c, double alpha = 1.0);
// Text in the toy "sans-serif" font anchored at (x, y): `h` aligns horizontally; `v` = End puts the
// baseline on y, Middle centres the capitals on y, Start hangs them below y.
void draw_text(cairo_t* cr, double x, double y, std::string_view s, double size, Align h = Align::Start,
               Align v = Align::End, bool bold = false);
// Text rotated 90° counter-clockwise, centred on (x, y): for vertical axis labels.
void draw_text_vertical(cairo_t* cr, double x, double y, std::string_view s, double size);

// White plot area, light grid and labels at the ticks, axis labels, dark border. Data is drawn
// afterwards by the caller, clipped to f.px.
void draw_axes(cairo_t* cr, const PlotFrame& f, std::string_view x_label, std::string_view y_label);

// Minimum and maximum per pixel column of a time series, so that millions of samples draw as a few
// thousand segments that look the same as the full series.
class SeriesEnvelope {
 public:
  explicit SeriesEnvelope(const PlotFrame& f);
  void add(double t, double v);
  void stroke(cairo_t* cr) const;  // builds the path and strokes it with the current source and width

 private:
  struct Column {
    double first = 0, last = 0, lo = 0, hi = 0;
    bool used = false;
  };
  PlotFrame f_;
  std::vector<Column> cols_;
};

}  // namespace softmc::report
