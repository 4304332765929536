// Address parsing and the table of system signal names for the SPC200 I/O image.
#include "control/spc/io_image.hpp"

#include <cctype>
#include <cstdio>

namespace softmc::control::spc {

namespace {

struct NamedSignal {
  std::string_view name;
  IoAddress addr;
};

// Both modes' names; the stimulus format and the HMI use them.
constexpr NamedSignal kSignals[] = {
    {"B0", {false, 0, 0}},         {"B1", {false, 0, 1}},         {"B2", {false, 0, 2}},
    {"B3", {false, 0, 3}},         {"B4", {false, 0, 4}},         {"SYNC_IB", sig::kSyncIB},
    {"SYNC_IA", sig::kSyncIA},     {"CLK_B", sig::kClkB},         {"CLK_A", sig::kClkA},
    {"STOP", sig::kStop},          {"START", sig::kStart},        {"RESET", sig::kReset},
    {"ENABLE", sig::kEnable},      {"MC_B", sig::kMcB},           {"MC_A", sig::kMcA},
    {"RC_B", sig::kRcB},           {"RC_A", sig::kRcA},           {"SYNC_OB", sig::kSyncOB},
    {"SYNC_OA", sig::kSyncOA},     {"ACK_B", sig::kAckB},         {"ACK_A", sig::kAckA},
    {"READY", sig::kReady},
};

bool iequal(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::toupper(static_cast<unsigned char>(a[i])) != std::toupper(static_cast<unsigned char>(b[i]))) return false;
  return true;
}

// Non-negative decimal of 1..2 digits; -1 if malformed.
int small_number(std::string_view s) {
  if (s.empty() || s.size() > 2) return -1;
  int v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return -1;
    v = v * 10 + (c - '0');
  }
  return v;
}

}  // namespace

std::optional<IoAddress> parse_address(std::string_view text) {
  if (text.size() < 4) return std::nullopt;
  const char k = static_cast<char>(std::toupper(static_cast<unsigned char>(text[0])));
  if (k != 'I' && k != 'Q') return std::nullopt;
  const auto dot = text.find('.');
  if (dot == std::string_view::npos) return std::nullopt;
  const int module = small_number(text.substr(1, dot - 1));
  const int bit = small_number(text.substr(dot + 1));
  if (module < 0 || bit < 0) return std::nullopt;
  const IoAddress a{k == 'Q', static_cast<std::uint8_t>(module), static_cast<std::uint8_t>(bit)};
  if (!valid(a)) return std::nullopt;
  return a;
}

std::optional<IoAddress> signal_address(std::string_view name) {
  for (const auto& s : kSignals)
    if (iequal(s.name, name)) return s.addr;
  return std::nullopt;
}

const char* format_address(IoAddress a, char* buf) {
  std::snprintf(buf, 6, "%c%u.%u", a.output ? 'Q' : 'I', static_cast<unsigned>(a.module) % 10u,
                static_cast<unsigned>(a.bit) % 100u);
  return buf;
}

}  // namespace softmc::control::spc
