// Registers from outside (S-5, S-12): names, the language's ranges, get/set through SQLite, all or nothing.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "io/register_access.hpp"

namespace softmc::io {
namespace {

std::string temp_db(const char* name) {
  const auto p = std::filesystem::temp_directory_path() / (std::string(name) + "_" + std::to_string(::getpid()) + ".db");
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(p.string() + suffix);
  return p.string();
}

std::string texts(const std::vector<RegisterValue>& v) {
  std::string s;
  for (const auto& x : v) s += x.text() + " ";
  return s;
}

TEST(Spc200, S12_RegisterNamesAndValuesParse) {
  const auto a = parse_register_args({"@3", "X=12.5", "@99u=-0.05", "r5=7", "R0=-32767", "@0Y=+9999.99"}, true);
  ASSERT_TRUE(a.errors.empty()) << a.errors[0];
  ASSERT_EQ(a.writes.size(), 5u);
  EXPECT_EQ(texts(a.writes), "@3X=12.50 @99U=-0.05 R5=7 R0=-32767 @0Y=9999.99 ");
  EXPECT_EQ(a.writes[0].value, 1250);
  EXPECT_EQ(a.writes[1].ref.axis, 3);
  const auto g = parse_register_args({"@3", "Z", "@4X", "R99", "F63"}, false);
  ASSERT_TRUE(g.errors.empty()) << g.errors[0];
  ASSERT_EQ(g.refs.size(), 4u);
  EXPECT_EQ(g.refs[0].name(), "@3Z");
  EXPECT_EQ(g.refs[3].kind, RegisterKind::Flag);
}

TEST(Spc200, S5_RegisterRangesAsTheLanguageHasThem) {
  // Each one bad: more than two decimals, beyond ±9999.99, beyond ±32767, no such register or axis.
  for (const char* bad : {"@1X=1.234", "@1X=10000", "@1X=-9999.995", "@1X=1e3", "@1X=", "R1=32768", "R1=-32768",
                          "R1=1.5", "R100=1", "@100X=1", "@1W=1", "Q1=1", "F64=1", "F1=2", "R1"}) {
    const auto a = parse_register_args({bad}, true);
    EXPECT_EQ(a.errors.size(), 1u) << bad;
    EXPECT_TRUE(a.writes.empty()) << bad;
  }
  std::string err;
  EXPECT_EQ(parse_position_centi("-9999.99", err), -999999);
  EXPECT_EQ(parse_position_centi(".5", err), 50);
  EXPECT_EQ(parse_position_centi("3.", err), 300);
  EXPECT_FALSE(parse_position_centi("1.001", err));
  EXPECT_NE(err.find("two decimals"), std::string::npos);
  EXPECT_FALSE(parse_position_centi("123456789012345", err));
  EXPECT_EQ(parse_register_args({"R1=1", "r1=2"}, true).errors.size(), 1u);  // written twice
}

TEST(Spc200, S12_RegistersSetThenGetRoundTripThroughTheFile) {
  const auto path = temp_db("spc_regaccess_roundtrip");
  {
    RegisterAccess regs(path);
    const auto a = parse_register_args({"@3X=12.5", "@99U=-9999.99", "R5=-7", "R99=32767"}, true);
    EXPECT_TRUE(regs.set(a.writes).empty());
  }
  // A fresh process sees them, as `softmc run` restores them (RetentiveStore::restore).
  control::spc::Registers fresh;
  RetentiveStore(path).restore(fresh);
  EXPECT_EQ(fresh.position_centi(0, 3), 1250);
  EXPECT_EQ(fresh.position_centi(3, 99), -999999);
  EXPECT_EQ(fresh.integer(5), -7);
  EXPECT_EQ(fresh.integer(99), 32767);

  RegisterAccess regs(path);
  std::vector<std::string> errors;
  const auto g = regs.get(parse_register_args({"@3X", "R5", "R6"}, false).refs, errors);
  EXPECT_TRUE(errors.empty());
  EXPECT_EQ(texts(g), "@3X=12.50 R5=-7 R6=0 ");
  EXPECT_EQ(texts(regs.nonzero()), "@3X=12.50 @99U=-9999.99 R5=-7 R99=32767 ");
}

TEST(Spc200, S5_FlagsAreNotRetentiveSoNotInTheFile) {
  const auto path = temp_db("spc_regaccess_flags");
  RegisterAccess regs(path);
  const auto a = parse_register_args({"R1=4", "F3=1"}, true);
  ASSERT_TRUE(a.errors.empty());
  const auto errors = regs.set(a.writes);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("not retentive"), std::string::npos);
  EXPECT_TRUE(regs.nonzero().empty());  // R1 was not written either: all or nothing
  std::vector<std::string> get_errors;
  EXPECT_TRUE(regs.get(parse_register_args({"F3"}, false).refs, get_errors).empty());
  EXPECT_EQ(get_errors.size(), 1u);
}

TEST(Spc200, S12_RegisterSetIsAllOrNothing) {
  const auto path = temp_db("spc_regaccess_atomic");
  RegisterAccess regs(path);
  ASSERT_TRUE(regs.set(parse_register_args({"R1=1", "@1X=1.00"}, true).writes).empty());
  // Values that passed the word check but not the registers' own (a hand-built value, as a server might send).
  std::vector<RegisterValue> w = {{{RegisterKind::Integer, 0, 1}, 2},
                                  {{RegisterKind::Position, 0, 1}, 2},
                                  {{RegisterKind::Integer, 0, 2}, 40000}};
  EXPECT_EQ(regs.set(w).size(), 1u);
  EXPECT_EQ(texts(regs.nonzero()), "@1X=1.00 R1=1 ");
  w.pop_back();
  EXPECT_TRUE(regs.set(w).empty());
  EXPECT_EQ(texts(regs.nonzero()), "@1X=0.02 R1=2 ");
}

}  // namespace
}  // namespace softmc::io
