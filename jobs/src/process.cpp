// Child processes started without a shell (fork + exec), as a study runs `camplace optimize`.
#include "camplace/jobs/process.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <stdexcept>

#include "camplace/jobs/interrupt.hpp"

namespace camplace::jobs {

namespace {

// Set by SIGINT while a child goes: the child handles Ctrl-C itself (the terminal sends it to
// the whole process group); the caller notes it and stops after the child.
std::atomic<bool> g_sigint_during_run{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the SIGINT flag must be lock-free");

extern "C" void note_sigint(int) { g_sigint_during_run.store(true); }

std::string errno_text(int error) { return std::strerror(error); }

}  // namespace

/// Sets SIGINT to note_sigint (no reset: a second Ctrl-C is the child's to handle) and SIGQUIT
/// to ignored for its lifetime, as std::system does while its command runs, and restores them
/// afterwards. SIGTERM and SIGHUP keep the caller's InterruptSignals handler, which forwards
/// them to the child (InterruptSignals::forward_to).
class ChildProcess::Signals {
 public:
  Signals() {
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
  ~Signals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGQUIT, &old_quit_, nullptr);
  }
  Signals(const Signals&) = delete;
  Signals& operator=(const Signals&) = delete;

 private:
  struct sigaction old_int_ {};
  struct sigaction old_quit_ {};
};

ChildProcess::ChildProcess(const std::string& program, const ProcessLaunch& launch)
    : program_(program) {
  std::vector<std::string> words = {program};
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

  signals_ = std::make_unique<Signals>();
  // SIGINT and SIGQUIT stay blocked across fork, so a Ctrl-C then reaches the child only once it
  // has its default handling back (and the caller's note once the child exists).
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
    if (::getppid() != parent) ::_exit(126);  // the caller died before prctl
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
    signals_.reset();
    throw std::runtime_error("cannot start a run: fork: " + errno_text(fork_error));
  }
  pid_ = pid;
  int child_error = 0;
  ssize_t got = 0;
  do {
    got = ::read(exec_error[0], &child_error, sizeof child_error);
  } while (got < 0 && errno == EINTR);
  ::close(exec_error[0]);
  if (got == static_cast<ssize_t>(sizeof child_error)) exec_error_ = child_error;
  InterruptSignals::forward_to(pid);
  // A SIGTERM or SIGHUP that arrived before the child existed is passed on now.
  if (InterruptSignals::received() == SIGTERM || InterruptSignals::received() == SIGHUP)
    ::kill(pid, InterruptSignals::received());
}

ChildProcess::~ChildProcess() {
  if (pid_ <= 0) return;
  ::kill(pid_, SIGTERM);
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  InterruptSignals::forward_to(0);
}

std::optional<ProcessOutcome> ChildProcess::poll() { return reap(WNOHANG); }

ProcessOutcome ChildProcess::wait() { return *reap(0); }

std::optional<ProcessOutcome> ChildProcess::reap(int options) {
  int status = 0;
  for (;;) {
    const pid_t got = ::waitpid(pid_, &status, options);
    if (got == 0) return std::nullopt;  // WNOHANG: still running
    if (got > 0) break;
    if (errno != EINTR) {
      const int error = errno;
      InterruptSignals::forward_to(0);
      pid_ = -1;
      throw std::runtime_error("waiting for a run: " + errno_text(error));
    }
  }
  pid_ = -1;
  InterruptSignals::forward_to(0);
  const ProcessOutcome ended = outcome(status);
  signals_.reset();
  return ended;
}

ProcessOutcome ChildProcess::outcome(int status) const {
  // A run stopped by a signal writes its best result and exits with 128 + the signal (or, on a
  // second Ctrl-C, dies of it).
  auto interrupt_signal = [](int sig) { return sig == SIGINT || sig == SIGTERM || sig == SIGHUP; };
  const bool exited_interrupted =
      WIFEXITED(status) && WEXITSTATUS(status) > 128 && interrupt_signal(WEXITSTATUS(status) - 128);
  ProcessOutcome outcome;
  outcome.interrupted = g_sigint_during_run.load() || InterruptSignals::flag().load() ||
                        exited_interrupted ||
                        (WIFSIGNALED(status) && interrupt_signal(WTERMSIG(status)));
  if (exec_error_ != 0) {
    outcome.failure = "could not be started: " + program_ + ": " + errno_text(exec_error_);
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

ProcessOutcome run_process(const std::string& program, const ProcessLaunch& launch) {
  return ChildProcess(program, launch).wait();
}

}  // namespace camplace::jobs
