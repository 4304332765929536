// Runs the real `softmc` binary of this build with arguments, stdout and stderr kept apart.
#pragma once

#include <string>

namespace softmc::test {

struct CliRun {
  int exit = -1;
  std::string out, err;
};

// `softmc ARGS` (ARGS as a shell would split them); the binary is the build's apps/softmc/softmc.
CliRun run_softmc(const std::string& args);

}  // namespace softmc::test
