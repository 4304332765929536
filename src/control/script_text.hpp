// The timed script formats (stimulus files of SPC and G-code runs, PLC orders files): lines of
// whitespace-separated fields starting with a time, `#` comments; one tokenizer and time check for all.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
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

}  // namespace softmc::control::script
