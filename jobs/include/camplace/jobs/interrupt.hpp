#pragma once
/// How the long commands stop on a signal: the first SIGINT (Ctrl-C), SIGTERM (kill,
/// a batch system's time limit) or SIGHUP (a closed terminal) sets one flag; the command
/// finishes what is under way, writes its results and throws Interrupted, which main turns into
/// the exit status 128 + the signal's number (130, 143, 129), as a shell reports a process the
/// signal ended. A second Ctrl-C ends the process at once; repeated SIGTERM or SIGHUP change
/// nothing (a study forwards them to its run, which may have had its own already).
///
/// Work that cannot stop in between (an evaluator's set-up, one exact evaluation) runs inside a
/// StopAtOnce scope: a signal then ends the process within a second, from a watcher thread,
/// keeping what was written before (StopAtOnce::writing() guards the writes), removing the
/// temporary files of unfinished atomic writes, and saying what was kept.
#include <atomic>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace camplace::jobs {

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

/// While one lives (inside an InterruptSignals), a signal, or the deadline, ends the process
/// within a second: a watcher thread waits until no write is under way (writing()), removes
/// the files `<name>.camplace-tmp<pid>` that core::write_file_atomically leaves in `temp_dirs`,
/// prints "interrupted: <kept>" (exit status 128 + the signal) or, at the deadline (its own or
/// set_deadline's, whichever comes first), "error: <deadline_message>; <kept>" (exit status 1)
/// on stderr and calls _exit. At the deadline it first sends SIGTERM to the process signals are
/// forwarded to (InterruptSignals::forward_to, e.g. a study's run), which a signal reached
/// already. A signal that came before the scope began ends the process when it begins. Nest
/// none (active() tells whether one lives).
class StopAtOnce {
 public:
  struct Options {
    /// What the process has written so far, for the message ("nothing was written").
    std::string kept = "nothing was written";
    /// Folders whose temporary files an unfinished write may leave.
    std::vector<std::string> temp_dirs;
    /// Seconds from construction until the process ends with deadline_message; ≤ 0: none.
    double deadline_seconds = 0.0;
    std::string deadline_message;
    /// false: only the deadline ends the process; a signal is left to the command's own
    /// stop after the work under way (e.g. validate's, which then writes its report).
    bool end_on_signal = true;
  };
  explicit StopAtOnce(Options options);
  ~StopAtOnce();
  StopAtOnce(const StopAtOnce&) = delete;
  StopAtOnce& operator=(const StopAtOnce&) = delete;

  /// Updates what the message says was kept (e.g. after a checkpoint was written).
  static void set_kept(const std::string& kept);
  /// Hold this lock while writing files that must not be cut short: the watcher ends the
  /// process only between writes.
  static std::mutex& writing();
  /// True while a StopAtOnce lives (nest none: callers that may run inside one ask first).
  static bool active();

 private:
  struct State;
  State* state_;
};

/// The whole command's bound (`--max-seconds S`), from this call on: every StopAtOnce scope
/// also ends the process when it passes (with its deadline_message, else this `message`), and
/// long loops ask seconds_left() to end their work in time. S ≤ 0: none.
void set_deadline(double seconds, const std::string& message);
/// Seconds until the deadline of set_deadline (≤ 0 once it passed); infinity without one.
double seconds_left();
/// set_deadline's message ("" without a deadline).
const std::string& deadline_message();

/// What the command is doing, with the options that size the work ("evaluate --resolution
/// 100x100x100 (the scene's), 256 cameras, --refine 0"): main names it when memory runs out.
void set_work_description(const std::string& description);
const std::string& work_description();

}  // namespace camplace::jobs
