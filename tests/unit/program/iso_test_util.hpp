// Helpers for the ISO parser tests: parse text, get the program's dump or the formatted errors.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "program/iso/parser.hpp"

namespace softmc::program::iso::test {

inline core::Vec xyz(double x, double y, double z = 0) {
  core::Vec v;
  v[0] = x;
  v[1] = y;
  v[2] = z;
  return v;
}

// Every diagnostic formatted as "file:line:col: severity: message".
inline std::vector<std::string> formatted(const ParseResult& r) {
  std::vector<std::string> out;
  for (const auto& d : r.diagnostics) out.push_back(d.format());
  return out;
}

// Parses text that must be valid; fails the test (with the diagnostics) otherwise.
inline Program parse_ok(std::string_view text, const ParseOptions& opt = {}) {
  auto r = parse(text, "t.ngc", opt);
  for (const auto& d : r.diagnostics)
    if (d.severity == core::Severity::Error) ADD_FAILURE() << d.format() << "\n--- in:\n" << text;
  EXPECT_TRUE(r.program.has_value());
  return r.program ? *r.program : Program{};
}

// Parses text that must be refused; returns the formatted diagnostics.
inline std::vector<std::string> parse_errors(std::string_view text, const ParseOptions& opt = {}) {
  auto r = parse(text, "t.ngc", opt);
  EXPECT_FALSE(r.program.has_value()) << text;
  EXPECT_TRUE(core::has_errors(r.diagnostics)) << text;
  return formatted(r);
}

// The single error a one-error program gives ("" and a test failure when there is not exactly one).
inline std::string one_error(std::string_view text) {
  const auto e = parse_errors(text);
  EXPECT_EQ(e.size(), 1u) << text;
  return e.empty() ? std::string() : e.front();
}

// A tool table from its text, which must read without a diagnostic (ParseOptions::tools points at it).
inline ToolTable tools_ok(std::string_view text) {
  core::Diagnostics d;
  ToolTable t = parse_tool_table(text, "tools.tbl", d);
  EXPECT_TRUE(d.empty()) << (d.empty() ? "" : d.front().format());
  return t;
}

// The end point of every motion (rapids, lines, arcs, G5/G5.1 splines), in program order.
inline std::vector<core::Vec> ends(const Program& p) {
  std::vector<core::Vec> out;
  for (const auto& i : p.instructions) {
    if (const auto* r = std::get_if<Rapid>(&i.op)) out.push_back(r->end);
    if (const auto* l = std::get_if<Linear>(&i.op)) out.push_back(l->end);
    if (const auto* a = std::get_if<Arc>(&i.op)) out.push_back(a->end);
    if (const auto* b = op_if<Bezier>(i.op)) out.push_back(b->end);
  }
  return out;
}

// The texts of the program's DEBUG/PRINT/MSG messages, in order.
inline std::vector<std::string> messages(const Program& p) {
  std::vector<std::string> out;
  for (const auto& i : p.instructions)
    if (const auto* m = std::get_if<Message>(&i.op)) out.push_back(m->text);
  return out;
}

template <class T>
const T& op_at(const Program& p, std::size_t i) {
  static const T kNone{};
  if (i >= p.instructions.size()) {
    ADD_FAILURE() << "no instruction " << i << " in a program of " << p.instructions.size();
    return kNone;
  }
  const T* t = std::get_if<T>(&p.instructions[i].op);
  if (!t) {
    ADD_FAILURE() << "instruction " << i << " has another type (variant index " << p.instructions[i].op.index() << ")";
    return kNone;
  }
  return *t;
}

}  // namespace softmc::program::iso::test
