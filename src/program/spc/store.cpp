// Program store: folder loading and the checks across programs.
#include "program/spc/store.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace softmc::program::spc {

int program_number_from_file_name(std::string_view name) {
  if (name.size() < 6 || (name[0] != 'P' && name[0] != 'p')) return -1;
  const auto dot = name.rfind('.');
  if (dot == std::string_view::npos) return -1;
  std::string ext(name.substr(dot));
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".spc") return -1;
  const auto digits = name.substr(1, dot - 1);
  if (digits.empty() || digits.size() > 2) return -1;
  int n = 0;
  for (char c : digits) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return -1;
    n = n * 10 + (c - '0');
  }
  return n;
}

bool ProgramStore::add(int n, std::string_view text, const std::string& file, const ParseOptions& opt,
                       core::Diagnostics& out) {
  ParseOptions o = opt;
  o.number = n;
  auto r = parse(text, file, o);
  out.insert(out.end(), r.diagnostics.begin(), r.diagnostics.end());
  if (!r.program) return false;
  add(std::move(*r.program));
  return true;
}

void ProgramStore::add(SpcProgram p) {
  const int n = p.number;
  if (n < 0 || n >= kPrograms) return;
  programs_[n] = std::make_unique<SpcProgram>(std::move(p));
}

std::vector<int> ProgramStore::numbers() const {
  std::vector<int> v;
  for (int i = 0; i < kPrograms; ++i)
    if (programs_[i]) v.push_back(i);
  return v;
}

std::optional<std::string> read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::stringstream ss;
  ss << in.rdbuf();
  if (in.bad()) return std::nullopt;
  return ss.str();
}

FolderFiles scan_folder(const std::string& dir) {
  namespace fs = std::filesystem;
  FolderFiles out;
  std::error_code ec;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (e.is_regular_file() && ext == ".spc") files.push_back(e.path());
  }
  if (ec) {
    out.diagnostics.push_back(
        {dir, 0, 0, core::Severity::Error, fmt::format("cannot read the program folder: {}", ec.message())});
    return out;
  }
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    const int n = program_number_from_file_name(f.filename().string());
    if (n < 0) {
      out.diagnostics.push_back({f.string(), 0, 0, core::Severity::Error, "a program file is named P<n>.spc with n = 0..99"});
      continue;
    }
    auto& slot = out.path[static_cast<std::size_t>(n)];
    if (!slot.empty()) {
      // Two files for one number: which one runs would depend on the directory order, so neither does.
      out.diagnostics.push_back(
          {f.string(), 0, 0, core::Severity::Error, fmt::format("program P{} is also in {}", n, slot)});
      continue;
    }
    slot = f.string();
  }
  return out;
}

void read_folder(const std::string& dir, core::Diagnostics& out,
                 const std::function<void(int n, const std::string& path, const std::string& text)>& fn) {
  auto files = scan_folder(dir);
  out.insert(out.end(), files.diagnostics.begin(), files.diagnostics.end());
  for (int n = 0; n < kPrograms; ++n) {
    const auto& f = files.path[static_cast<std::size_t>(n)];
    if (f.empty()) continue;
    const auto text = read_text_file(f);
    if (!text) {
      out.push_back({f, 0, 0, core::Severity::Error, "cannot read the file"});
      continue;
    }
    fn(n, f, *text);
  }
}

core::Diagnostics ProgramStore::load_folder(const std::string& dir, const ParseOptions& opt) {
  core::Diagnostics out;
  read_folder(dir, out, [&](int n, const std::string& f, const std::string& text) { add(n, text, f, opt, out); });
  auto v = validate();
  out.insert(out.end(), v.begin(), v.end());
  return out;
}

core::Diagnostics ProgramStore::validate() const {
  core::Diagnostics out;
  for (const auto& p : programs_) {
    if (!p) continue;
    for (const auto& ins : p->ir.instructions) {
      const auto* call = std::get_if<SpcCall>(&ins.op);
      if (!call || call->via_reg) continue;
      const auto* callee = get(call->program);
      if (!callee || callee->size() == 0)
        out.push_back({p->ir.files.at(0), ins.loc.line, ins.loc.col, core::Severity::Error,
                       fmt::format("call of program P{}, which is empty or missing (S-4)", call->program)});
    }
  }
  return out;
}

}  // namespace softmc::program::spc
