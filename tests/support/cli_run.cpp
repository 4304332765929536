// The real softmc binary, found beside the test binaries (build/tests/X → build/apps/softmc/softmc).
#include "cli_run.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace softmc::test {

CliRun run_softmc(const std::string& args) {
  namespace fs = std::filesystem;
  CliRun r;
  const auto exe = fs::read_symlink("/proc/self/exe").parent_path().parent_path() / "apps/softmc/softmc";
  if (!fs::exists(exe)) {
    r.err = exe.string() + " not built (cmake --build ... --target softmc)";
    return r;
  }
  const auto err_file = fs::temp_directory_path() / ("softmc_cli_err_" + std::to_string(::getpid()));
  const std::string cmd = exe.string() + " " + args + " 2>" + err_file.string();
  std::FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), p)) r.out += buf.data();
  r.exit = WEXITSTATUS(::pclose(p));
  std::ifstream in(err_file, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  r.err = ss.str();
  fs::remove(err_file);
  return r;
}

}  // namespace softmc::test
