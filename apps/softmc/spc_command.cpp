// `softmc run STORE`: resolve the options, load the store and the scripts, run, print text or JSON.
#include "spc_command.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "program/spc/store.hpp"
#include "spc_simulation.hpp"

namespace softmc::app {

namespace {

namespace fs = std::filesystem;
using namespace control::spc;

bool print(const core::Diagnostics& d) {
  for (const auto& x : d) std::cerr << x.format() << '\n';
  return !core::has_errors(d);
}

// A folder is loaded and checked as a whole; a single P<n>.spc is a store of one program.
bool load_store(const std::string& path, bool record_select, program::spc::ProgramStore& store, int& single) {
  if (fs::is_directory(path)) return print(store.load_folder(path, {record_select, -1}));
  const int n = program::spc::program_number_from_file_name(fs::path(path).filename().string());
  if (n < 0) {
    std::cerr << path << ": error: an SPC program file is named P<n>.spc, n = 0..99\n";
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in) {
    std::cerr << path << ": error: cannot read the file\n";
    return false;
  }
  core::Diagnostics d;
  store.add(n, text.str(), path, {record_select, n}, d);
  const auto v = store.validate();
  d.insert(d.end(), v.begin(), v.end());
  single = n;
  return print(d);
}

const char* signal_state(const std::array<std::uint16_t, kIoModules>& out, IoAddress a) {
  return ((out[a.module] >> a.bit) & 1u) ? "1" : "0";
}

}  // namespace

int run_spc_command(const SpcCommandArgs& args, const machine::MachineConfig& cfg_in) {
  machine::MachineConfig cfg = cfg_in;
  if (!args.mode.empty()) {
    if (args.mode != "start-stop" && args.mode != "record-select") {
      std::cerr << "softmc: --mode must be start-stop or record-select (got " << args.mode << ")\n";
      return 1;
    }
    cfg.spc.mode = args.mode;
  }
  if (args.task_a) cfg.spc.task_a = *args.task_a;
  if (args.task_b) cfg.spc.task_b = *args.task_b;
  const bool record_select = cfg.spc.mode == "record-select";

  program::spc::ProgramStore store;
  int single = -1;
  if (!load_store(args.store, record_select, store, single)) return 1;
  if (single >= 0 && cfg.spc.task_a < 0 && cfg.spc.task_b < 0) cfg.spc.task_a = single;
  if (cfg.spc.task_a < 0 && cfg.spc.task_b < 0) {
    std::cerr << "softmc: no program for task A or B: give --task-a N / --task-b N or [spc] task_a / task_b\n";
    return 1;
  }
  for (const auto& [name, n] : {std::pair{"A", cfg.spc.task_a}, std::pair{"B", cfg.spc.task_b}})
    if (n >= 0 && !store.get(n)) {
      std::cerr << fmt::format("softmc: task {} program P{} is not in the store {}\n", name, n, args.store);
      return 1;
    }

  SpcRunConfig rc;
  rc.controller = controller_config_from(cfg.spc);
  rc.until_s = args.until_s;
  if (!args.stimulus.empty()) {
    auto r = load_stimulus(args.stimulus);
    if (!print(r.diagnostics)) return 1;
    rc.stimulus = std::move(r.stimulus);
  } else if (args.plc.empty()) {
    rc.stimulus = default_stimulus(rc.controller);
  }
  if (!args.plc.empty()) {
    auto r = load_plc_script(args.plc);
    if (!print(r.diagnostics)) return 1;
    rc.plc = std::move(r.script);
  }
  std::string registers = args.registers.empty() ? cfg.spc.registers_file : args.registers;
  if (registers.empty())
    registers = ((fs::is_directory(args.store) ? fs::path(args.store) : fs::path(args.store).parent_path()) /
                 "registers.sqlite").string();
  rc.record = !args.trace_csv.empty() || !args.plot.empty();

  const auto res = run_spc(store, cfg, rc, registers);

  const std::string mode = record_select ? "record-select" : "start-stop";
  if (!args.trace_csv.empty()) report::write_spc_trace_csv(args.trace_csv, res.trace);
  if (!args.plot.empty())
    report::write_spc_plot(args.plot, res.trace,
                           fmt::format("{} — {} on {}", args.store, mode, args.machine_label));
  const auto sigs = report::spc_signals(record_select);
  if (args.json) {
    nlohmann::json j;
    j["store"] = args.store;
    j["machine"] = args.machine_label;
    j["mode"] = mode;
    j["task_a"] = cfg.spc.task_a;
    j["task_b"] = cfg.spc.task_b;
    j["registers_file"] = registers;
    j["ok"] = res.ok;
    j["t_end_s"] = res.t_end_s;
    j["cycles"] = res.cycles;
    nlohmann::json pos = nlohmann::json::object();
    for (std::size_t i = 0; i < program::kSpcAxes; ++i)
      if (res.trace.axes & (1u << i)) pos[std::string(1, program::kSpcAxisLetters[i])] = res.final_mm[i];
    j["final_mm"] = pos;
    nlohmann::json outs = nlohmann::json::object();
    for (const auto& s : sigs)
      if (s.addr.output) outs[s.name] = ((res.outputs[s.addr.module] >> s.addr.bit) & 1u) != 0;
    j["outputs"] = outs;
    j["errors"] = nlohmann::json::array();
    for (const auto& e : res.errors)
      j["errors"].push_back({{"t_s", e.t_s}, {"task", e.task < 0 ? "" : (e.task == 0 ? "A" : "B")}, {"program", e.program},
                             {"line", e.line}, {"message", e.message}, {"text", e.text}});
    j["tasks"] = nlohmann::json::array();
    for (int t = 0; t < 2; ++t) {
      const auto& ts = res.tasks[static_cast<std::size_t>(t)];
      j["tasks"].push_back({{"task", t == 0 ? "A" : "B"}, {"program", t == 0 ? cfg.spc.task_a : cfg.spc.task_b},
                            {"running", ts.running}, {"line", ts.line},
                            {"instructions", res.instructions[static_cast<std::size_t>(t)]}});
    }
    if (res.plc) {
      j["plc"] = nlohmann::json::array();
      for (const auto& c : *res.plc)
        j["plc"].push_back({{"ordered", c.ordered}, {"accepted", c.accepted}, {"completed", c.completed},
                            {"failed", c.failed}, {"interrupted", c.interrupted}, {"order_errors", c.order_errors},
                            {"motion_errors", c.motion_errors}});
    }
    if (!args.trace_csv.empty()) j["trace"] = args.trace_csv;
    if (!args.plot.empty()) j["plot"] = args.plot;
    std::cout << j.dump() << '\n';
  } else {
    std::cout << fmt::format("store        {}\nmachine      {}\nmode         {}  (task A: P{}, task B: P{})\n", args.store,
                             args.machine_label, mode, cfg.spc.task_a, cfg.spc.task_b);
    std::cout << fmt::format("ran          {:.3f} s ({} cycles)\n", res.t_end_s, res.cycles);
    std::cout << "final        ";
    for (std::size_t i = 0; i < program::kSpcAxes; ++i)
      if (res.trace.axes & (1u << i)) std::cout << fmt::format("{}={:.2f} ", program::kSpcAxisLetters[i], res.final_mm[i]);
    std::cout << "\noutputs      ";
    for (const auto& s : sigs)
      if (s.addr.output) std::cout << s.name << '=' << signal_state(res.outputs, s.addr) << ' ';
    std::cout << '\n';
    if (res.plc)
      for (int t = 0; t < 2; ++t) {
        const auto& c = (*res.plc)[static_cast<std::size_t>(t)];
        std::cout << fmt::format("plc {}        ordered {} accepted {} completed {} failed {} interrupted {}\n",
                                 t == 0 ? 'A' : 'B', c.ordered, c.accepted, c.completed, c.failed, c.interrupted);
      }
    std::cout << "registers    " << registers << '\n';
    if (!args.trace_csv.empty()) std::cout << "trace        " << args.trace_csv << '\n';
    if (!args.plot.empty()) std::cout << "plot         " << args.plot << '\n';
  }
  for (const auto& e : res.errors) std::cerr << "softmc: READY=0: " << e.text << '\n';
  return res.ok ? 0 : 2;
}

}  // namespace softmc::app
