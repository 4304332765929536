// Conformance with LinuxCNC 2.9: `softmc moves` of every tests/golden/iso/*.ngc agrees with the
// golden rs274 canonical calls (*.rs274, written by regen.sh) move for move: same kinds, end points
// and arc centres within 1e-4 (the reference prints 4 decimals in the program's units).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "golden_setup.hpp"
#include "moves.hpp"
#include "program/iso/parser.hpp"

namespace fs = std::filesystem;
using namespace softmc;

namespace {

const fs::path kDir = fs::path(SOFTMC_SOURCE_DIR) / "tests" / "golden" / "iso";
constexpr double kMmPerInch = 25.4;

// One canonical motion, in mm, machine axes X Y Z A B C (rs274 prints no U V W here).
struct Move {
  std::string kind;  // rapid, feed, arc
  double end[6] = {};
  bool has_center = false;
  int center_axes[2] = {0, 1};
  double center[2] = {};
  int rotation = 0;  // rs274 ARC_FEED rotation: +n counter-clockwise n turns, -n clockwise
  std::string text;  // as read, for failure messages
};

std::vector<double> numbers_in(const std::string& s) {
  std::vector<double> v;
  const auto open = s.find('('), close = s.rfind(')');
  std::stringstream ss(s.substr(open + 1, close - open - 1));
  std::string item;
  while (std::getline(ss, item, ',')) v.push_back(std::stod(item));
  return v;
}

// The golden file: canonical calls in program order; plane and units apply to the calls after them.
std::vector<Move> read_golden(const fs::path& p) {
  std::ifstream in(p);
  std::vector<Move> out;
  std::string line;
  int plane = 0;  // 0 XY, 1 XZ (first = Z, second = X), 2 YZ
  double k = 1.0;
  double tool[6] = {};  // USE_TOOL_LENGTH_OFFSET: rs274's moves leave it out, softmc's machine positions have it
  while (std::getline(in, line)) {
    if (line.rfind("USE_TOOL_LENGTH_OFFSET(", 0) == 0) {
      std::string inner = line.substr(line.find('(') + 1, line.rfind(')') - line.find('(') - 1);
      std::replace(inner.begin(), inner.end(), ',', ' ');
      std::stringstream ss(inner);
      for (int i = 0; i < 6; ++i) {
        ss >> tool[i];
        if (i < 3) tool[i] *= k;
      }
      continue;
    }
    if (line.rfind("USE_LENGTH_UNITS(", 0) == 0) k = line.find("INCHES") != std::string::npos ? kMmPerInch : 1.0;
    if (line.rfind("SELECT_PLANE(", 0) == 0)
      plane = line.find("XZ") != std::string::npos ? 1 : line.find("YZ") != std::string::npos ? 2 : 0;
    const bool traverse = line.rfind("STRAIGHT_TRAVERSE(", 0) == 0, feed = line.rfind("STRAIGHT_FEED(", 0) == 0;
    const bool arc = line.rfind("ARC_FEED(", 0) == 0;
    if (!traverse && !feed && !arc) continue;
    const auto v = numbers_in(line);
    Move m;
    m.text = line;
    if (!arc) {
      m.kind = traverse ? "rapid" : "feed";
      for (int i = 0; i < 6; ++i) m.end[i] = (i < 3 ? v.at(i) * k : v.at(i)) + tool[i];
    } else {
      // ARC_FEED(first_end, second_end, first_axis, second_axis, rotation, axis_end_point, a, b, c)
      static constexpr int kFirst[3] = {0, 2, 1}, kSecond[3] = {1, 0, 2}, kNormal[3] = {2, 1, 0};
      m.kind = "arc";
      m.end[kFirst[plane]] = v.at(0) * k;
      m.end[kSecond[plane]] = v.at(1) * k;
      m.end[kNormal[plane]] = v.at(5) * k;
      for (int i = 3; i < 6; ++i) m.end[i] = v.at(i + 3);
      for (int i = 0; i < 6; ++i) m.end[i] += tool[i];
      m.has_center = true;
      m.center_axes[0] = kFirst[plane];
      m.center_axes[1] = kSecond[plane];
      m.center[0] = v.at(2) * k + tool[kFirst[plane]];
      m.center[1] = v.at(3) * k + tool[kSecond[plane]];
      m.rotation = static_cast<int>(v.at(4));
    }
    out.push_back(m);
  }
  return out;
}

// softmc's side, read back from the `softmc moves` JSON Lines.
std::vector<Move> read_softmc(const program::Program& prog) {
  std::vector<Move> out;
  std::stringstream ss(app::moves_jsonl(prog, 0x1FF));
  std::string line;
  while (std::getline(ss, line)) {
    const auto j = nlohmann::json::parse(line);
    const std::string type = j.at("type");
    if (type != "rapid" && type != "feed" && type != "arc") continue;
    Move m;
    m.kind = type;
    m.text = line;
    for (int i = 0; i < 6; ++i) m.end[i] = j.at("end").at(std::string(1, core::letter(i)));
    if (type == "arc") {
      m.has_center = true;
      const std::string plane = j.at("plane");
      for (int c = 0; c < 2; ++c) {
        m.center_axes[c] = static_cast<int>(*core::axis_from_letter(plane[c]));
        m.center[c] = j.at("center").at(std::string(1, plane[c]));
      }
      const int turns = j.at("turns");
      m.rotation = j.at("direction") == "ccw" ? turns : -turns;
    }
    out.push_back(m);
  }
  return out;
}

// Centres compare by axis, whichever order the two sides list the plane's axes in.
double center_on(const Move& m, int axis) {
  for (int c = 0; c < 2; ++c)
    if (m.center_axes[c] == axis) return m.center[c];
  return NAN;
}

std::vector<std::string> programs() {
  std::vector<std::string> v;
  for (const auto& e : fs::directory_iterator(kDir))
    if (e.path().extension() == ".ngc") v.push_back(e.path().stem().string());
  std::sort(v.begin(), v.end());
  return v;
}

std::string first_line(const fs::path& p) {
  std::ifstream in(p);
  std::string s;
  std::getline(in, s);
  return s;
}

class GoldenIso : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(GoldenIso, MovesMatchLinuxCncRs274) {
  const fs::path ngc = kDir / (GetParam() + ".ngc");
  const fs::path golden = kDir / (GetParam() + ".rs274");
  ASSERT_TRUE(fs::exists(golden)) << "no golden file: run tests/golden/regen.sh " << ngc;
  const auto r = program::iso::parse_file(ngc.string(), golden::setup().options());
  if (!r.program) {
    // A program may name the interpreter feature it waits for on its first line: "(needs: ...)".
    const std::string head = first_line(ngc);
    const auto at = head.find("needs:");
    std::string why = r.diagnostics.empty() ? std::string("?") : r.diagnostics.front().format();
    if (at != std::string::npos) GTEST_SKIP() << head.substr(at, head.rfind(')') - at) << " — " << why;
    for (const auto& d : r.diagnostics) ADD_FAILURE() << d.format();
    return;
  }
  // rs274 prints 4 decimals of the program's units: 1e-4 mm, or 1e-4 in for programs in inches.
  std::ifstream gin(golden);
  const std::string gtext((std::istreambuf_iterator<char>(gin)), std::istreambuf_iterator<char>());
  const double tol = gtext.find("CANON_UNITS_INCHES") != std::string::npos ? 1e-4 * kMmPerInch : 1e-4;
  const auto want = read_golden(golden);
  const auto got = read_softmc(*r.program);
  ASSERT_EQ(got.size(), want.size()) << "number of moves";
  for (std::size_t i = 0; i < want.size(); ++i) {
    const Move &w = want[i], &g = got[i];
    SCOPED_TRACE("move " + std::to_string(i) + "\n  rs274:  " + w.text + "\n  softmc: " + g.text);
    ASSERT_EQ(g.kind, w.kind);
    for (int a = 0; a < 6; ++a) EXPECT_NEAR(g.end[a], w.end[a], tol) << "end " << core::letter(a);
    if (w.has_center) {
      for (int c = 0; c < 2; ++c)
        EXPECT_NEAR(center_on(g, w.center_axes[c]), w.center[c], tol) << "centre " << core::letter(w.center_axes[c]);
      EXPECT_EQ(g.rotation, w.rotation) << "turns and direction";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Conformance, GoldenIso, ::testing::ValuesIn(programs()),
                         [](const auto& info) { return info.param; });
