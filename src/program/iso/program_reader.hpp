// The ISO program reader's class, shared by parser.cpp (lines, blocks, diagnostics) and program_flow.cpp (internal).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_set>
#include <utility>
#include <vector>

#include "program/iso/block.hpp"
#include "program/iso/cutter_comp.hpp"
#include "program/iso/fast_block.hpp"
#include "program/iso/flow_index.hpp"
#include "program/iso/interpreter.hpp"
#include "program/iso/lexer.hpp"
#include "program/iso/line_error.hpp"
#include "program/iso/m_functions.hpp"
#include "program/iso/modal_state.hpp"
#include "program/iso/parameters.hpp"
#include "program/iso/parser.hpp"

namespace softmc::program::iso::detail {

// The whole file in one read (parser.cpp); the error, if it cannot be read.
std::optional<std::string> read_text(const std::string& path, std::string& text);

struct SourceFile {
  std::string path;
  std::string text;
  std::vector<std::string_view> lines;
  FlowIndex flow;
};

struct LoopCount {
  std::size_t file = 0, line = 0;
  std::size_t count = 0;
  long long repeat_left = 0;
};

struct CallFrame {
  std::size_t file = 0, return_line = 0;
  std::vector<LoopCount> loops;
  // An M98 call of a Fanuc-style subprogram: its named locals are its own, #1…#30 the caller's
  // (LinuxCNC); its O line, and the passes left including the present one (M98 L).
  bool m98 = false;
  std::size_t program_line = 0;
  long long passes_left = 0;
  // M70/M73: the modal state saved at this call level (each call its own, the main program one);
  // M73 also restores it when the call returns (endsub, return, each pass's M99).
  std::optional<ModalState> saved_modes;
  bool autorestore = false;
  void forget_modes() {  // M71, and each M98 pass's end
    saved_modes.reset();
    autorestore = false;
  }
};

// Reads one program (parser.cpp's diagram): the lines of its files, plain blocks through the
// interpreter, O-word flow and calls (program_flow.cpp), and every diagnostic.
class ProgramReader {
 public:
  ProgramReader(const std::string& file, const ParseOptions& opt);

  ParseResult run(std::string text);

 private:
  std::size_t file_rank(const std::string& name) const;

  // The work limits (ParseOptions): one pass over every line read, plus what loops and calls add.
  std::size_t block_limit() const { return total_lines_ + opt_.max_blocks; }
  std::size_t instruction_limit() const { return 2 * total_lines_ + opt_.max_instructions; }
  std::size_t instructions_made() const { return sunk_ + program_.instructions.size(); }

  void flush_to_sink();
  std::size_t add_file(const std::string& path, std::string text);

  // ---- plain blocks (parser.cpp) ----

  void read_line(std::size_t f, std::size_t pc);
  bool aborts(std::size_t f, std::size_t pc);
  void emit_messages(std::size_t f, std::size_t pc, std::uint32_t col);
  void deliver(const core::SourceLoc& loc, const core::Vec& before);
  void switch_comp(const core::SourceLoc& loc, const core::Vec& before);
  void put(Instruction ins);
  void lex(std::string_view line, std::size_t pc);

  // Where the tool is: under cutter compensation the compensated end of the last move (the
  // programmed end moved by the tool radius along its normal there), as LinuxCNC's #5420… give it.
  const core::Vec& tool_position() const { return comp_.active() ? comp_.tool_position() : state_.position; }

  void update_position_parameters();
  void fail(std::size_t f, std::size_t pc, std::string_view line, LineError e);

  // ---- O-words (program_flow.cpp) ----

  bool eval_o(std::size_t f, std::size_t pc, OWord& out);
  bool condition(std::size_t f, std::size_t pc, bool& value);
  LoopCount* loop(std::size_t f, std::size_t line);
  void drop_loop(std::size_t f, std::size_t line);
  bool count_pass(std::size_t f, std::size_t line, const OEntry& e);
  void o_line(const OEntry& e, std::size_t& f, std::size_t& pc);
  bool find_sub(const std::string& name, std::size_t f, std::size_t& sub_file, std::size_t& sub_line, std::string& why);
  void call(const OEntry& e, std::size_t& f, std::size_t& pc);
  bool enter_call(std::size_t f, std::size_t pc, std::uint32_t col, const char* what, CallFrame frame);
  // Back to the caller from the return at (f, pc) (`col`: its word, for a restore's error).
  void return_from_sub(std::size_t& f, std::size_t& pc, std::uint32_t col = 1);

  // ---- Fanuc-style subprograms: M98 P<n> [L<k>] calls O<n> … M99 (program_flow.cpp) ----

  enum class Found : std::uint8_t { Yes, Rejected, No };  // find_program's answer
  Found find_program(std::size_t f, long long p, bool has_l, long long& passes, std::size_t& pf, std::size_t& line);
  void call_m98(std::size_t f, std::size_t pc, const Word& m);
  void m99(const OEntry& e, std::size_t& f, std::size_t& pc);

  // ---- modal state: M70 save, M71 invalidate, M72 restore, M73 save and restore on return (program_flow.cpp) ----

  void modal_state_m(std::size_t f, std::size_t pc, const Word& m);
  bool restore_modes(const ModalState& saved, std::size_t f, std::size_t pc, std::uint32_t col, std::string_view what);
  // M73: the modes the call level saved come back at its return (endsub, return, an M99).
  void autorestore(std::size_t f, std::size_t pc, std::uint32_t col);

  void finish();

  // ---- diagnostics (parser.cpp) ----

  static std::uint32_t line_no(std::size_t pc) {
    return static_cast<std::uint32_t>(std::min<std::size_t>(pc + 1, 0xFFFFFFFFu));
  }

  void add_error(std::size_t f, std::size_t pc, std::uint32_t col, std::string message);
  void add_error_loc(const core::SourceLoc& loc, std::string message);
  void add_error_at(const std::string& file, std::uint32_t line, std::uint32_t col, std::string message);
  void add_diag(std::size_t f, std::size_t pc, std::uint32_t col, core::Severity sev, std::string message);

  const MTable& mtable() const;

  const ParseOptions& opt_;
  InterpOptions interp_;
  Program program_;
  ModalState state_;
  core::SourceLoc nurbs_open_;  // the G5.2 word of the open NURBS block
  Parameters params_;
  CutterComp comp_;
  std::vector<Instruction> comp_out_;
  std::vector<std::unique_ptr<SourceFile>> files_;
  std::vector<CallFrame> frames_;
  std::optional<std::pair<std::size_t, std::size_t>> jump_;  // where a line's M98 goes next (file, line)
  std::string main_dir_;
  LexedLine lexed_;
  FastBlock fast_;
  Block block_;
  BlockOutput out_;
  core::Diagnostics diags_;
  std::optional<core::Diagnostic> note_;
  std::unordered_set<std::string> seen_;
  std::unordered_set<std::string> missing_subs_;  // searched for and not found: not searched again
  std::size_t errors_ = 0;
  std::size_t blocks_ = 0;
  std::size_t total_lines_ = 0;  // of every file read
  std::size_t sunk_ = 0;         // instructions handed to ParseOptions::sink
  bool position_params_stale_ = true;
  bool named_params_stale_ = true;  // the predefined named parameters, likewise
  bool seen_block_ = false;
  bool percent_open_ = false;
  bool back_edge_ = false;
  bool done_ = false;
};

}  // namespace softmc::program::iso::detail
