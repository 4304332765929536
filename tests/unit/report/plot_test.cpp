// Run plots: SVG and PNG by extension, refusal of other formats, and a realistic picture to look at.
#include "report/plot.hpp"

#include <gtest/gtest.h>

#include <cairo.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "synthetic_trace.hpp"

using namespace softmc;
using namespace softmc::report;
using namespace softmc::report::testing;

namespace {
std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

Trace realistic_trace(const program::Program& prog) {
  return sample_program(prog, {.acc_mm_s2 = 800, .lag_tau_s = 0.008, .quantum_mm = 0.127});
}
}  // namespace

TEST(Plot, WritesSvg) {
  const auto prog = rounded_square();
  const std::string path = ::testing::TempDir() + "report_plot_test.svg";
  write_plot(path, prog, test_table(), realistic_trace(prog));
  const std::string svg = slurp(path);
  ASSERT_GT(svg.size(), 1000u);
  EXPECT_TRUE(svg.rfind("<?xml", 0) == 0 || svg.rfind("<svg", 0) == 0) << svg.substr(0, 40);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
}

TEST(Plot, WritesPng) {
  const auto prog = rounded_square();
  const std::string path = ::testing::TempDir() + "report_plot_test.png";
  write_plot(path, prog, test_table(), realistic_trace(prog));
  const std::string png = slurp(path);
  ASSERT_GT(png.size(), 1000u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
}

TEST(Plot, ExtensionIsCaseInsensitive) {
  const auto prog = rounded_square();
  const std::string path = ::testing::TempDir() + "report_plot_upper.PNG";
  write_plot(path, prog, test_table(), realistic_trace(prog));
  EXPECT_EQ(slurp(path).substr(0, 4), std::string("\x89PNG", 4));
}

TEST(Plot, OutputIsDeterministic) {
  const auto prog = rounded_square();
  const auto tr = realistic_trace(prog);
  for (const char* ext : {".png", ".svg"}) {
    const std::string a = ::testing::TempDir() + "report_plot_det_a" + ext;
    const std::string b = ::testing::TempDir() + "report_plot_det_b" + ext;
    write_plot(a, prog, test_table(), tr);
    write_plot(b, prog, test_table(), tr);
    EXPECT_EQ(slurp(a), slurp(b)) << ext;
  }
}

TEST(Plot, RefusesOtherExtensions) {
  const auto prog = rounded_square();
  EXPECT_THROW(write_plot(::testing::TempDir() + "plot.txt", prog, test_table(), Trace{}), std::runtime_error);
  EXPECT_THROW(write_plot(::testing::TempDir() + "plot", prog, test_table(), Trace{}), std::runtime_error);
}

TEST(Plot, UnwritableFileThrows) {
  const auto prog = rounded_square();
  EXPECT_THROW(write_plot("/nonexistent-dir/for/sure/plot.png", prog, test_table(), Trace{}), std::runtime_error);
  EXPECT_THROW(write_plot("/nonexistent-dir/for/sure/plot.svg", prog, test_table(), Trace{}), std::runtime_error);
}

TEST(Plot, EmptyTraceAndEmptyProgramStillDraw) {
  const std::string path = ::testing::TempDir() + "report_plot_empty.png";
  EXPECT_NO_THROW(write_plot(path, program::Program{}, machine::MachineConfig{}, Trace{}));
  EXPECT_EQ(slurp(path).substr(0, 4), std::string("\x89PNG", 4));
}

TEST(Plot, LargePartShowsTheWholeTable) {
  // A part spanning most of the table: no zoom.
  program::Program prog;
  prog.files = {"big.ngc"};
  prog.start = xy(0, 0);
  prog.instructions = {ins(program::Rapid{xy(20, 20)}),
                       ins(program::ToolSwitch{true}),
                       ins(program::Linear{xy(580, 20), 200}),
                       ins(program::Linear{xy(580, 380), 200}),
                       ins(program::Linear{xy(20, 20), 200}),
                       ins(program::ToolSwitch{false}),
                       ins(program::ProgramEnd{})};
  const std::string path = ::testing::TempDir() + "report_plot_big.png";
  write_plot(path, prog, test_table(), sample_program(prog, {.acc_mm_s2 = 2000, .lag_tau_s = 0.01}));
  EXPECT_EQ(slurp(path).substr(0, 4), std::string("\x89PNG", 4));
}

TEST(Plot, SmallPartFarFromTheStartZoomsOntoThePart) {
  // The rounded square moved to the middle of the table, started from the home corner: the rapids
  // would make the view a third of the table, so it shows the part and leaves them to the overview.
  auto prog = rounded_square();
  for (auto& in : prog.instructions) {
    auto shift = [](core::Vec& v) { v = v + xy(250, 150); };
    std::visit(
        [&](auto& op) {
          if constexpr (requires { op.end; }) shift(op.end);
          if constexpr (requires { op.center0; }) {
            op.center0 += 250;
            op.center1 += 150;
          }
        },
        in.op);
  }
  const std::string path = ::testing::TempDir() + "report_plot_far.png";
  write_plot(path, prog, test_table(), realistic_trace(prog));
  EXPECT_EQ(slurp(path).substr(0, 4), std::string("\x89PNG", 4));
}

namespace {
// Pixels of the event colour (kEvent: 0.55, 0.20, 0.65) in a PNG, by cairo's own reader.
int event_pixels(const std::string& png) {
  cairo_surface_t* img = cairo_image_surface_create_from_png(png.c_str());
  EXPECT_EQ(cairo_surface_status(img), CAIRO_STATUS_SUCCESS);
  cairo_surface_flush(img);
  const int w = cairo_image_surface_get_width(img), h = cairo_image_surface_get_height(img);
  const int stride = cairo_image_surface_get_stride(img);
  const unsigned char* d = cairo_image_surface_get_data(img);
  int n = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto px = reinterpret_cast<const std::uint32_t*>(d + y * stride)[x];  // ARGB32, opaque here
      const int r = (px >> 16) & 0xff, g = (px >> 8) & 0xff, b = px & 0xff;
      if (std::abs(r - 140) < 12 && std::abs(g - 51) < 12 && std::abs(b - 166) < 12) ++n;
    }
  cairo_surface_destroy(img);
  return n;
}
}  // namespace

// The PLC's signal writes of a run (--stimulus) are marked on the speed panel, and only there.
TEST(Plot, SignalEventsAreMarkedOnTheSpeedPanel) {
  const auto prog = rounded_square();
  const auto tr = realistic_trace(prog);
  const std::string plain = ::testing::TempDir() + "report_plot_plain.png";
  const std::string marked = ::testing::TempDir() + "report_plot_events.png";
  write_plot(plain, prog, test_table(), tr);
  write_plot(marked, prog, test_table(), tr, {{0.5, "hold"}, {1.0, "release"}, {tr.rows.back().t_s, "stop"}});
  EXPECT_EQ(event_pixels(plain), 0);
  EXPECT_GT(event_pixels(marked), 150);  // three dashed lines across the panel, and their labels
}
