// The timed script formats (stimulus files of SPC and G-code runs, PLC orders files): lines of
// whitespace-separated fields starting with a time, `#` comments; one tokenizer and time check for all.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/diagnostic.hpp"

namespace softmc::control::script {

inline constexpr double kTimeEpsS = 1e-9;

struct Field {
  std::string_view text;
  std::uint32_t col = 0;  // 1-based
};

// Splits a line into whitespace-separated fields, up to a '#' comment.
std::vector<Field> fields_of(std::string_view line);
// ASCII case-insensitive equality.
bool iequal(std::string_view a, std::string_view b);
// A whole field as an int.
bool to_int(std::string_view s, int& v);

// Calls f(line_no, fields) for every line of `text` that has fields (1-based line numbers).
template <class F>
void for_each_line(std::string_view text, F&& f) {
  std::uint32_t line_no = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t eol = text.find('\n', pos);
    const std::string_view line = text.substr(pos, eol == std::string_view::npos ? text.size() - pos : eol - pos);
    pos = eol == std::string_view::npos ? text.size() + 1 : eol + 1;
    ++line_no;
    const auto fields = fields_of(line);
    if (!fields.empty()) f(line_no, fields);
  }
}

// The leading time field: a number ≥ 0 that does not go back before `last_t`. On success sets t and
// last_t; otherwise returns the error message (the column is the field's).
std::optional<std::string> read_time(const Field& f, double& last_t, double& t);

// The whole file as text, or nothing (the caller reports "cannot read").
std::optional<std::string> read_file(const std::string& path);

// A `time signal value` line with other than three fields: the column and message of its error
// (`signal_words` says what the second field should be: "a signal name"); nothing when it has three.
std::optional<std::pair<std::uint32_t, std::string>> three_fields(const std::vector<Field>& f,
                                                                   std::string_view signal_words);

// Reads `path` and parses it with parse(text, path); an unreadable file is one diagnostic,
// "cannot read the <what>".
template <class Result, class Parse>
Result load(const std::string& path, std::string_view what, Parse&& parse) {
  const auto text = read_file(path);
  if (!text) {
    Result res;
    res.diagnostics.push_back({path, 0, 0, core::Severity::Error, "cannot read the " + std::string(what)});
    return res;
  }
  return parse(*text, path);
}

}  // namespace softmc::control::script
