// Curvature-continuous smoothing of CAM polylines: runs, B-spline pieces, the tolerance check.
#include "motion/geometry/polyline_smoothing.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/ordered_parallel.hpp"
#include "motion/geometry/bezier.hpp"

namespace softmc::motion {

namespace {

double turn(const Vec& a, const Vec& b, const Vec& c) {
  const Vec u = b - a, w = c - b;
  const double lu = core::norm(u), lw = core::norm(w);
  if (!(lu > 0) || !(lw > 0)) return 3.2;
  const double chord = core::norm(u * (1 / lu) - w * (1 / lw));  // 2·sin(δ/2), exact near 0
  return 2 * std::asin(std::min(1.0, chord / 2));
}

// The control points lie on the chord c0 → c3 (within kStraight_mm) and advance along it, and the
// piece leaves and ends along the chord (its end tangents, which its neighbours share, within
// kStraightTurn of it): as a line it then meets them at a turn the planner takes as tangent
// (PlannerConfig::tangent_rad, 1e-9) and that adds no jerk to speak of: a turn θ crossed at v adds
// about v·θ/dt² (1e-12 rad at 250 mm/s: 2.5e-4 mm/s³). Near-collinear points printed to 7 decimals
// pass the first test but turn by 1e-8 to 1e-7 rad: as lines they were corners, blended and crossed
// at 6 mm/s on average; at 9 decimals, turns of 1e-9 passed the planner as tangent and added 0.12
// mm/s³ over the jerk limit (a fuzzer's cases). They stay cubics.
bool straight(const std::array<Vec, 4>& c) {
  constexpr double kStraight_mm = 1e-9, kStraightTurn = 1e-12;
  const Vec d = c[3] - c[0];
  const double len = core::norm(d);
  if (!(len > 0)) return false;
  const Vec u = d * (1 / len);
  const Vec t0 = c[1] - c[0], t1 = c[3] - c[2];
  const double l0 = core::norm(t0), l1 = core::norm(t1);
  if (!(l0 > 0) || !(l1 > 0) || core::norm(t0 * (1 / l0) - u) > kStraightTurn || core::norm(t1 * (1 / l1) - u) > kStraightTurn)
    return false;
  double prev = 0;
  for (int k = 1; k <= 3; ++k) {
    const Vec o = c[k] - c[0];
    const double along = core::dot(o, u);
    if (along < prev || core::norm(o - u * along) > kStraight_mm) return false;
    prev = along;
  }
  return true;
}

// Appends the cubic piece c, or its two halves (de Casteljau at ½: the same curve, split exactly),
// each again split while that pays (split_pays: a long line meeting short ones bends at one end),
// down to pieces of min_length.
void append_piece(std::vector<Segment>& out, const std::array<Vec, 4>& c, const PolylineSmoothing& cfg, int depth,
                  const Segment* built = nullptr) {
  // A piece whose control points lie on one line, in order, is that line: run as a line, it keeps
  // the whole jerk and acceleration a line allows instead of a curve's shares (zero curvature, and
  // its neighbours' curvature is zero where they meet it: the spline stays C²).
  if (depth == 0 && straight(c)) {
    out.push_back(make_line(c[0], c[3]));
    return;
  }
  const Segment whole = built ? *built : make_cubic_bezier(c[0], c[1], c[2], c[3]);
  if (depth >= cfg.split_depth || !(whole.length > 2 * cfg.split_min_length_mm)) {
    out.push_back(whole);
    return;
  }
  const Vec m01 = (c[0] + c[1]) * 0.5, m12 = (c[1] + c[2]) * 0.5, m23 = (c[2] + c[3]) * 0.5;
  const Vec l2 = (m01 + m12) * 0.5, r1 = (m12 + m23) * 0.5, mid = (l2 + r1) * 0.5;
  const std::array<Vec, 4> lc{c[0], m01, l2, mid}, rc{mid, r1, m23, c[3]};
  const Segment left = make_cubic_bezier(lc[0], lc[1], lc[2], lc[3]);
  const Segment right = make_cubic_bezier(rc[0], rc[1], rc[2], rc[3]);
  if (!split_pays(whole, left, right)) {
    out.push_back(whole);
    return;
  }
  append_piece(out, lc, cfg, depth + 1, &left);
  append_piece(out, rc, cfg, depth + 1, &right);
}

// The run's points for control points: `tiers[t]` receives pts[a .. b] low-pass filtered 0, 1, 2,
// 4, … filter_passes times ([1 2 1]/4, ends fixed). CAM points carry the rounding of their last
// printed digit, and a curve through them carries it into its curvature (a 0.5 µm error at 0.25 mm
// spacing is a curvature of 0.03/mm, and a jerk of v³·dκ/ds); filtering also evens out where legs
// change length, where a uniform B-spline bends (3D_Chips.ngc runs 8 mm along its floor, then
// 0.008 mm: a curvature spike of 909/mm through the unfiltered points).
void filter_tiers(std::span<const Vec> pts, std::size_t a, std::size_t b, const PolylineSmoothing& cfg,
                  std::vector<std::vector<Vec>>& tiers) {
  std::vector<Vec> c(pts.begin() + static_cast<std::ptrdiff_t>(a), pts.begin() + static_cast<std::ptrdiff_t>(b) + 1);
  tiers.assign(1, c);
  std::vector<Vec> next(c.size());
  for (int it = 1, tier_end = 1; it <= cfg.filter_passes; ++it) {
    next.front() = c.front();
    next.back() = c.back();
    for (std::size_t k = 1; k + 1 < c.size(); ++k) next[k] = (c[k - 1] + c[k] * 2 + c[k + 1]) * 0.25;
    c.swap(next);
    if (it == tier_end || it == cfg.filter_passes) {
      tiers.push_back(c);
      tier_end *= 2;
    }
  }
}

// The programmed lines of a run [a, b), for distances to them: line a + m runs from pts[a + m]
// along dir[m], inv_l2[m] = 1/|dir[m]|² (0 for a line of no length). Taken once a run.
struct RunLines {
  std::vector<Vec> dir;
  std::vector<double> inv_l2;
  RunLines(std::span<const Vec> pts, std::size_t a, std::size_t b) : dir(b - a), inv_l2(b - a) {
    for (std::size_t m = 0; m < b - a; ++m) {
      dir[m] = pts[a + m + 1] - pts[a + m];
      const double l2 = core::dot(dir[m], dir[m]);
      inv_l2[m] = l2 > 0 ? 1 / l2 : 0.0;
    }
  }
};

// The run of lines [a, b) of pts as B-spline pieces over the control points c (pts[a .. b] as
// filter_tiers and the weights make them): true and `lines` filled when every piece and both stubs
// stay within the tolerance; otherwise false with `bad` = the lines whose pieces (or stubs) leave
// it, in order. Only the pieces j (and stubs: n = b − a the first, n + 1 the last) with dirty[j]
// are checked: the others passed with the same control points before.
bool build_run(std::span<const Vec> pts, std::size_t a, std::size_t b, const std::vector<Vec>& c, std::span<const char> dirty,
               const RunLines& prog, const PolylineSmoothing& cfg, std::vector<std::vector<Segment>>& lines,
               std::vector<std::size_t>& bad) {
  const std::size_t n = b - a;
  bad.clear();
  // A cubic B-spline over the control points c[0] twice, c[1 … n − 1], c[n] twice, one piece per
  // line, with knot intervals D(j) = |c[j + 1] − c[j]|^knot_exponent (the ends repeat their legs'):
  // centripetal at ½. A uniform B-spline (exponent 0) bends where its legs change length, and
  // 3D_Chips.ngc's floor passes end with an 8.9 mm leg and then 0.3 mm legs: its piece there had κ
  // 1.94/mm and |dκ/ds| 42/mm² where the program turns with κ 0.8 (7.3/mm² centripetal).
  // Piece j's inner Bézier points divide its leg c[j] → c[j + 1] as D(j − 1) : D(j) : D(j + 1);
  // the knot between two pieces divides b2 of the one and b1 of the next as D(j − 1) : D(j) (Farin,
  // "Curves and Surfaces for CAGD", B-spline to Bézier), so the curve stays C² in its knot parameter
  // and curvature-continuous as a path; piece j depends on c[j − 2 … j + 3].
  // An interval is at least a hundredth of its neighbours' (legs of under 1e-4 of theirs at ½): a
  // micron leg beside millimetre ones otherwise squeezes its pieces' inner points so close that the
  // rounding of their coordinates bends them (curvature 1e4/mm where the spline meets its stub).
  std::vector<double> dk(n);
  for (std::size_t j = 0; j < n; ++j)
    dk[j] = cfg.knot_exponent == 0 ? 1.0 : std::max(1e-12, std::pow(core::distance(c[j], c[j + 1]), cfg.knot_exponent));
  if (cfg.knot_exponent != 0) {
    std::vector<double> raw = dk;
    for (std::size_t j = 0; j < n; ++j) {
      const double near = std::max(j > 0 ? raw[j - 1] : 0.0, j + 1 < n ? raw[j + 1] : 0.0);
      dk[j] = std::max(raw[j], 0.01 * near);
    }
  }
  const auto D = [&](std::ptrdiff_t j) { return dk[static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(j, 0, static_cast<std::ptrdiff_t>(n) - 1))]; };
  std::vector<Vec> b1(n), b2(n);
  for (std::size_t j = 0; j < n; ++j) {
    const auto J = static_cast<std::ptrdiff_t>(j);
    const double sum = D(J - 1) + D(J) + D(J + 1);
    const Vec leg = c[j + 1] - c[j];
    b1[j] = c[j] + leg * (D(J - 1) / sum);
    b2[j] = c[j] + leg * ((D(J - 1) + D(J)) / sum);
  }
  // Knot points, computed once so that neighbouring pieces share them bit for bit (at the run's
  // ends the doubled control point is both b2 and b1 of the degenerate leg).
  std::vector<Vec> knot(n + 1);
  for (std::size_t j = 0; j <= n; ++j) {
    const auto J = static_cast<std::ptrdiff_t>(j);
    const Vec& before = j == 0 ? c.front() : b2[j - 1];
    const Vec& after = j == n ? c.back() : b1[j];
    knot[j] = before + (after - before) * (D(J - 1) / (D(J - 1) + D(J)));
  }
  // Check every piece first (evaluated directly: cheap, so a run split many times costs little),
  // and build the segments, whose arc-length tables are the expensive part, only for a run that passes.
  const auto ctrl = [&](std::size_t j) { return std::array<Vec, 4>{knot[j], b1[j], b2[j], knot[j + 1]}; };
  // Distance to the nearest of the programmed lines m0 … m1 (one square root a point).
  const auto dist = [&](const Vec& p, std::size_t m0, std::size_t m1) {
    double d2 = 1e300;
    for (std::size_t m = m0; m <= m1; ++m) {
      const Vec o = p - pts[m];
      const Vec& d = prog.dir[m - a];
      const Vec r = o - d * std::clamp(core::dot(o, d) * prog.inv_l2[m - a], 0.0, 1.0);
      d2 = std::min(d2, core::dot(r, r));
    }
    return std::sqrt(d2);
  };
  // Within the tolerance all along the curve at(t), t ∈ [0, 1], near the lines m0 … m1, proven, not
  // sampled: `speed` bounds |d at/dt|, and the distance to the lines changes no faster than the
  // point, so between t0 < t1 at distances d0, d1 it stays below (d0 + d1 + speed·(t1 − t0))/2.
  // After `samples` even samples, each interval that bound does not keep within P is halved (its
  // middle evaluated) until it does or a point beyond P turns up; one still unproven after
  // kMaxHalvings halvings, or past kEvalBudget evaluations, counts as leaving P. Until stop 27 the
  // samples' local peaks were refined by golden sections: with centripetal knots a turn at a long
  // leg followed by micron legs is squeezed into a few thousandths of t, and a piece went 1.18·P
  // off the program between two samples that were not a peak (the review's case,
  // PolylineSmoothing.APieceIsWithinPEvenBetweenSamples).
  const auto within = [&](const auto& at, int samples, std::size_t m0, std::size_t m1, double speed) {
    constexpr int kMaxHalvings = 40, kEvalBudget = 4096;
    const double tol = cfg.tolerance_mm;
    const auto proven = [&](double t0, double d0, double t1, double d1) {
      return (d0 + d1 + speed * (t1 - t0)) / 2 * (1 + 1e-9) + 1e-15 <= tol;
    };
    struct Interval {
      double t0, d0, t1, d1;
      int halvings;
    };
    std::array<Interval, kMaxHalvings + 2> stack{};  // depth first: one pending half a level
    int evals = 0;
    double t_prev = 0, d_prev = dist(at(0.0), m0, m1);
    if (!(d_prev <= tol)) return false;
    for (int k = 1; k <= samples; ++k) {
      const double t = static_cast<double>(k) / samples, d = dist(at(t), m0, m1);
      if (!(d <= tol)) return false;
      std::size_t top = 0;
      stack[top++] = {t_prev, d_prev, t, d, 0};
      while (top > 0) {
        const Interval iv = stack[--top];
        if (proven(iv.t0, iv.d0, iv.t1, iv.d1)) continue;
        if (iv.halvings >= kMaxHalvings || ++evals > kEvalBudget) return false;
        const double tm = 0.5 * (iv.t0 + iv.t1), dm = dist(at(tm), m0, m1);
        if (!(dm <= tol)) return false;
        stack[top++] = {tm, dm, iv.t1, iv.d1, iv.halvings + 1};
        stack[top++] = {iv.t0, iv.d0, tm, dm, iv.halvings + 1};
      }
      t_prev = t, d_prev = d;
    }
    return true;
  };
  for (std::size_t i = a; i < b; ++i) {
    if (!dirty[i - a]) continue;
    const auto c4 = ctrl(i - a);
    // The piece lies in the hull of its control points, near pts[i-1 .. i+2]: its nearest
    // programmed lines are i-1, i, i+1.
    const std::size_t lo = i > a ? i - 1 : i, hi = std::min(b - 1, i + 1);
    const auto at = [&](double t) {
      const double u = 1 - t;
      return c4[0] * (u * u * u) + c4[1] * (3 * u * u * t) + c4[2] * (3 * u * t * t) + c4[3] * (t * t * t);
    };
    // |C'| ≤ 3·max |c_{k+1} − c_k| (a cubic's derivative is a quadratic Bézier over those legs).
    double speed = 0;
    for (int k = 0; k < 3; ++k) speed = std::max(speed, 3 * core::distance(c4[k], c4[k + 1]));
    if (!within(at, 32, lo, hi, speed)) bad.push_back(i);
  }
  // The stubs run from P_a towards the first filtered point, and into P_b: near the first two and
  // last two lines, checked like the pieces.
  const Segment first = make_line(pts[a], knot.front()), last = make_line(knot.back(), pts[b]);
  if (dirty[n] && !within([&](double t) { return first.point(first.length * t); }, 8, a, std::min(a + 1, b - 1), first.length) &&
      (bad.empty() || bad.front() != a))
    bad.insert(bad.begin(), a);
  if (dirty[n + 1] && !within([&](double t) { return last.point(last.length * t); }, 8, b >= a + 2 ? b - 2 : a, b - 1, last.length) &&
      (bad.empty() || bad.back() != b - 1))
    bad.push_back(b - 1);
  if (!bad.empty()) return false;
  lines[a].push_back(first);
  for (std::size_t i = a; i < b; ++i) {
    const auto c4 = ctrl(i - a);
    append_piece(lines[i], c4, cfg, 0);
  }
  lines[b - 1].push_back(last);
  return true;
}

// `w0`: the points' weights to start from (a part of a run split in two goes on from where the
// whole had come; empty: the most filtered tier everywhere).
void smooth_range(std::span<const Vec> pts, std::size_t a, std::size_t b, const PolylineSmoothing& cfg,
                  std::vector<std::vector<Segment>>& lines, std::span<const double> w0 = {}) {
  if (b < a + 2) return;  // one line is kept as it is
  // As much filtering as the tolerance allows, point by point. Each point's weight w (0 … the last
  // tier) places it between two tiers of filter_tiers: tier ⌊w⌋ and the next, by w's fraction. All
  // start at the most filtered tier. The control points of a piece that leaves the tolerance (the
  // four of a uniform spline around it; the run's end points are the same in every tier and do not
  // count) keep filter_cut of their way above the tier below (0.85: they come down by 15 %, once for
  // each such piece), and drop to it once within a sixteenth of a tier; a point's weight stays
  // within filter_taper of its neighbours', so the control points pass smoothly from one tier to
  // the next (whole tiers from point to point made curvature bumps: 3D_Chips.ngc ran slower than
  // with the whole run filtered less). A piece that leaves the tolerance unfiltered splits the run
  // there; each part goes on with the weights it had, but for the points within the taper's reach
  // of the cut, which start again from the top (starting both parts from the top made a 1 000-line
  // run with a jog every 4 lines at P 0.005 take 218 splits of up to 46 rounds: 20–80× the time of
  // the whole-run filter). Before (stop 26), the whole run came down to 2 passes, and then to none,
  // where any piece left it: on 3D_Chips.ngc 397 of 4 546 smoothed lines kept 8 passes.
  std::vector<std::vector<Vec>> tiers;
  filter_tiers(pts, a, b, cfg, tiers);
  if (tiers.size() == 1) tiers.push_back(tiers[0]);  // no filtering: two equal tiers, every weight 0
  const double top = cfg.filter_passes > 0 ? static_cast<double>(tiers.size() - 1) : 0.0;
  const std::size_t n = b - a;
  std::vector<double> w(n + 1, top);
  // Each weight within filter_taper of its neighbours' (a part's carried weights rise from the cut).
  const auto taper = [&] {
    for (std::size_t k = 1; k < w.size(); ++k) w[k] = std::min(w[k], w[k - 1] + cfg.filter_taper);
    for (std::size_t k = w.size() - 1; k-- > 0;) w[k] = std::min(w[k], w[k + 1] + cfg.filter_taper);
  };
  if (w0.size() == n + 1) {
    std::copy(w0.begin(), w0.end(), w.begin());
    taper();
  }
  std::vector<Vec> c(n + 1), checked;
  // Pieces to check this round: all in the first; then those whose control points moved since the
  // last (piece j depends on c[j − 2 … j + 3]; the stubs, n and n + 1, on the first three and the
  // last three) and those that left P. The others passed with the same control points: the same
  // decisions as checking every piece every round, at a fraction of the work.
  std::vector<char> dirty(n + 2, 1);
  std::vector<std::size_t> bad;
  const RunLines prog(pts, a, b);
  for (int round = 0;; ++round) {
    for (std::size_t k = 0; k < c.size(); ++k) {
      const std::size_t t = std::min(tiers.size() - 2, static_cast<std::size_t>(w[k]));
      c[k] = tiers[t][k] + (tiers[t + 1][k] - tiers[t][k]) * (w[k] - static_cast<double>(t));
    }
    if (round > 0) {
      // What left P last round is checked again even where its points did not move (a lowered
      // weight need not move a point: the run's ends, or tiers that agree there).
      std::fill(dirty.begin(), dirty.end(), 0);
      for (const std::size_t i : bad) {
        dirty[i - a] = 1;
        if (i == a) dirty[n] = 1;
        if (i + 1 == b) dirty[n + 1] = 1;
      }
      for (std::size_t k = 0; k <= n; ++k) {
        if (c[k] == checked[k]) continue;
        for (std::size_t j = k >= 3 ? k - 3 : 0; j <= std::min(n - 1, k + 2); ++j) dirty[j] = 1;
        if (k <= 2) dirty[n] = 1;
        if (k + 2 >= n) dirty[n + 1] = 1;
      }
    }
    if (build_run(pts, a, b, c, dirty, prog, cfg, lines, bad)) return;
    checked = c;
    // Past kMaxRounds (bounds the work), a piece's points go straight to their tier below.
    constexpr int kMaxRounds = 64;
    const double cut = round < kMaxRounds ? cfg.filter_cut : 0.0;
    for (const std::size_t i : bad) {
      const std::size_t j = i - a, k0 = j > 1 ? j - 1 : 1, k1 = std::min(n - 1, j + 2);
      bool lowered = false;
      for (std::size_t k = k0; k <= k1; ++k) {
        if (!(w[k] > 0)) continue;
        const double below = std::ceil(w[k]) - 1, rest = (w[k] - below) * cut;
        w[k] = rest < 1.0 / 16 ? below : below + rest;
        lowered = true;
      }
      if (!lowered) {  // split around the piece that leaves the tolerance unfiltered
        // The points near the cut were lowered for the piece that is no longer in either part: they
        // start again from the top, within the taper's reach of the cut; the rest keep their weights.
        const auto reach = static_cast<std::size_t>(std::ceil(top / cfg.filter_taper));
        std::vector<double> left(w.begin(), w.begin() + static_cast<std::ptrdiff_t>(j + 1)), right(w.begin() + static_cast<std::ptrdiff_t>(j + 1), w.end());
        for (std::size_t k = 0; k < reach && k < left.size(); ++k) left[left.size() - 1 - k] = top;
        for (std::size_t k = 0; k < reach && k < right.size(); ++k) right[k] = top;
        smooth_range(pts, a, i, cfg, lines, left);
        smooth_range(pts, i + 1, b, cfg, lines, right);
        return;
      }
    }
    taper();
  }
}

}  // namespace

void smooth_polyline(std::span<const Vec> pts, const PolylineSmoothing& settings, std::vector<std::vector<Segment>>& lines,
                     const std::function<void(std::size_t, std::size_t)>& range_done) {
  // Settings outside their ranges take their defaults: weights must only fall (cut below 1, taper
  // above 0, neither NaN), and knot intervals are between uniform and chord length.
  PolylineSmoothing cfg = settings;
  const PolylineSmoothing defaults;
  if (!(cfg.filter_cut >= 0 && cfg.filter_cut < 1)) cfg.filter_cut = defaults.filter_cut;
  if (!(cfg.filter_taper > 0 && std::isfinite(cfg.filter_taper))) cfg.filter_taper = defaults.filter_taper;
  if (!(cfg.knot_exponent >= 0 && cfg.knot_exponent <= 1)) cfg.knot_exponent = defaults.knot_exponent;
  const std::size_t n = pts.size() < 2 ? 0 : pts.size() - 1;
  lines.assign(n, {});
  if (!(cfg.tolerance_mm > 0)) return;
  // The stretches, each smoothed on its own: lines [a, b) up to a sharp turn, a short line or
  // max_run_lines.
  struct Stretch {
    std::size_t a, b;
  };
  std::vector<Stretch> stretches;
  std::size_t a = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const bool short_line = !(core::distance(pts[i], pts[i + 1]) > cfg.min_length_mm);
    // Line i ends the run at its end point when the turn there is sharp (or it is the last line).
    const bool corner = i + 1 == n || i + 1 - a >= cfg.max_run_lines ||
                        turn(pts[i], pts[i + 1], pts[i + 2]) > cfg.max_turn_rad;
    if (short_line || corner) {
      stretches.push_back({a, short_line ? i : i + 1});
      a = i + 1;
    }
  }
  // Each stretch is smoothed on its own (it writes its own lines only: the same pieces on any
  // thread), several at once, and handed over in order.
  core::ordered_parallel(
      stretches.size(), cfg.threads, 0,
      [&](std::size_t k) { smooth_range(pts, stretches[k].a, stretches[k].b, cfg, lines); },
      [&](std::size_t k) {
        if (range_done && stretches[k].b > stretches[k].a) range_done(stretches[k].a, stretches[k].b);
      });
}

void thin_polyline(std::span<const Vec> pts, double eps_mm, double max_leg_mm, std::size_t max_dropped,
                   std::vector<std::size_t>& kept) {
  kept.clear();
  if (pts.empty()) return;
  kept.push_back(0);
  const std::size_t last = pts.size() - 1;
  std::size_t a = 0;
  while (a < last) {
    // Extend the chord a → b while every point between lies within eps of it and they advance along it.
    std::size_t b = a + 1;
    while (b < last && b - a <= max_dropped) {
      const std::size_t e = b + 1;
      const Vec d = pts[e] - pts[a];
      const double len = core::norm(d);
      if (!(len > 0) || len > max_leg_mm) break;
      const Vec c = d * (1 / len);
      double prev = 0;
      bool ok = true;
      for (std::size_t k = a + 1; k < e && ok; ++k) {
        const Vec o = pts[k] - pts[a];
        const double along = core::dot(o, c);
        const double off2 = core::dot(o, o) - along * along;
        ok = along > prev && off2 <= eps_mm * eps_mm;
        prev = along;
      }
      if (!ok || !(len > prev)) break;
      b = e;
    }
    kept.push_back(b);
    a = b;
  }
}

}  // namespace softmc::motion
