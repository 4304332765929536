// InterpSetup: the machine's [gcode] settings (tool table file, subroutine folders, P-10 M functions) as ParseOptions.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "temp_dir.hpp"
#include "iso_test_util.hpp"
#include "program/iso/interp_config.hpp"

namespace softmc::program::iso {
namespace {

namespace fs = std::filesystem;
using test::formatted;

using softmc::test::TempDir;

template <class T>
std::vector<T> all(const Program& p) {
  std::vector<T> v;
  for (const auto& i : p.instructions)
    if (const auto* x = op_if<T>(i.op)) v.push_back(*x);
  return v;
}

TEST(IsoInterpConfig, ToolTableFileFeedsG43AndG41) {
  TempDir dir;
  InterpConfig ic;
  ic.tool_table = dir.file("tools.tbl", "T1 P1 D6.0 Z25.4 ;6 mm end mill\n");
  InterpSetup setup;
  ASSERT_TRUE(setup.load(ic).empty());
  // G43 H1: Z moves by the tool length; G41 D1: the path is offset by the radius 3 mm to the left.
  const auto r = parse("G43 H1\nG0 X0 Y-10 Z5\nG41 D1\nG1 X0 Y0 F600\nG1 X50\nG40\nG0 X60\nM2\n", "t.ngc", setup.options());
  ASSERT_TRUE(r.program) << (r.diagnostics.empty() ? "" : r.diagnostics[0].format());
  const auto rapids = all<Rapid>(*r.program);
  EXPECT_DOUBLE_EQ(rapids.at(0).end[2], 5 + 25.4);
  const auto feeds = all<Linear>(*r.program);
  ASSERT_GE(feeds.size(), 2u);
  EXPECT_NEAR(feeds[0].end[0], -3.0, 1e-9);  // entry along +Y ends D6 / 2 to its left
  EXPECT_NEAR(feeds[1].end[1], 3.0, 1e-9);   // the X move runs 3 mm to the left of Y0
  EXPECT_EQ(all<Arc>(*r.program).size(), 1u);  // round the outside corner
  EXPECT_NEAR(all<OffsetsChanged>(*r.program).at(0).tool[2], 25.4, 1e-12);
  // Without the setup there is no tool 1.
  EXPECT_EQ(formatted(parse("G43 H1\n", "t.ngc")).at(0), "t.ngc:1:5: error: tool 1 is not in the tool table");
}

TEST(IsoInterpConfig, ToolTableProblemsAreReportedBeforeAnyProgram) {
  TempDir dir;
  InterpConfig ic;
  ic.tool_table = dir.file("bad.tbl", "T1 D6\nT2 K1\n");
  InterpSetup setup;
  const auto d = setup.load(ic);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].format(), ic.tool_table + ":2:4: error: unknown tool table word K");
  ic.tool_table = (dir.path / "missing.tbl").string();
  EXPECT_EQ(InterpSetup().load(ic).at(0).message, "cannot read tool table");
}

TEST(IsoInterpConfig, SubroutineFoldersAreSearchedInOrder) {
  TempDir dir;
  dir.file("a/other.ngc", "o<other> sub\nG0 X1\no<other> endsub\n");
  dir.file("b/peck.ngc", "o<peck> sub\nG0 X7\no<peck> endsub\n");
  InterpConfig ic;
  ic.subroutine_path = {(dir.path / "a").string(), (dir.path / "b").string()};
  InterpSetup setup;
  ASSERT_TRUE(setup.load(ic).empty());
  const auto r = parse("o<peck> call\nM2\n", (dir.path / "main.ngc").string(), setup.options());
  ASSERT_TRUE(r.program);
  EXPECT_EQ(all<Rapid>(*r.program).at(0).end[0], 7);
}

// P-10: "Configuration per M function (number 0..100): group, breaks continuous path at block start,
// breaks continuous path at block end, changes machine position. Fixed functions cannot leave their
// group but their flags can change; unknown ones fall into group 14".
TEST(PlcInterface, P10_MFunctionConfigurationFromTheMachine) {
  InterpConfig ic;
  ic.m_functions = {{100, 4, true, false, false}, {101, 4, false, true, false}, {6, 0, true, true, true}};
  InterpSetup setup;
  ASSERT_TRUE(setup.load(ic).empty());
  EXPECT_EQ(setup.m_table().get(100).group, 4);
  EXPECT_TRUE(setup.m_table().get(100).breaks_path_at_start);
  EXPECT_EQ(setup.m_table().get(6).group, 9);  // group 0: a fixed function keeps its own
  EXPECT_TRUE(setup.m_table().get(6).breaks_path_at_start);
  EXPECT_EQ(setup.m_table().get(102).group, 14);  // unknown ones: group 14
  // The program check uses the configured groups: M100 and M101 now share group 4.
  EXPECT_EQ(formatted(parse("M100 M101\n", "t.ngc", setup.options())).at(0),
            "t.ngc:1:6: error: two M codes of group 4 in one block: M100 and M101");
  EXPECT_TRUE(parse("M100 M101\n", "t.ngc").program.has_value());  // both in group 14 by default
  const auto p = parse("M100\n", "t.ngc", setup.options());
  ASSERT_TRUE(p.program);
  EXPECT_EQ(all<MFunction>(*p.program).at(0).group, 4);

  ic.m_functions = {{6, 4, false, false, false}, {120, 5, false, false, false}, {250, 4, false, false, false}};
  const auto d = InterpSetup().load(ic);
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[0].message, "gcode.m.6.group: M6 is a fixed P-10 function of group 9 and cannot leave it (got 4); "
                          "only its flags may change");
  EXPECT_EQ(d[1].message, "gcode.m.120.group: user M functions go in the free groups 4, 10, 11, 12, 13 or 14 (got 5)");
  EXPECT_EQ(d[2].message, "gcode.m.250: M functions are numbered 0 … 199");
}

}  // namespace
}  // namespace softmc::program::iso
