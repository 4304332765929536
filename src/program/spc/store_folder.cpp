// The program store folder: validate the store that would result, then write it file by file atomically.
#include "program/spc/store_folder.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <set>

namespace softmc::program::spc {

namespace fs = std::filesystem;

namespace {

std::string canonical_name(int n) { return fmt::format("P{}.spc", n); }

bool valid_number(int n) { return n >= 0 && n < kPrograms; }

// Writes all of `text` to fd; false on any error.
bool write_all(int fd, std::string_view text) {
  while (!text.empty()) {
    const ssize_t w = ::write(fd, text.data(), text.size());
    if (w < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    text.remove_prefix(static_cast<std::size_t>(w));
  }
  return true;
}

void fsync_dir(const fs::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// Writes the temp file next to `path`; returns its name, or "" with `err` set.
std::string write_temp(const std::string& path, std::string_view text, std::string& err) {
  const fs::path p(path);
  std::string tmpl = (p.parent_path() / ("." + p.filename().string() + ".tmp-XXXXXX")).string();
  const int fd = ::mkstemp(tmpl.data());
  if (fd < 0) {
    err = fmt::format("cannot create a temporary file next to {}: {}", path, std::strerror(errno));
    return {};
  }
  ::fchmod(fd, 0644);
  const bool ok = write_all(fd, text) && ::fsync(fd) == 0;
  const int saved = errno;
  ::close(fd);
  if (!ok) {
    ::unlink(tmpl.c_str());
    err = fmt::format("cannot write {}: {}", tmpl, std::strerror(saved));
    return {};
  }
  return tmpl;
}

}  // namespace

std::string program_title(std::string_view text) {
  const auto semi = text.find(';');
  if (semi == std::string_view::npos) return {};
  auto rest = text.substr(semi + 1);
  rest = rest.substr(0, rest.find_first_of("\r\n"));
  const auto b = rest.find_first_not_of(" \t");
  if (b == std::string_view::npos) return {};
  const auto e = rest.find_last_not_of(" \t");
  return std::string(rest.substr(b, e - b + 1));
}

std::string write_file_atomically(const std::string& path, std::string_view text) {
  std::string err;
  const auto tmp = write_temp(path, text, err);
  if (tmp.empty()) return err;
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    err = fmt::format("cannot rename {} to {}: {}", tmp, path, std::strerror(errno));
    ::unlink(tmp.c_str());
    return err;
  }
  fsync_dir(fs::path(path).parent_path());
  return {};
}

StoreFolder::StoreFolder(std::string dir, ParseOptions opt) : dir_(std::move(dir)), opt_(opt) { opt_.number = -1; }

core::Diagnostic StoreFolder::error(std::string message) const {
  return {dir_, 0, 0, core::Severity::Error, std::move(message)};
}

std::string StoreFolder::path_of(int n) const {
  if (valid_number(n)) {
    auto files = scan_folder(dir_);
    const auto& p = files.path[static_cast<std::size_t>(n)];
    if (!p.empty()) return p;
  }
  return (fs::path(dir_) / canonical_name(n)).string();
}

core::Diagnostics StoreFolder::check() const {
  if (!fs::is_directory(dir_)) return {error("not a program store folder")};
  ProgramStore store;
  return store.load_folder(dir_, opt_);
}

std::vector<ProgramInfo> StoreFolder::list(core::Diagnostics& out) const {
  std::vector<ProgramInfo> v;
  if (!fs::is_directory(dir_)) {
    out.push_back(error("not a program store folder"));
    return v;
  }
  read_folder(dir_, out, [&](int n, const std::string& f, const std::string& text) {
    ParseOptions o = opt_;
    o.number = n;
    auto r = parse(text, f, o);
    out.insert(out.end(), r.diagnostics.begin(), r.diagnostics.end());
    if (r.program) v.push_back({n, r.program->size(), program_title(text), f});
  });
  return v;
}

std::optional<std::string> StoreFolder::read(int n, core::Diagnostics& out) const {
  if (!valid_number(n)) {
    out.push_back(error(fmt::format("P{}: a program number is 0..99", n)));
    return std::nullopt;
  }
  const auto files = scan_folder(dir_);
  const auto& f = files.path[static_cast<std::size_t>(n)];
  if (f.empty()) {
    out.push_back(error(fmt::format("program P{} is not in the store", n)));
    return std::nullopt;
  }
  auto text = read_text_file(f);
  if (!text) out.push_back({f, 0, 0, core::Severity::Error, "cannot read the file"});
  return text;
}

std::vector<int> StoreFolder::callers_of(int n, core::Diagnostics& out) const {
  ProgramStore store;
  auto d = store.load_folder(dir_, opt_);
  // Only problems that hide a caller matter here (a file that does not parse); a caller's own
  // "call of a missing program" is the very thing the question is about.
  for (auto& x : d)
    if (x.message.find("which is empty or missing") == std::string::npos) out.push_back(std::move(x));
  std::vector<int> v;
  for (int m : store.numbers()) {
    if (m == n) continue;
    for (const auto& ins : store.get(m)->ir.instructions) {
      const auto* call = std::get_if<SpcCall>(&ins.op);
      if (call && !call->via_reg && call->program == n) {
        v.push_back(m);
        break;
      }
    }
  }
  return v;
}

StoreChange StoreFolder::import(const std::vector<ImportItem>& items) const {
  StoreChange res;
  if (!fs::is_directory(dir_)) {
    res.diagnostics.push_back(error("not a program store folder (create it first)"));
    return res;
  }
  if (items.empty()) {
    res.diagnostics.push_back(error("nothing to import"));
    return res;
  }
  // 1. The new programs, each parsed as `softmc run` parses it.
  std::array<const ImportItem*, kPrograms> incoming{};
  ProgramStore store;
  for (const auto& it : items) {
    if (!valid_number(it.number)) {
      res.diagnostics.push_back({it.source, 0, 0, core::Severity::Error,
                                 fmt::format("P{}: a program number is 0..99", it.number)});
      continue;
    }
    if (incoming[static_cast<std::size_t>(it.number)]) {
      res.diagnostics.push_back({it.source, 0, 0, core::Severity::Error,
                                 fmt::format("program P{} is also imported from {}", it.number,
                                             incoming[static_cast<std::size_t>(it.number)]->source)});
      continue;
    }
    incoming[static_cast<std::size_t>(it.number)] = &it;
    store.add(it.number, it.text, it.source, opt_, res.diagnostics);
  }
  // 2. The rest of the store as it is on disk; its problems block the import too: only a store that
  //    checks clean is written (an import may be what repairs it: a replaced file's own errors do not count).
  auto files = scan_folder(dir_);
  for (auto& d : files.diagnostics) res.diagnostics.push_back(std::move(d));
  for (int n = 0; n < kPrograms; ++n) {
    const auto& f = files.path[static_cast<std::size_t>(n)];
    if (f.empty() || incoming[static_cast<std::size_t>(n)]) continue;
    const auto text = read_text_file(f);
    if (!text) {
      res.diagnostics.push_back({f, 0, 0, core::Severity::Error, "cannot read the file"});
      continue;
    }
    store.add(n, *text, f, opt_, res.diagnostics);
  }
  // 3. Across programs: callers of a replaced program are checked against its new text (S-4).
  auto v = store.validate();
  res.diagnostics.insert(res.diagnostics.end(), v.begin(), v.end());
  if (!res.ok()) return res;

  // 4. Act: every temp file first, then the renames, so a failed write leaves the store untouched.
  std::vector<std::pair<std::string, std::string>> renames;  // temp → final
  for (const auto& it : items) {
    const auto final_path = (fs::path(dir_) / canonical_name(it.number)).string();
    std::string err;
    auto tmp = write_temp(final_path, it.text, err);
    if (tmp.empty()) {
      for (const auto& [t, f] : renames) ::unlink(t.c_str());
      res.diagnostics.push_back(error(err));
      res.write_failed = true;
      return res;
    }
    renames.emplace_back(std::move(tmp), final_path);
  }
  for (std::size_t i = 0; i < items.size(); ++i) {
    const auto& [tmp, final_path] = renames[i];
    if (::rename(tmp.c_str(), final_path.c_str()) != 0) {
      res.diagnostics.push_back(error(fmt::format("cannot rename {} to {}: {}", tmp, final_path, std::strerror(errno))));
      for (std::size_t j = i; j < renames.size(); ++j) ::unlink(renames[j].first.c_str());
      res.write_failed = true;
      return res;
    }
    // An old file of the same number under another spelling (p3.spc, P03.spc) goes, or it would shadow.
    const auto& old = files.path[static_cast<std::size_t>(items[i].number)];
    if (!old.empty() && fs::path(old).filename() != fs::path(final_path).filename()) ::unlink(old.c_str());
    res.changed.push_back(items[i].number);
  }
  fsync_dir(dir_);
  return res;
}

StoreChange StoreFolder::remove(int n, bool force) const {
  StoreChange res;
  if (!valid_number(n)) {
    res.diagnostics.push_back(error(fmt::format("P{}: a program number is 0..99", n)));
    return res;
  }
  const auto files = scan_folder(dir_);
  const auto& f = files.path[static_cast<std::size_t>(n)];
  if (f.empty()) {
    res.diagnostics.push_back(error(fmt::format("program P{} is not in the store", n)));
    return res;
  }
  core::Diagnostics load_problems;
  const auto callers = callers_of(n, load_problems);
  if (!callers.empty()) {
    std::string names;
    for (int c : callers) names += fmt::format("{}P{}", names.empty() ? "" : ", ", c);
    if (!force) {
      res.diagnostics.push_back(
          {f, 0, 0, core::Severity::Error,
           fmt::format("program P{} is called by {}; deleting it would break them (--force deletes it anyway)", n,
                       names)});
      return res;
    }
    res.diagnostics.push_back({f, 0, 0, core::Severity::Warning,
                               fmt::format("deleted although {} call it: the store no longer checks", names)});
  }
  if (::unlink(f.c_str()) != 0) {
    res.diagnostics.push_back({f, 0, 0, core::Severity::Error, fmt::format("cannot delete: {}", std::strerror(errno))});
    res.write_failed = true;
    return res;
  }
  fsync_dir(dir_);
  res.changed.push_back(n);
  return res;
}

StoreChange StoreFolder::export_to(const std::vector<int>& numbers, const std::string& to_dir) const {
  StoreChange res;
  if (!fs::is_directory(to_dir)) {
    res.diagnostics.push_back({to_dir, 0, 0, core::Severity::Error, "not a folder"});
    return res;
  }
  std::vector<std::pair<int, std::string>> texts;
  std::set<int> seen;
  for (int n : numbers) {
    if (!seen.insert(n).second) continue;
    auto t = read(n, res.diagnostics);
    if (t) texts.emplace_back(n, std::move(*t));
  }
  if (!res.ok()) return res;
  for (const auto& [n, text] : texts) {
    const auto out = (fs::path(to_dir) / canonical_name(n)).string();
    std::error_code ec;
    if (fs::equivalent(fs::path(out), fs::path(path_of(n)), ec)) {
      res.changed.push_back(n);  // exporting a store onto itself: the file is already there
      continue;
    }
    if (auto err = write_file_atomically(out, text); !err.empty()) {
      res.diagnostics.push_back({out, 0, 0, core::Severity::Error, err});
      res.write_failed = true;
      return res;
    }
    res.changed.push_back(n);
  }
  return res;
}

}  // namespace softmc::program::spc
