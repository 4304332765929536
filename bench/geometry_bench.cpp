// Cost of one geometric query per segment kind: point(s), and frame(s) (point, tangent, curvature).
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "motion/geometry/bezier.hpp"
#include "motion/geometry/newton_polynomial.hpp"
#include "motion/geometry/nurbs.hpp"
#include "motion/geometry/polyline_smoothing.hpp"
#include "motion/geometry/segment.hpp"
#include "motion/geometry/segment_store.hpp"

using namespace softmc;

namespace {
core::Vec xy(double x, double y, double z = 0) {
  core::Vec v;
  v[0] = x;
  v[1] = y;
  v[2] = z;
  return v;
}

motion::Segment line() { return motion::make_line(xy(0, 0), xy(100, 40, 5)); }
motion::Segment helix() { return motion::make_arc(xy(10, 0), xy(10, 0, 5), 0, 1, 0, 0, 1); }
// A G-code arc whose end is off its circle by the program's rounding (R5 through 1 rad, its end to
// four decimals: 8 µm off): a slight spiral, whose angle at s is the root of a quadratic.
motion::Segment slight_spiral() { return motion::make_arc(xy(5, 0), xy(2.7015, 4.2074), 0, 1, 0, 0, 1); }
// A tiny arc 18 µm off on R0.5 through 0.1 rad: its dr/dφ is 3.6e-4 of the radius, past the
// quadratic's reach: Newton steps on the closed-form length.
motion::Segment notch_spiral() { return motion::make_arc(xy(0.5, 0), xy(0.49752, 0.04992), 0, 1, 0, 0, 1); }
// A tiny arc within the interpreter's allowance: r 0.01 → 0.037 mm, a few Newton steps.
motion::Segment strong_spiral() { return motion::make_arc(xy(10, 10), xy(10.047, 10), 0, 1, 10.01, 10, -1); }
motion::Segment cubic() { return motion::make_cubic_bezier(xy(0, 0), xy(30, 80), xy(90, -60), xy(100, 20, 5)); }
motion::Segment quarter_circle() {
  const std::vector<core::Vec> c{xy(30, 30), xy(30, 40), xy(20, 40)};
  const std::vector<double> w{1, std::sqrt(0.5), 1};
  return motion::nurbs_g5_2(c, w, 3).segments.at(0);
}
motion::Segment quintic_nurbs_piece() {
  const std::vector<core::Vec> c{xy(0, 0), xy(1, 3), xy(4, 4), xy(6, 1), xy(9, 2), xy(12, 0)};
  const std::vector<double> w{1, 0.5, 2, 1, 3, 1};
  return motion::nurbs_g5_2(c, w, 6).segments.at(0);
}
motion::Segment thesis_polynomial() {
  const std::vector<motion::Node2> n{{10, 11}, {40, 22}, {60, 20}, {90, 5}};
  return motion::newton_polynomial(n).segments.at(0);
}

// Walks the segment at a step that is not a multiple of anything in its tables.
template <motion::Segment (*Make)()>
void BM_Point(benchmark::State& state) {
  const motion::Segment s = Make();
  const double step = s.length / 997.3;
  double at = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(s.point(at));
    at += step;
    if (at > s.length) at -= s.length;
  }
}

template <motion::Segment (*Make)()>
void BM_Frame(benchmark::State& state) {
  const motion::Segment s = Make();
  const double step = s.length / 997.3;
  double at = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(s.frame(at));
    at += step;
    if (at > s.length) at -= s.length;
  }
}
}  // namespace

BENCHMARK(BM_Point<line>)->Name("GeometryPoint/Line");
BENCHMARK(BM_Point<helix>)->Name("GeometryPoint/Helix");
BENCHMARK(BM_Point<cubic>)->Name("GeometryPoint/CubicBezier");
BENCHMARK(BM_Point<quarter_circle>)->Name("GeometryPoint/NurbsQuarterCircle");
BENCHMARK(BM_Point<quintic_nurbs_piece>)->Name("GeometryPoint/QuinticNurbs");
BENCHMARK(BM_Point<thesis_polynomial>)->Name("GeometryPoint/NewtonThesis");
BENCHMARK(BM_Frame<helix>)->Name("GeometryFrame/Helix");
BENCHMARK(BM_Frame<slight_spiral>)->Name("GeometryFrame/SlightSpiral");
BENCHMARK(BM_Frame<notch_spiral>)->Name("GeometryFrame/NotchSpiral");
BENCHMARK(BM_Frame<strong_spiral>)->Name("GeometryFrame/StrongSpiral");
BENCHMARK(BM_Frame<cubic>)->Name("GeometryFrame/CubicBezier");
BENCHMARK(BM_Frame<thesis_polynomial>)->Name("GeometryFrame/NewtonThesis");

// Building one cubic Bézier segment (arc-length table, bounds, sampled maxima): what the smoothing of
// CAM line runs pays per line at load.
static void BM_BuildCubicBezier(benchmark::State& state) {
  double x = 0;
  for (auto _ : state) {
    const auto s = motion::make_cubic_bezier({x, 0, 0}, {x + 0.1, 0.01, 0.002}, {x + 0.2, 0.015, 0.003}, {x + 0.3, 0.02, 0.004});
    benchmark::DoNotOptimize(s.length);
    x += 1e-3;
  }
}
BENCHMARK(BM_BuildCubicBezier);

// Smooths pts at tolerance tol (turns up to 20° in a run, as the Channel sets it) every iteration,
// on one thread (the benchmark times the calling thread's CPU; BM_ChannelLoad times the load on
// every core); reported per programmed line.
static void smooth_per_line(benchmark::State& state, const std::vector<motion::Vec>& pts, double tol) {
  motion::PolylineSmoothing cfg;
  cfg.threads = 1;
  cfg.tolerance_mm = tol;
  cfg.max_turn_rad = 20 * 3.14159265358979323846 / 180;
  std::vector<std::vector<motion::Segment>> lines;
  for (auto _ : state) {
    motion::smooth_polyline(pts, cfg, lines);
    benchmark::DoNotOptimize(lines.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(pts.size() - 1));
}

// Smoothing a CAM polyline at load (polyline_smoothing.hpp): six raster passes over a surface with a
// wall (0.25 mm steps printed to 1 µm, the wall 4 mm high over 1 mm, as bench/smoothing_variety.py's
// kind 0), at P 0.09 (3D_Chips's P0.1) and 0.02: the wall's points are filtered less, point by point,
// over several rounds of checks.
static void BM_SmoothPolylineWall(benchmark::State& state) {
  std::vector<motion::Vec> pts;
  for (int row = 0; row < 6; ++row) {
    for (int i = 0; i <= 160; ++i) {
      const double x = 0.25 * (row % 2 ? 160 - i : i), y = 2.0 * row;
      const double z = -4 / (1 + std::exp(-(x - 20) / 0.25)) + 0.3 * std::sin(x * 0.5 + y);
      pts.push_back({std::round(x * 1000) / 1000, std::round(y * 1000) / 1000, std::round(z * 1000) / 1000});
    }
  }
  smooth_per_line(state, pts, state.range(0) / 1000.0);
}
BENCHMARK(BM_SmoothPolylineWall)->Arg(90)->Arg(20)->Unit(benchmark::kMillisecond);

// The smoothing's worst load found so far (the stop-27 review's): an R50 arc of 1 000 lines of 0.25 mm
// with every fourth point moved 0.05 mm aside, at P 0.005: most pieces leave P at every tier, and the
// run is split about two hundred times.
static void BM_SmoothPolylineJogs(benchmark::State& state) {
  std::vector<motion::Vec> pts;
  for (int k = 0; k <= 1000; ++k) {
    const double t = 0.25 * k / 50;
    pts.push_back({50 * std::sin(t), 50 * (1 - std::cos(t)) + (k % 4 == 2 ? 0.05 : 0.0), 0});
  }
  smooth_per_line(state, pts, 0.005);
}
BENCHMARK(BM_SmoothPolylineJogs)->Unit(benchmark::kMillisecond);

// Reading a smoothed piece back from the Channel's store (SegmentStore::get, in the cycle at every
// push of a piece to the planner): a wave of 0.1 mm lines in X and Z, its cubics read in turn.
static void BM_SegmentStoreGet(benchmark::State& state) {
  std::vector<motion::Vec> pts;
  for (int k = 0; k <= 2000; ++k) pts.push_back(xy(0.1 * k, 0, -1 + 0.5 * std::sin(0.02 * k)));
  std::vector<std::vector<motion::Segment>> lines;
  motion::smooth_polyline(pts, motion::PolylineSmoothing{}, lines);
  motion::SegmentStore store;
  for (const auto& l : lines)
    for (const auto& seg : l) store.push_back(seg);
  motion::Segment out;
  std::size_t i = 0;
  for (auto _ : state) {
    store.get(i, out);
    benchmark::DoNotOptimize(out.length);
    if (++i == store.size()) i = 0;
  }
}
BENCHMARK(BM_SegmentStoreGet);
