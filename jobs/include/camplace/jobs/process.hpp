#pragma once
/// A child process started without a shell (fork + exec), its standard output in a file: what a
/// study runs for each `camplace optimize`. The child shares the caller's process group (Ctrl-C
/// in the terminal reaches both) and is ended with SIGTERM if the caller dies first; SIGTERM and
/// SIGHUP to the caller are passed on to it while it runs (InterruptSignals::forward_to).
#include <sys/types.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace camplace::jobs {

/// What to start: `PROGRAM ARGS...`, standard output into `output_file` (replaced).
struct ProcessLaunch {
  std::vector<std::string> args;  ///< the arguments after the program, one per entry
  std::string output_file;        ///< file that receives the process's standard output
};

/// How a process ended.
struct ProcessOutcome {
  /// A SIGINT, SIGTERM or SIGHUP came while it went (to it or to the caller): it then wrote its
  /// best result and exited with 128 + the signal, or died of the signal.
  bool interrupted = false;
  /// Empty when it exited with status 0 (or was interrupted); else how it ended, for messages
  /// ("exit status 1", "killed by signal 9 (Killed)", "could not be started: ...").
  std::string failure;
};

/// A running child process. While it lives, SIGINT only notes the Ctrl-C (the child handles
/// its own) and SIGQUIT is ignored, as std::system does.
class ChildProcess {
 public:
  /// Starts `program` (a path, no PATH search) with `launch`. Throws std::runtime_error when
  /// the output file cannot be written or the process cannot be forked; a failed exec is
  /// reported in the outcome ("could not be started: PROGRAM: ...").
  ChildProcess(const std::string& program, const ProcessLaunch& launch);
  /// A process still going (the caller failed meanwhile) is ended with SIGTERM and waited for.
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// How the process ended, or nothing while it goes on (does not wait).
  std::optional<ProcessOutcome> poll();
  /// How the process ended, once it has.
  ProcessOutcome wait();

 private:
  class Signals;
  std::optional<ProcessOutcome> reap(int options);
  ProcessOutcome outcome(int status) const;

  std::string program_;
  std::unique_ptr<Signals> signals_;
  pid_t pid_ = -1;
  int exec_error_ = 0;  ///< errno of a failed exec, 0 if it succeeded
};

/// Starts the process and waits for it.
ProcessOutcome run_process(const std::string& program, const ProcessLaunch& launch);

}  // namespace camplace::jobs
