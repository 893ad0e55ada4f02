#pragma once
/// How the long commands (optimize, study, validate) stop on a signal (issue 16): the first
/// SIGINT (Ctrl-C), SIGTERM (kill, a batch system's time limit) or SIGHUP (a closed terminal)
/// sets one flag; the command finishes what is under way, writes its results and throws
/// Interrupted, which main turns into the exit status 128 + the signal's number (130, 143, 129),
/// as a shell reports a process the signal ended. A second Ctrl-C ends the process at once;
/// repeated SIGTERM or SIGHUP change nothing (a study forwards them to its run, which may have
/// had its own already).
#include <atomic>
#include <stdexcept>
#include <string>

namespace camplace::app {

/// Installs the handlers for its lifetime and restores the previous ones afterwards.
class InterruptSignals {
 public:
  InterruptSignals();
  ~InterruptSignals();
  InterruptSignals(const InterruptSignals&) = delete;
  InterruptSignals& operator=(const InterruptSignals&) = delete;

  /// Set by the first of the three signals (lock-free, written by the handler).
  static std::atomic<bool>& flag();
  /// The signal that set flag(), 0 if none.
  static int received();
  /// Also send each SIGTERM and SIGHUP to this process (0: none), e.g. a study's current run.
  static void forward_to(int pid);
};

/// Thrown by a command that stopped on a signal after writing its results; main prints the
/// message and exits with 128 + received() (130 if no signal was recorded).
struct Interrupted : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The exit status for an interrupted command: 128 + the signal's number.
int interrupted_exit_status();

}  // namespace camplace::app
