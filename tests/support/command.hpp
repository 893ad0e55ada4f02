#pragma once
// Runs the real `camplace` binary as a user would (tests of the command-line tool).
#include <sys/types.h>

#include <string>

namespace camplace::testing {

struct CommandResult {
  int exit_code = -1;  ///< -1 when the process did not exit normally
  std::string output;  ///< stdout and stderr together
};

/// Runs `<camplace binary> args` through the shell, capturing stdout and stderr.
CommandResult run_camplace(const std::string& binary, const std::string& args);

/// The whole content of the file at `path` ("" when it cannot be read).
std::string read_text(const std::string& path);

/// The standard output of a shell `command` (stderr not captured).
std::string capture(const std::string& command);

/// Waits up to `seconds` for the child `pid`; its wait status, or -1 on timeout (the child is
/// then killed with SIGKILL and reaped).
int wait_for(pid_t pid, double seconds);

}  // namespace camplace::testing
