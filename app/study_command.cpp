// `camplace study`: the paper's examinations (SPEC §9), each run a `camplace optimize` process
// of its own (so the run file's peak memory is the run's), started without a shell.
#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "camplace/compare/study.hpp"
#include "camplace/core/files.hpp"
#include "camplace/optimize/report.hpp"
#include "commands.hpp"
#include "interrupt.hpp"

namespace camplace::app {

namespace {

// Set by SIGINT while a run goes: the run handles Ctrl-C itself (the terminal sends it to the
// whole process group); the study notes it and stops after the run.
std::atomic<bool> g_sigint_during_run{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the SIGINT flag must be lock-free");

extern "C" void note_sigint(int) { g_sigint_during_run.store(true); }

/// Sets SIGINT to note_sigint (no reset: a second Ctrl-C is the run's to handle) and SIGQUIT to
/// ignored for its lifetime, as std::system does while its command runs, and restores them
/// afterwards. SIGTERM and SIGHUP keep the study's InterruptSignals handler, which forwards them
/// to the run (InterruptSignals::forward_to).
class RunSignals {
 public:
  RunSignals() {
    g_sigint_during_run.store(false);
    struct sigaction note {};
    note.sa_handler = note_sigint;
    sigemptyset(&note.sa_mask);
    struct sigaction ignore {};
    ignore.sa_handler = SIG_IGN;
    sigemptyset(&ignore.sa_mask);
    sigaction(SIGINT, &note, &old_int_);
    sigaction(SIGQUIT, &ignore, &old_quit_);
  }
  ~RunSignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGQUIT, &old_quit_, nullptr);
  }
  RunSignals(const RunSignals&) = delete;
  RunSignals& operator=(const RunSignals&) = delete;

 private:
  struct sigaction old_int_ {};
  struct sigaction old_quit_ {};
};

std::string errno_text(int error) { return std::strerror(error); }

/// Runs `PROGRAM optimize ARGS` (PROGRAM: this camplace binary) as a child process with its
/// standard output in the launch's file, and waits for it. The child shares the study's process
/// group (Ctrl-C in the terminal reaches both) and is ended with SIGTERM if the study dies first.
compare::LaunchOutcome launch_optimize(const std::string& program,
                                       const compare::OptimizeLaunch& launch) {
  std::vector<std::string> words = {program, "optimize"};
  words.insert(words.end(), launch.args.begin(), launch.args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);

  const int out =
      ::open(launch.output_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (out < 0) {
    throw std::runtime_error("cannot write " + launch.output_file + ": " + errno_text(errno));
  }
  // The child reports a failed exec through this pipe; a successful exec closes it unwritten.
  int exec_error[2];
  if (::pipe2(exec_error, O_CLOEXEC) != 0) {
    const int error = errno;
    ::close(out);
    throw std::runtime_error("cannot start a run: pipe: " + errno_text(error));
  }

  const RunSignals signals;
  // SIGINT and SIGQUIT stay blocked across fork, so a Ctrl-C then reaches the child only once it
  // has its default handling back (and the study's note once the child exists).
  sigset_t blocked, old_mask;
  sigemptyset(&blocked);
  sigaddset(&blocked, SIGINT);
  sigaddset(&blocked, SIGQUIT);
  sigprocmask(SIG_BLOCK, &blocked, &old_mask);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    // The child: only async-signal-safe calls until exec.
    ::close(exec_error[0]);
    ::signal(SIGINT, SIG_DFL);
    ::signal(SIGQUIT, SIG_DFL);
    ::sigprocmask(SIG_SETMASK, &old_mask, nullptr);
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != parent) ::_exit(126);  // the study died before prctl
    if (::dup2(out, STDOUT_FILENO) >= 0) ::execv(program.c_str(), argv.data());
    const int error = errno;
    [[maybe_unused]] const ssize_t written = ::write(exec_error[1], &error, sizeof error);
    ::_exit(127);
  }
  const int fork_error = errno;
  sigprocmask(SIG_SETMASK, &old_mask, nullptr);
  ::close(out);
  ::close(exec_error[1]);
  if (pid < 0) {
    ::close(exec_error[0]);
    throw std::runtime_error("cannot start a run: fork: " + errno_text(fork_error));
  }
  int child_error = 0;
  ssize_t got = 0;
  do {
    got = ::read(exec_error[0], &child_error, sizeof child_error);
  } while (got < 0 && errno == EINTR);
  ::close(exec_error[0]);
  InterruptSignals::forward_to(pid);
  // A SIGTERM or SIGHUP that arrived before the child existed is passed on now.
  if (InterruptSignals::received() == SIGTERM || InterruptSignals::received() == SIGHUP)
    ::kill(pid, InterruptSignals::received());
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      InterruptSignals::forward_to(0);
      throw std::runtime_error("waiting for a run: " + errno_text(errno));
    }
  }
  InterruptSignals::forward_to(0);

  // A run stopped by a signal writes its best result and exits with 128 + the signal (or, on a
  // second Ctrl-C, dies of it).
  auto interrupt_signal = [](int sig) { return sig == SIGINT || sig == SIGTERM || sig == SIGHUP; };
  const bool exited_interrupted =
      WIFEXITED(status) && WEXITSTATUS(status) > 128 && interrupt_signal(WEXITSTATUS(status) - 128);
  compare::LaunchOutcome outcome;
  outcome.interrupted = g_sigint_during_run.load() || InterruptSignals::flag().load() ||
                        exited_interrupted ||
                        (WIFSIGNALED(status) && interrupt_signal(WTERMSIG(status)));
  if (got == static_cast<ssize_t>(sizeof child_error)) {
    outcome.failure = "could not be started: " + program + ": " + errno_text(child_error);
  } else if (exited_interrupted) {
    // interrupted, not failed: the run file holds its best result and is run again on resume
  } else if (WIFEXITED(status) && WEXITSTATUS(status) != 0) {
    outcome.failure = "exit status " + std::to_string(WEXITSTATUS(status));
  } else if (WIFSIGNALED(status)) {
    outcome.failure = "killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
                      ::strsignal(WTERMSIG(status)) + ")";
  }
  return outcome;
}

}  // namespace

void register_study_command(CLI::App& app) {
  auto options = std::make_shared<compare::StudyOptions>();
  CLI::App* cmd = app.add_subcommand(
      "study", "run a study of the paper's examinations (resumable), report in DIR");
  cmd->add_option("study", options->study_file, "study JSON file (e.g. data/studies/paper.json)")
      ->required();
  cmd->add_option("--out", options->out_dir, "output directory; rerun to resume")->required();
  cmd->add_flag("--validate", options->validate,
                "after the runs, check each against the exact pipeline (camplace validate) and "
                "add the check to the report");
  cmd->add_flag("--restart", options->restart,
                "discard the runs, report and exact checks already in --out and run the study "
                "afresh (without it, runs made with other settings are refused)");
  cmd->callback([options] {
    // SIGINT, SIGTERM and SIGHUP stop the study after the run under way (interrupt.hpp).
    const InterruptSignals signals;
    core::create_output_directory(options->out_dir, "--out");
    // The running binary, so a study's runs use the same camplace as the study.
    std::error_code ec;
    std::string program = std::filesystem::read_symlink("/proc/self/exe", ec).string();
    if (ec || program.empty()) program = "/proc/self/exe";
    options->launch = [program](const compare::OptimizeLaunch& launch) {
      return launch_optimize(program, launch);
    };
    options->command = "camplace study " + options->study_file + " --out " + options->out_dir +
                       (options->validate ? " --validate" : "");
    if (options->validate) {
      options->on_validate_progress = [](const compare::ValidationProgress& p) {
        std::fprintf(stderr, "validate: %d/%d runs, %.0f s\n", p.done, p.total, p.seconds);
      };
    }
    compare::StudyOutcome outcome;
    try {
      outcome = compare::run_study(*options);
    } catch (const optimize::SettingsChanged& e) {
      throw std::runtime_error(std::string(e.what()) + "\n" + restart_hint(options->out_dir));
    }
    if (options->restart) {
      std::cout << "restart: discarded " << outcome.runs_discarded << " run files\n";
    }
    std::cout << "runs: " << outcome.runs_total << " (" << outcome.runs_done_before << " found, "
              << outcome.runs_done_now << " run now)"
              << (outcome.interrupted ? ", interrupted" : "") << "\nreport: " << options->out_dir
              << "/report.md\n";
    if (outcome.interrupted || InterruptSignals::flag().load())
      throw Interrupted("study interrupted; rerun the same command to resume");
  });
}

}  // namespace camplace::app
