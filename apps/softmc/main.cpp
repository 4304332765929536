// softmc command line: run, check, config.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "control/travel_check.hpp"
#include "machine/config.hpp"
#include "program/iso/interp_config.hpp"
#include "program/iso/parser.hpp"
#include "program/spc/store.hpp"
#include "report/plot.hpp"
#include "report/summary.hpp"
#include "gcode_setup.hpp"
#include "homing_run.hpp"
#include "moves.hpp"
#include "simulation.hpp"
#include "spc_admin.hpp"
#include "spc_command.hpp"

namespace {

using namespace softmc;

struct MachineArgs {
  std::string file;
  std::vector<std::string> overrides;

  void add_to(CLI::App* cmd) {
    cmd->add_option("--machine", file, "machine configuration (TOML); default: the built-in cutting table");
    cmd->add_option("--set", overrides, "override one configuration key, e.g. --set axes.x.max_vel_mm_s=100")
        ->type_name("KEY=VALUE");
  }
  machine::MachineConfig load() const {
    auto cfg = file.empty() ? machine::default_machine() : machine::load_machine(file);
    for (const auto& o : overrides) machine::apply_override(cfg, o);
    machine::validate(cfg);
    return cfg;
  }
};

// How many diagnostics `softmc run` prints on stderr before it only counts the rest (a program
// that leaves the travel on every line of a long contour would print one per line).
constexpr std::size_t kRunDiagnosticsShown = 20;

// Prints diagnostics on stderr, at most `shown` of them (then how many more and where to see them).
void print_diagnostics(const core::Diagnostics& d, std::size_t shown, const std::string& path) {
  for (std::size_t i = 0; i < d.size() && i < shown; ++i) std::cerr << d[i].format() << '\n';
  if (d.size() > shown)
    std::cerr << fmt::format("softmc: {} more not shown ({} in all; `softmc check {}` lists every one)\n",
                             d.size() - shown, d.size(), path);
}

// The program's diagnostics as `softmc run --json` prints a program it did not run.
std::string rejection_json(const std::string& path, const std::string& machine, const core::Diagnostics& d) {
  auto list = nlohmann::ordered_json::array();
  for (const auto& x : d)
    list.push_back(nlohmann::ordered_json{{"file", x.file},
                    {"line", x.line},
                    {"col", x.col},
                    {"severity", x.severity == core::Severity::Error ? "error" : "warning"},
                    {"message", x.message}});
  nlohmann::ordered_json j{{"program", path}, {"machine", machine}, {"result", "rejected"}, {"diagnostics", list}};
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// Parses a program and checks its path against the travel; every diagnostic goes to `diags`.
// Returns nothing on any error.
// `start`: the machine position the program starts from (default: the origin).
std::optional<program::Program> load_program(const std::string& path, const machine::MachineConfig& cfg,
                                             core::Diagnostics& diags, const core::Vec* start = nullptr) {
  const auto setup = app::gcode_setup(cfg);
  auto popt = setup->options();
  if (start) popt.start = *start;
  auto r = program::iso::parse_file(path, popt);
  // Validate the whole thing, then act: the path must stay inside the travel (P-9) before anything moves.
  if (r.program) {
    auto travel = control::check_travel(*r.program, cfg.limits());
    r.diagnostics.insert(r.diagnostics.end(), travel.begin(), travel.end());
  }
  diags = std::move(r.diagnostics);
  if (core::has_errors(diags)) return std::nullopt;
  return std::move(r.program);
}

class ProgressBar {
 public:
  explicit ProgressBar(bool enabled) : enabled_(enabled) {}
  void operator()(double f) {
    if (!enabled_) return;
    const int pct = static_cast<int>(f * 100.0 + 0.5);
    if (pct == last_) return;
    last_ = pct;
    constexpr int kWidth = 40;
    const int fill = pct * kWidth / 100;
    std::fprintf(stderr, "\rsimulating [%s%s] %3d%%", std::string(fill, '#').c_str(),
                 std::string(kWidth - fill, '.').c_str(), pct);
    if (pct >= 100) std::fputc('\n', stderr);
    std::fflush(stderr);
  }

 private:
  bool enabled_;
  int last_ = -1;
};

// `softmc run --home`: the start-up sequence first (T-4, T-5), its figures on stdout (text) or as the
// summary's "homing" member (JSON).
struct HomeArgs {
  bool home = false;
  std::vector<std::string> power_up;  // AXIS=MM
};

core::Vec power_up_positions(const HomeArgs& h, const machine::MachineConfig& cfg) {
  core::Vec p = app::mid_travel(cfg);
  for (const auto& w : h.power_up) {
    const auto eq = w.find('=');
    const auto ax = eq == 1 ? core::axis_from_letter(w[0]) : std::nullopt;
    if (!ax || !cfg.axis(*ax))
      throw std::runtime_error("--power-up " + w + ": expected AXIS=MM with an axis of the machine (X=120)");
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(w.substr(2), &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != w.size() - 2 || !std::isfinite(v))
      throw std::runtime_error("--power-up " + w + ": expected AXIS=MM with a number of mm (X=120)");
    p[*ax] = v;
  }
  return p;
}

nlohmann::ordered_json homing_json(const app::HomingRunResult& h, const machine::MachineConfig& cfg) {
  nlohmann::ordered_json axes = nlohmann::ordered_json::object();
  for (const auto& a : cfg.axes) {
    if (!a.enabled) continue;
    const auto& r = h.axis[a.index];
    axes[std::string(1, core::letter(a.index))] = {{"homed", r.homed}, {"power_up_mm", r.power_up_mm},
                                                   {"switch_mm", r.switch_mm}, {"position_mm", r.position_mm},
                                                   {"true_mm", r.true_mm}, {"reference_error_mm", r.reference_error_mm},
                                                   {"overshoot_mm", r.overshoot_mm}, {"time_s", r.time_s}};
  }
  return {{"result", h.result}, {"time_s", h.time_s}, {"axes", axes}};
}

std::string homing_text(const app::HomingRunResult& h, const machine::MachineConfig& cfg) {
  if (!h.ok) return fmt::format("homing       failed: {}\n", h.result);
  std::string s = fmt::format("homing       {} in {:.3f} s\n", h.result, h.time_s);
  for (const auto& a : cfg.axes) {
    if (!a.enabled) continue;
    const auto& r = h.axis[a.index];
    if (!r.homed) {
      s += fmt::format("  {}          not homed (no limit switches): reading 0 where it stands\n", core::letter(a.index));
      continue;
    }
    s += fmt::format("  {}          switch at {:.3f} mm, now at {:.3f} mm, reference error {:+.4f} mm, at most {:.3f} mm "
                     "past the switch, done at {:.3f} s\n",
                     core::letter(a.index), r.switch_mm, r.position_mm, r.reference_error_mm, r.overshoot_mm, r.time_s);
  }
  return s;
}

int cmd_run(const std::string& path, const MachineArgs& margs, const std::string& plot, const std::string& trace_csv,
            bool json, const std::string& stimulus_file, const HomeArgs& home_args) {
  const auto cfg = margs.load();
  const std::string machine_name = margs.file.empty() ? cfg.name + " (built-in)" : margs.file;
  std::optional<app::HomingRunResult> homed;
  if (!home_args.home && !home_args.power_up.empty()) throw std::runtime_error("--power-up needs --home");
  if (home_args.home) {
    homed.emplace(app::run_homing(cfg, power_up_positions(home_args, cfg)));
    if (!homed->ok) {
      if (json) std::cout << homing_json(*homed, cfg).dump() << '\n';
      else std::cout << homing_text(*homed, cfg);
      std::cerr << "softmc: " << homed->result << '\n';
      return 2;
    }
  }
  core::Diagnostics diags;
  const auto prog = load_program(path, cfg, diags, homed ? &homed->position : nullptr);
  // Every diagnostic in the JSON object of a rejected program; on stderr the first few.
  if (!prog && json) std::cout << rejection_json(path, machine_name, diags) << '\n';
  else print_diagnostics(diags, kRunDiagnosticsShown, path);
  // The PLC's motion signals over time (docs/cli.md): checked whole before anything moves.
  std::optional<control::ChannelStimulus> stimulus;
  if (!stimulus_file.empty()) {
    auto st = control::load_channel_stimulus(stimulus_file, cfg.axis_mask());
    for (const auto& d : st.diagnostics) std::cerr << d.format() << '\n';
    if (!st.stimulus) return 1;
    stimulus = std::move(st.stimulus);
  }
  if (!prog) return 1;
  app::SimOptions opt;
  if (stimulus) opt.stimulus = &*stimulus;
  if (homed) opt.drives = &homed->drives;
  ProgressBar bar(!json);
  opt.on_progress = [&](double f) { bar(f); };
  // The summary and the CSV are made row by row: only a plot keeps the trace in memory.
  report::SummaryBuilder builder(*prog, cfg, cfg.period_s, cfg.axis_mask());
  std::optional<report::TraceCsvWriter> csv;
  if (!trace_csv.empty()) csv.emplace(trace_csv, cfg.axis_mask(), builder.locations());
  opt.record = !plot.empty();
  opt.on_row = [&](const report::TraceRow& row) {
    builder.add(row);
    if (csv) csv->add(row);
  };
  const auto res = app::simulate(*prog, cfg, opt);
  if (csv) csv->close();
  auto summary = builder.finish();
  summary.program = path;
  summary.machine = machine_name;
  summary.result = res.result;
  if (!plot.empty()) {
    // The stimulus's writes up to the run's end, marked on the speed panel (one label per time).
    std::vector<report::PlotEvent> events;
    const double end_s = res.trace.rows.empty() ? 0.0 : res.trace.rows.back().t_s;
    if (stimulus)
      for (const auto& e : stimulus->events) {
        const auto label = control::short_label(e);
        if (label.empty() || e.t_s > end_s) continue;
        if (!events.empty() && events.back().t_s == e.t_s) events.back().label += ", " + label;
        else events.push_back({e.t_s, label});
      }
    report::write_plot(plot, *prog, cfg, res.trace, events);
  }
  if (json) {
    if (homed) {
      auto j = report::to_json_object(summary);
      j["homing"] = homing_json(*homed, cfg);
      std::cout << j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) << '\n';
    } else {
      std::cout << report::to_json(summary) << '\n';
    }
  } else {
    if (homed) std::cout << homing_text(*homed, cfg);
    std::cout << report::to_text(summary);
    if (!trace_csv.empty()) std::cout << "trace        " << trace_csv << '\n';
    if (!plot.empty()) std::cout << "plot         " << plot << '\n';
  }
  if (!res.ok) std::cerr << "softmc: run stopped: " << res.result << '\n';
  else if (res.stopped && !json) std::cerr << "softmc: " << res.result << '\n';
  return res.ok ? 0 : 2;
}

// SPC (spc200.md): a P<n>.spc file, or a folder = a program store (every P<n>.spc, calls checked across).
bool is_spc(const std::string& path) {
  namespace fs = std::filesystem;
  return fs::is_directory(path) || fs::path(path).extension() == ".spc" || fs::path(path).extension() == ".SPC";
}
bool check_spc(const std::string& path) {
  namespace fs = std::filesystem;
  core::Diagnostics d;
  if (fs::is_directory(path)) {
    program::spc::ProgramStore store;
    d = store.load_folder(path);
  } else {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    if (!in) d.push_back({path, 0, 0, core::Severity::Error, "cannot read the file"});
    else {
      const int n = program::spc::program_number_from_file_name(fs::path(path).filename().string());
      d = program::spc::parse(text.str(), path, {false, n}).diagnostics;
    }
  }
  for (const auto& x : d) std::cerr << x.format() << '\n';
  return !core::has_errors(d);
}

int cmd_check(const std::vector<std::string>& paths, const MachineArgs& margs) {
  const auto cfg = margs.load();
  int rc = 0;
  for (const auto& p : paths) {
    if (is_spc(p)) {
      if (!check_spc(p)) rc = 1;
      continue;
    }
    core::Diagnostics diags;
    if (!load_program(p, cfg, diags)) rc = 1;
    print_diagnostics(diags, diags.size(), p);
  }
  return rc;
}

// `softmc moves`: the interpreter's canonical output, one JSON object per line (docs/moves.md).
int cmd_moves(const std::string& path, const MachineArgs& margs) {
  const auto cfg = margs.load();
  // Streamed (moves.hpp): same options as load_program, output only for a program without errors.
  const auto setup = app::gcode_setup(cfg);
  const auto diags = app::write_program_moves(stdout, path, setup->options(), cfg.axis_mask());
  for (const auto& d : diags) std::cerr << d.format() << '\n';
  if (core::has_errors(diags)) return 1;
  return std::fflush(stdout) == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"softmc: a software motion controller"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "softmc 0.1.0");

  MachineArgs run_m, check_m, config_m;
  std::string run_prog, plot, trace_csv;
  bool json = false;
  auto* run = app.add_subcommand("run", "simulate a program on the machine in virtual time and report");
  run->add_option("program", run_prog, "part program (.ngc), or an SPC program store (a folder of P<n>.spc) or P<n>.spc")
      ->required()
      ->check(CLI::ExistingPath);
  run_m.add_to(run);
  run->add_option("--plot", plot, "write a plot (.svg or .png)");
  run->add_option("--trace", trace_csv, "write one CSV row per cycle");
  run->add_flag("--json", json, "print the summary as one JSON object");
  app::SpcCommandArgs spc_args;  // SPC runs (docs/spc.md): options over the [spc] configuration
  run->add_option("--mode", spc_args.mode, "SPC: start-stop or record-select");
  run->add_option("--task-a", spc_args.task_a, "SPC: start/record program of task A (0..99)");
  run->add_option("--task-b", spc_args.task_b, "SPC: start/record program of task B (0..99)");
  run->add_option("--stimulus", spc_args.stimulus,
                  "timed signal writes (time, signal, value): SPC input terminals, or for G-code the motion "
                  "signals (feed_override_permille, feed_hold, axis_enable[X], stop_request, ...)");
  run->add_option("--plc", spc_args.plc, "SPC: orders file for the reference PLC of S-10 (time, task, line)");
  run->add_option("--registers", spc_args.registers, "SPC: SQLite file of the retentive registers (:memory: = none)");
  run->add_option("--until", spc_args.until_s, "SPC: run this many seconds of virtual time");
  HomeArgs home_args;
  run->add_flag("--home", home_args.home,
                "G-code: home every axis with limit switches first (T-4), then run the program from there");
  run->add_option("--power-up", home_args.power_up,
                  "G-code, with --home: where a simulated axis stands at power-up, AXIS=MM (default: mid-travel)")
      ->delimiter(',');

  std::vector<std::string> check_progs;
  auto* check = app.add_subcommand("check", "parse and validate programs without moving anything");
  check->add_option("programs", check_progs, "part programs")->required();
  check_m.add_to(check);

  MachineArgs moves_m;
  std::string moves_prog;
  auto* moves = app.add_subcommand("moves", "print the interpreter's canonical moves and events as JSON Lines");
  moves->add_option("program", moves_prog, "part program (.ngc)")->required();
  moves_m.add_to(moves);

  auto* config = app.add_subcommand("config", "print the effective machine configuration as TOML");
  config_m.add_to(config);

  app::SpcAdminCli spc_admin(app);  // `programs STORE ...`, `registers ...` (docs/cli.md, S-12)

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  try {
    if (auto rc = spc_admin.run()) return *rc;
    if (*run && is_spc(run_prog) && home_args.home)
      throw std::runtime_error("--home homes the axes before a G-code program; SPC runs do not take it");
    if (*run && is_spc(run_prog)) {
      spc_args.store = run_prog;
      spc_args.trace_csv = trace_csv;
      spc_args.plot = plot;
      spc_args.json = json;
      spc_args.machine_label = run_m.file.empty() ? "cutting_table (built-in)" : run_m.file;
      return app::run_spc_command(spc_args, run_m.load());
    }
    if (*run) return cmd_run(run_prog, run_m, plot, trace_csv, json, spc_args.stimulus, home_args);
    if (*check) return cmd_check(check_progs, check_m);
    if (*moves) return cmd_moves(moves_prog, moves_m);
    if (*config) {
      std::cout << machine::to_toml(config_m.load());
      return 0;
    }
  } catch (const machine::ConfigError& e) {
    std::cerr << e.what() << '\n';
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "softmc: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
