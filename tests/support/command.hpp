#pragma once
// Runs the real `camplace` binary as a user would (tests of the command-line tool).
#include <string>

namespace camplace::testing {

struct CommandResult {
  int exit_code = -1;  ///< -1 when the process did not exit normally
  std::string output;  ///< stdout and stderr together
};

/// Runs `<camplace binary> args` through the shell, capturing stdout and stderr.
CommandResult run_camplace(const std::string& binary, const std::string& args);

}  // namespace camplace::testing
