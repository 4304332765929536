// The program store folder (S-1, S-12): import all or nothing, callers re-checked, delete refused while called, export.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "temp_dir.hpp"
#include "program/spc/store_folder.hpp"

namespace softmc::program::spc {
namespace {

namespace fs = std::filesystem;

using test::TempDir;

// Every file of a folder (hidden ones too, so a left-over temp file shows) with its bytes.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(dir)) m[e.path().filename().string()] = *read_text_file(e.path().string());
  return m;
}

std::string dump(const core::Diagnostics& d) {
  std::string s;
  for (const auto& x : d) s += x.format() + "\n";
  return s;
}

const char* kMain = "N000 G01 X10 FX0 ; main: go to 10\nN001 L2\nN002 M30\n";
const char* kSub = "; P2: a subroutine\nN000 #LR1=5\nN001 M02\n";

TEST(Spc200, S12_ImportGoodProgramsAndListThem) {
  TempDir d;
  StoreFolder store(d.str());
  // P1 calls P2: imported together, the store checks clean.
  auto r = store.import({{1, kMain, "main.txt"}, {2, kSub, "sub.txt"}});
  ASSERT_TRUE(r.ok()) << dump(r.diagnostics);
  EXPECT_EQ(r.changed, (std::vector<int>{1, 2}));
  EXPECT_EQ(*read_text_file((d.path / "P1.spc").string()), kMain);
  EXPECT_EQ(snapshot(d.path).size(), 2u);  // no temp file left behind
  EXPECT_TRUE(store.check().empty());

  core::Diagnostics diags;
  const auto list = store.list(diags);
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].number, 1);
  EXPECT_EQ(list[0].lines, 3u);
  EXPECT_EQ(list[0].title, "main: go to 10");
  EXPECT_EQ(list[1].number, 2);
  EXPECT_EQ(list[1].lines, 2u);
  EXPECT_EQ(list[1].title, "P2: a subroutine");
  EXPECT_TRUE(diags.empty());
}

TEST(Spc200, S12_ImportOfABadProgramChangesNothingByteForByte) {
  TempDir d;
  d.file("P1.spc", kMain);
  d.file("P2.spc", kSub);
  const auto before = snapshot(d.path);
  StoreFolder store(d.str());
  // A syntax error (decreasing line numbers, S-1) in the replacement of P2 and a fine P3 beside it.
  auto r = store.import({{3, "N000 M30\n", "p3.txt"}, {2, "N001 #LR1=5\nN000 M02\n", "bad.spc"}});
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(r.changed.empty());
  ASSERT_FALSE(r.diagnostics.empty());
  EXPECT_EQ(r.diagnostics[0].file, "bad.spc");
  EXPECT_EQ(r.diagnostics[0].line, 2u);
  EXPECT_EQ(snapshot(d.path), before);
}

TEST(Spc200, S12_ReplacingACalledProgramRechecksItsCallers) {
  TempDir d;
  d.file("P1.spc", kMain);
  d.file("P2.spc", kSub);
  const auto before = snapshot(d.path);
  StoreFolder store(d.str());
  // An empty P2 parses, but P1's L2 would call an empty program (S-4): refused, and the error is P1's.
  auto r = store.import({{2, "; nothing left\n", "empty.spc"}});
  EXPECT_FALSE(r.ok());
  ASSERT_EQ(r.diagnostics.size(), 1u) << dump(r.diagnostics);
  EXPECT_EQ(r.diagnostics[0].file, (d.path / "P1.spc").string());
  EXPECT_EQ(r.diagnostics[0].line, 2u);
  EXPECT_NE(r.diagnostics[0].message.find("P2"), std::string::npos);
  EXPECT_EQ(snapshot(d.path), before);
  // A real replacement goes in, and only P2 changes.
  r = store.import({{2, "N000 #LR1=6\nN001 M02\n", "sub2.spc"}});
  ASSERT_TRUE(r.ok()) << dump(r.diagnostics);
  auto after = snapshot(d.path);
  EXPECT_EQ(after["P1.spc"], before.at("P1.spc"));
  EXPECT_EQ(after["P2.spc"], "N000 #LR1=6\nN001 M02\n");
}

TEST(Spc200, S12_ImportRefusedWhileTheRestOfTheStoreIsBrokenButMayRepairIt) {
  TempDir d;
  d.file("P1.spc", kMain);  // calls P2, which is missing
  StoreFolder store(d.str());
  auto r = store.import({{5, "N000 M30\n", "p5.spc"}});
  EXPECT_FALSE(r.ok());
  EXPECT_FALSE(fs::exists(d.path / "P5.spc"));
  r = store.import({{2, kSub, "sub.spc"}});  // the missing callee: the store now checks clean
  EXPECT_TRUE(r.ok()) << dump(r.diagnostics);
  EXPECT_TRUE(store.check().empty());
}

TEST(Spc200, S12_ImportReplacesAnOtherwiseSpelledFile) {
  TempDir d;
  d.file("p07.spc", "N000 M30\n");
  StoreFolder store(d.str());
  EXPECT_EQ(store.path_of(7), (d.path / "p07.spc").string());
  auto r = store.import({{7, "N000 G04 10\nN001 M30\n", "x"}});
  ASSERT_TRUE(r.ok()) << dump(r.diagnostics);
  const auto after = snapshot(d.path);
  ASSERT_EQ(after.size(), 1u);
  EXPECT_EQ(after.begin()->first, "P7.spc");
}

TEST(Spc200, S1_TwoFilesForOneProgramNumberAreAnError) {
  TempDir d;
  d.file("P3.spc", "N000 M30\n");
  d.file("P03.spc", "N000 G04 1\n");
  StoreFolder store(d.str());
  const auto diags = store.check();
  ASSERT_EQ(diags.size(), 1u) << dump(diags);
  EXPECT_NE(diags[0].message.find("P3 is also in"), std::string::npos);
}

TEST(Spc200, S9_RecordSelectStoreRefusesANonMotionProgram) {
  TempDir d;
  StoreFolder store(d.str(), {true, -1});
  auto r = store.import({{1, "N000 #LR1=5\n", "p1.spc"}});
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(snapshot(d.path).empty());
  EXPECT_TRUE(store.import({{1, "N000 G01 X5 FX0\n", "p1.spc"}}).ok());
}

TEST(Spc200, S12_DeleteRefusedWhileCalledUnlessForced) {
  TempDir d;
  d.file("P1.spc", kMain);
  d.file("P2.spc", kSub);
  StoreFolder store(d.str());
  core::Diagnostics diags;
  EXPECT_EQ(store.callers_of(2, diags), std::vector<int>{1});
  auto r = store.remove(2, false);
  EXPECT_FALSE(r.ok());
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_NE(r.diagnostics[0].message.find("called by P1"), std::string::npos) << r.diagnostics[0].message;
  EXPECT_TRUE(fs::exists(d.path / "P2.spc"));
  r = store.remove(2, true);
  EXPECT_TRUE(r.ok());
  EXPECT_FALSE(fs::exists(d.path / "P2.spc"));
  EXPECT_FALSE(store.check().empty());  // forced: P1 now calls a missing program
  // A program nobody calls goes at once; a missing one is an error.
  EXPECT_TRUE(store.remove(1, false).ok());
  EXPECT_FALSE(store.remove(1, false).ok());
  EXPECT_FALSE(store.remove(100, false).ok());
}

TEST(Spc200, S12_ExportAndImportRoundTripByteForByte) {
  TempDir a, out, b;
  // CRLF line ends and a trailing comment line: exported exactly as stored.
  a.file("P1.spc", "N000 G01 X10 FX0\r\nN001 L2\r\nN002 M30\r\n; end\r\n");
  a.file("P2.spc", kSub);
  StoreFolder src(a.str());
  auto r = src.export_to({1, 2}, out.str());
  ASSERT_TRUE(r.ok()) << dump(r.diagnostics);
  EXPECT_EQ(snapshot(out.path), snapshot(a.path));
  // A missing program refuses the whole export.
  TempDir out2;
  EXPECT_FALSE(src.export_to({1, 9}, out2.str()).ok());
  EXPECT_TRUE(snapshot(out2.path).empty());

  StoreFolder dst(b.str());
  std::vector<ImportItem> items;
  for (const auto& [name, text] : snapshot(out.path))
    items.push_back({program_number_from_file_name(name), text, (out.path / name).string()});
  ASSERT_TRUE(dst.import(items).ok());
  EXPECT_EQ(snapshot(b.path), snapshot(a.path));
}

TEST(Spc200, S1_ProgramTitleIsTheFirstComment) {
  EXPECT_EQ(program_title("N000 M30\n"), "");
  EXPECT_EQ(program_title("N000 M30 ;  end  \r\nN001 ; other\n"), "end");
  EXPECT_EQ(program_title(";\n"), "");
}

}  // namespace
}  // namespace softmc::program::spc
