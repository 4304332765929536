// `softmc programs` and `softmc registers`: command-line faces of program::spc::StoreFolder and io::RegisterAccess.
#include "spc_admin.hpp"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "io/register_access.hpp"
#include "machine/config.hpp"
#include "program/spc/store_folder.hpp"

namespace softmc::app {

namespace {

namespace fs = std::filesystem;
namespace spc = program::spc;

void print(const core::Diagnostics& d) {
  for (const auto& x : d) std::cerr << x.format() << '\n';
}

machine::MachineConfig load_config(const std::string& file) {
  auto cfg = file.empty() ? machine::default_machine() : machine::load_machine(file);
  machine::validate(cfg);
  return cfg;
}

// "12", "P12" or "p12" → 12; nothing otherwise.
std::optional<int> program_number(std::string_view s) {
  if (!s.empty() && (s[0] == 'P' || s[0] == 'p')) s.remove_prefix(1);
  int n = -1;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), n);
  if (s.empty() || ec != std::errc{} || p != s.data() + s.size() || n < 0 || n >= spc::kPrograms) return std::nullopt;
  return n;
}

// Parses every number first: a bad one refuses the whole command.
std::optional<std::vector<int>> program_numbers(const ProgramsArgs& a) {
  std::vector<int> v;
  bool ok = true;
  for (const auto& s : a.items) {
    if (auto n = program_number(s)) v.push_back(*n);
    else {
      std::cerr << fmt::format("{}: error: '{}' is not a program number (0..99 or P0..P99)\n", a.store, s);
      ok = false;
    }
  }
  if (!ok) return std::nullopt;
  return v;
}

int programs_list(const spc::StoreFolder& store, const machine::MachineConfig& cfg, bool json) {
  core::Diagnostics d;
  const auto list = store.list(d);
  print(d);
  auto start_of = [&](int n) -> std::string {
    std::string s;
    if (cfg.spc.task_a == n) s += "A";
    if (cfg.spc.task_b == n) s += "B";
    return s;
  };
  if (json) {
    auto j = nlohmann::json::array();
    for (const auto& p : list)
      j.push_back({{"number", p.number}, {"lines", p.lines}, {"title", p.title}, {"file", p.file},
                   {"start_task", start_of(p.number)}});
    std::cout << j.dump() << '\n';
  } else {
    for (const auto& p : list) {
      const auto start = start_of(p.number);
      std::cout << fmt::format("P{:<3} {:>4} lines  {:<9} {}\n", p.number, p.lines,
                               start.empty() ? "" : "start " + start, p.title);
    }
  }
  return core::has_errors(d) ? 1 : 0;
}

// Import: files named P<n>.spc (or one file with --as N); the store stays unchanged on any error.
int programs_import(const spc::StoreFolder& store, const ProgramsArgs& a) {
  if (a.as && a.items.size() != 1) {
    std::cerr << "softmc: --as N imports exactly one file\n";
    return 1;
  }
  std::vector<spc::ImportItem> items;
  bool ok = true;
  for (const auto& f : a.items) {
    const int n = a.as ? *a.as : spc::program_number_from_file_name(fs::path(f).filename().string());
    if (n < 0 || n >= spc::kPrograms) {
      std::cerr << fmt::format("{}:0:0: error: {}\n", f,
                               a.as ? "--as takes a program number 0..99"
                                    : "a program file is named P<n>.spc with n = 0..99 (or give --as N)");
      ok = false;
      continue;
    }
    auto text = spc::read_text_file(f);
    if (!text) {
      std::cerr << f << ":0:0: error: cannot read the file\n";
      ok = false;
      continue;
    }
    items.push_back({n, std::move(*text), f});
  }
  if (!ok) return 1;
  const auto r = store.import(items);
  print(r.diagnostics);
  if (!r.ok()) {
    if (r.changed.empty()) std::cerr << fmt::format("softmc: nothing imported; the store {} is unchanged\n", store.dir());
    return r.write_failed ? 2 : 1;
  }
  for (int n : r.changed) std::cout << fmt::format("imported P{} -> {}\n", n, store.path_of(n));
  return 0;
}

}  // namespace

int run_programs_command(const ProgramsArgs& a) {
  const auto cfg = load_config(a.machine);
  spc::ParseOptions opt;
  opt.record_select = cfg.spc.mode == "record-select";
  const spc::StoreFolder store(a.store, opt);

  if (a.action == "list") return programs_list(store, cfg, a.json);
  if (a.action == "check") {
    const auto d = store.check();
    print(d);
    return core::has_errors(d) ? 1 : 0;
  }
  if (a.action == "import") return programs_import(store, a);

  const auto numbers = program_numbers(a);
  if (!numbers) return 1;
  if (a.action == "show") {
    core::Diagnostics d;
    for (int n : *numbers)
      if (auto text = store.read(n, d)) std::cout << *text;
    print(d);
    return core::has_errors(d) ? 1 : 0;
  }
  if (a.action == "export") {
    const auto r = store.export_to(*numbers, a.to_dir);
    print(r.diagnostics);
    for (int n : r.changed) std::cout << fmt::format("exported P{} -> {}\n", n, (fs::path(a.to_dir) / fmt::format("P{}.spc", n)).string());
    return r.ok() ? 0 : (r.write_failed ? 2 : 1);
  }
  if (a.action == "delete") {
    if (numbers->size() != 1) {
      std::cerr << "softmc: delete takes one program number\n";
      return 1;
    }
    const auto r = store.remove(numbers->front(), a.force);
    print(r.diagnostics);
    for (int n : r.changed) std::cout << fmt::format("deleted P{}\n", n);
    return r.ok() ? 0 : (r.write_failed ? 2 : 1);
  }
  std::cerr << "softmc: programs: unknown action " << a.action << '\n';
  return 1;
}

int run_registers_command(const RegistersArgs& a) {
  std::string path = a.registers;
  if (path.empty() && !a.machine.empty()) path = load_config(a.machine).spc.registers_file;
  if (path.empty()) {
    if (a.store.empty()) {
      std::cerr << "softmc: registers: give a STORE folder or --registers FILE\n";
      return 1;
    }
    path = (fs::path(a.store) / "registers.sqlite").string();
  }
  const bool set = a.action == "set";
  const auto parsed = io::parse_register_args(a.words, set);
  for (const auto& e : parsed.errors) std::cerr << fmt::format("{}: error: {}\n", path, e);
  if (!parsed.errors.empty()) {
    if (set) std::cerr << fmt::format("softmc: nothing written; {} is unchanged\n", path);
    return 1;
  }
  if (set && parsed.writes.empty()) {
    std::cerr << "softmc: registers set: nothing to set (NAME=VALUE ...)\n";
    return 1;
  }
  // A get does not create the file: a mistyped path must not read as "all registers 0".
  if (!set && path != ":memory:" && !fs::exists(path)) {
    std::cerr << fmt::format("{}: error: no register file (softmc run or registers set creates it)\n", path);
    return 2;
  }
  try {
    io::RegisterAccess regs(path);
    if (set) {
      const auto errors = regs.set(parsed.writes);
      for (const auto& e : errors) std::cerr << fmt::format("{}: error: {}\n", path, e);
      if (!errors.empty()) {
        std::cerr << fmt::format("softmc: nothing written; {} is unchanged\n", path);
        return 1;
      }
      for (const auto& w : parsed.writes) std::cout << w.text() << '\n';
      return 0;
    }
    std::vector<std::string> errors;
    const auto values = parsed.refs.empty() ? regs.nonzero() : regs.get(parsed.refs, errors);
    for (const auto& e : errors) std::cerr << fmt::format("{}: error: {}\n", path, e);
    if (a.json) {
      auto j = nlohmann::json::object();
      for (const auto& v : values)
        j[v.ref.name()] = v.ref.kind == io::RegisterKind::Position ? nlohmann::json(static_cast<double>(v.value) / 100.0)
                                                                   : nlohmann::json(v.value);
      std::cout << j.dump() << '\n';
    } else {
      for (const auto& v : values) std::cout << v.text() << '\n';
    }
    return errors.empty() ? 0 : 1;
  } catch (const io::StoreError& e) {
    std::cerr << fmt::format("{}: error: {}\n", path, e.what());
    return 2;
  }
}

SpcAdminCli::SpcAdminCli(CLI::App& app) {
  programs_cmd_ = app.add_subcommand("programs", "the SPC program store: list, show, import, export, delete, check (S-12)");
  programs_cmd_->add_option("store", programs_.store, "program store folder (P<n>.spc files)")->required();
  programs_cmd_->add_option("--machine", programs_.machine, "configuration: [spc] mode and start programs");
  programs_cmd_->require_subcommand(1);
  programs_cmd_->fallthrough();  // `programs STORE list --machine M.toml` as well as before `list`
  auto action = [this](CLI::App* sub) { sub->callback([this, sub] { programs_.action = sub->get_name(); }); };
  auto* list = programs_cmd_->add_subcommand("list", "number, lines, title, start program");
  list->add_flag("--json", programs_.json, "one JSON array");
  action(list);
  auto* show = programs_cmd_->add_subcommand("show", "print programs as stored");
  show->add_option("numbers", programs_.items, "program numbers (3 or P3)")->required();
  action(show);
  auto* imp = programs_cmd_->add_subcommand("import", "add or replace programs from P<n>.spc files, all or nothing");
  imp->add_option("files", programs_.items, "program files")->required();
  imp->add_option("--as", programs_.as, "store the one file as this program number");
  action(imp);
  auto* exp = programs_cmd_->add_subcommand("export", "copy programs out as P<n>.spc");
  exp->add_option("numbers", programs_.items, "program numbers")->required();
  exp->add_option("--to", programs_.to_dir, "target folder (default: the current one)");
  action(exp);
  auto* del = programs_cmd_->add_subcommand("delete", "delete a program (refused while another calls it)");
  del->add_option("number", programs_.items, "program number")->required();
  del->add_flag("--force", programs_.force, "delete even if other programs call it");
  action(del);
  action(programs_cmd_->add_subcommand("check", "load and check the whole store"));

  registers_cmd_ = app.add_subcommand("registers", "retentive SPC registers @n X, Rn: get and set (S-5, S-12)");
  registers_cmd_->add_option("store", registers_.store, "program store folder (registers.sqlite in it)");
  registers_cmd_->add_option("--registers", registers_.registers, "SQLite register file");
  registers_cmd_->add_option("--machine", registers_.machine, "configuration: [spc] registers_file");
  registers_cmd_->require_subcommand(1);
  registers_cmd_->fallthrough();
  auto ract = [this](CLI::App* sub) { sub->callback([this, sub] { registers_.action = sub->get_name(); }); };
  auto* get = registers_cmd_->add_subcommand("get", "print registers (none named: every register that is not 0)");
  get->add_option("names", registers_.words, "@n X, Rn");
  get->add_flag("--json", registers_.json, "one JSON object");
  ract(get);
  auto* setc = registers_cmd_->add_subcommand("set", "write registers in one transaction, all or nothing");
  setc->add_option("assignments", registers_.words, "@n X=v, Rn=v")->required();
  ract(setc);
}

std::optional<int> SpcAdminCli::run() const {
  if (programs_cmd_ && programs_cmd_->parsed()) return run_programs_command(programs_);
  if (registers_cmd_ && registers_cmd_->parsed()) return run_registers_command(registers_);
  return std::nullopt;
}

}  // namespace softmc::app
