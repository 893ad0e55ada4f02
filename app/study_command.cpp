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
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "camplace/compare/study.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/optimize/report.hpp"
#include "commands.hpp"
#include "interrupt.hpp"
#ifdef CAMPLACE_HAVE_MPI
#include "mpi_work.hpp"
#endif

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

/// A run started as `PROGRAM optimize ARGS` (PROGRAM: this camplace binary), a child process
/// with its standard output in the launch's file. The child shares the study's process group
/// (Ctrl-C in the terminal reaches both) and is ended with SIGTERM if the study dies first.
/// SIGTERM and SIGHUP to the study are passed on to it while it runs.
class RunProcess {
 public:
  RunProcess(const std::string& program, const compare::OptimizeLaunch& launch);
  /// A run still going (the study failed meanwhile) is ended with SIGTERM and waited for.
  ~RunProcess();
  RunProcess(const RunProcess&) = delete;
  RunProcess& operator=(const RunProcess&) = delete;

  /// How the run ended, or nothing while it goes on (does not wait).
  std::optional<compare::LaunchOutcome> poll() { return reap(WNOHANG); }
  /// How the run ended, once it has.
  compare::LaunchOutcome wait() { return *reap(0); }

 private:
  std::optional<compare::LaunchOutcome> reap(int options);
  compare::LaunchOutcome outcome(int status) const;

  std::string program_;
  std::unique_ptr<RunSignals> signals_;
  pid_t pid_ = -1;
  int exec_error_ = 0;  ///< errno of a failed exec, 0 if it succeeded
};

RunProcess::RunProcess(const std::string& program, const compare::OptimizeLaunch& launch)
    : program_(program) {
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

  signals_ = std::make_unique<RunSignals>();
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

RunProcess::~RunProcess() {
  if (pid_ <= 0) return;
  ::kill(pid_, SIGTERM);
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  InterruptSignals::forward_to(0);
}

std::optional<compare::LaunchOutcome> RunProcess::reap(int options) {
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
  const compare::LaunchOutcome ended = outcome(status);
  signals_.reset();
  return ended;
}

compare::LaunchOutcome RunProcess::outcome(int status) const {
  // A run stopped by a signal writes its best result and exits with 128 + the signal (or, on a
  // second Ctrl-C, dies of it).
  auto interrupt_signal = [](int sig) { return sig == SIGINT || sig == SIGTERM || sig == SIGHUP; };
  const bool exited_interrupted =
      WIFEXITED(status) && WEXITSTATUS(status) > 128 && interrupt_signal(WEXITSTATUS(status) - 128);
  compare::LaunchOutcome outcome;
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

/// Runs `camplace optimize` for the launch and waits for it (the serial study's launcher).
compare::LaunchOutcome launch_optimize(const std::string& program,
                                       const compare::OptimizeLaunch& launch) {
  return RunProcess(program, launch).wait();
}

/// "I/N" of --shard: 1 ≤ I ≤ N. Throws core::OptionError naming --shard.
std::pair<int, int> parse_shard(const std::string& text) {
  const std::string reason =
      "must be I/N with whole numbers 1 ≤ I ≤ N (e.g. 2/8), not \"" + text + "\"";
  const std::size_t slash = text.find('/');
  auto number = [&](const std::string& digits) {
    if (digits.empty() || digits.size() > 6 ||
        digits.find_first_not_of("0123456789") != std::string::npos) {
      throw core::OptionError("shard", reason);
    }
    return std::stoi(digits);
  };
  if (slash == std::string::npos) throw core::OptionError("shard", reason);
  const int index = number(text.substr(0, slash)), count = number(text.substr(slash + 1));
  if (index < 1 || index > count) throw core::OptionError("shard", reason);
  return {index, count};
}

#ifdef CAMPLACE_HAVE_MPI
// A run's launch as an MPI payload: the output file, then the arguments, '\0' between them.
std::string encode_launch(const compare::OptimizeLaunch& launch) {
  std::string text = launch.output_file;
  for (const std::string& arg : launch.args) text += '\0' + arg;
  return text;
}

compare::OptimizeLaunch decode_launch(const std::string& text) {
  compare::OptimizeLaunch launch;
  std::size_t start = 0;
  for (bool first = true;; first = false) {
    const std::size_t end = text.find('\0', start);
    std::string word = text.substr(start, end == std::string::npos ? end : end - start);
    if (first) {
      launch.output_file = std::move(word);
    } else {
      launch.args.push_back(std::move(word));
    }
    if (end == std::string::npos) return launch;
    start = end + 1;
  }
}

// A run's result as an MPI message: whether the rank had a signal, whether the run was
// interrupted ('1'/'0' each), then LaunchOutcome::failure.
std::string encode_outcome(const compare::LaunchOutcome& outcome, bool rank_signalled) {
  return std::string(rank_signalled ? "1" : "0") + (outcome.interrupted ? "1" : "0") +
         outcome.failure;
}

/// A run of the study under way on this rank.
class RunTask : public mpi::Task {
 public:
  RunTask(const std::string& program, const std::string& payload) {
    try {
      process_ = std::make_unique<RunProcess>(program, decode_launch(payload));
    } catch (const std::exception& e) {
      compare::LaunchOutcome failed;
      failed.failure = std::string("could not be started: ") + e.what();
      result_ = encode_outcome(failed, InterruptSignals::flag().load());
    }
  }
  std::optional<std::string> poll() override {
    if (result_) return result_;
    const std::optional<compare::LaunchOutcome> ended = process_->poll();
    if (!ended) return std::nullopt;
    return encode_outcome(*ended, InterruptSignals::flag().load());
  }

 private:
  std::unique_ptr<RunProcess> process_;
  std::optional<std::string> result_;
};

/// A run whose process died of a signal its rank did not get (killed) is given to another rank
/// this often before it counts as failed.
constexpr int kAttempts = 3;

/// The study's runs carried out on every rank of the session (rank 0 included): each run as
/// the serial study does it (RunProcess, the same arguments and files).
compare::RunDispatcher mpi_dispatcher(const mpi::Session& session, const std::string& program) {
  return [&session, program](const std::vector<compare::PendingRun>& runs) {
    std::vector<std::string> payloads;
    for (const compare::PendingRun& run : runs) payloads.push_back(encode_launch(run.launch));
    std::vector<compare::LaunchOutcome> outcomes(runs.size());
    std::vector<int> attempts(runs.size(), 0);
    int handed_out = 0;
    mpi::Handlers handlers;
    handlers.start = [program](const std::string& payload) {
      return std::make_unique<RunTask>(program, payload);
    };
    handlers.on_assign = [&](std::size_t item, int rank) {
      if (attempts[item] > 0) {
        std::fprintf(stderr, "study: %s on rank %d (again)\n", runs[item].label.c_str(), rank);
        return;
      }
      std::fprintf(stderr, "study: %s on rank %d (%d of %zu to run)\n", runs[item].label.c_str(),
                   rank, ++handed_out, runs.size());
    };
    handlers.judge = [&](std::size_t item, int rank, const std::string& result) {
      compare::LaunchOutcome& outcome = outcomes[item];
      const bool rank_signalled = result.size() >= 2 && result[0] == '1';
      outcome.interrupted = result.size() >= 2 && result[1] == '1';
      outcome.failure = result.size() >= 2 ? result.substr(2) : "a malformed MPI result";
      if (rank_signalled || InterruptSignals::flag().load()) {
        // The job is being stopped (mpirun signals its ranks one after another): rank 0 stops
        // its own run now too, as if the signal had reached it, and reports what is finished.
        if (!InterruptSignals::flag().load()) std::raise(SIGTERM);
        outcome.interrupted = true;
        return mpi::Verdict::stop;
      }
      const bool killed = outcome.interrupted || outcome.failure.rfind("killed by signal", 0) == 0;
      if (killed) {
        // The run's process died of a signal its rank did not get: redo it elsewhere, without
        // the interrupted result it may have written.
        std::error_code ec;
        std::filesystem::remove(runs[item].run_file, ec);
        const std::string how =
            outcome.failure.empty() ? "was stopped by a signal" : outcome.failure;
        if (++attempts[item] < kAttempts) {
          std::fprintf(stderr, "study: %s on rank %d %s; handing it out again\n",
                       runs[item].label.c_str(), rank, how.c_str());
          return mpi::Verdict::retry;
        }
        outcome.interrupted = false;
        outcome.failure = how + ", " + std::to_string(kAttempts) + " times";
        return mpi::Verdict::stop;
      }
      return outcome.failure.empty() ? mpi::Verdict::done : mpi::Verdict::stop;
    };
    handlers.interrupt = &InterruptSignals::flag();
    const std::vector<std::optional<std::string>> results =
        mpi::distribute(session, payloads, handlers);
    for (std::size_t i = 0; i < runs.size(); ++i) {
      // Not started (an interrupt, or an error elsewhere): as after Ctrl-C, run on resume.
      if (!results[i]) outcomes[i] = {true, ""};
    }
    return outcomes;
  };
}

/// A rank > 0 of `mpirun camplace study`: carries out the runs rank 0 hands it.
void serve_runs(const mpi::Session& session, const std::string& program) {
  mpi::Handlers handlers;
  handlers.start = [program](const std::string& payload) {
    return std::make_unique<RunTask>(program, payload);
  };
  mpi::serve(session, handlers);
}
#endif

}  // namespace

void register_study_command(CLI::App& app) {
  auto options = std::make_shared<compare::StudyOptions>();
  auto shard = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand(
      "study", "run a study of the paper's examinations (resumable), report in DIR");
  cmd->footer(
      "Under `mpirun -n N camplace study ...` the runs are spread over the N ranks (rank 0 "
      "plans,\nhands out the runs and writes the report). See docs/cluster.md.");
  cmd->add_option("study", options->study_file, "study JSON file (e.g. data/studies/paper.json)")
      ->required();
  cmd->add_option("--out", options->out_dir, "output directory; rerun to resume")->required();
  cmd->add_flag("--validate", options->validate,
                "after the runs, check each against the exact pipeline (camplace validate) and "
                "add the check to the report");
  cmd->add_flag("--restart", options->restart,
                "discard the runs, report and exact checks already in --out and run the study "
                "afresh (without it, runs made with other settings are refused)");
  cmd->add_option("--shard", *shard,
                  "I/N: run only the I-th of N fixed parts of the study's runs (the k-th run "
                  "goes to part k mod N + 1; e.g. a Slurm array task), no report; shards may run "
                  "at the same time into one --out");
  cmd->add_flag("--report-only", options->report_only,
                "run nothing: write the report from the runs in --out and list the missing ones");
  cmd->callback([options, shard] {
    if (!shard->empty()) {
      std::tie(options->shard_index, options->shard_count) = parse_shard(*shard);
      for (const auto& [set, name] : {std::pair{options->restart, "--restart"},
                                      {options->report_only, "--report-only"},
                                      {options->validate, "--validate"}}) {
        if (set) throw core::OptionError("shard", std::string("cannot go with ") + name);
      }
    }
    if (options->report_only && options->restart) {
      throw core::OptionError("report-only", "cannot go with --restart");
    }
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
#ifdef CAMPLACE_HAVE_MPI
    // Under mpirun with more than one rank: rank 0 plans and hands out, the others run.
    std::unique_ptr<mpi::Session> session;
    if (mpi::launched_by_mpirun()) session = std::make_unique<mpi::Session>();
    if (session && session->rank() > 0) {
      serve_runs(*session, program);
      return;
    }
    if (session && session->size() > 1) options->dispatch = mpi_dispatcher(*session, program);
#endif
    options->command = "camplace study " + options->study_file + " --out " + options->out_dir +
                       (options->validate ? " --validate" : "") +
                       (shard->empty() ? "" : " --shard " + *shard) +
                       (options->report_only ? " --report-only" : "");
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
    if (options->shard_count > 0) {
      std::cout << "shard " << *shard << ": runs: " << outcome.runs_in_shard << " of the study's "
                << outcome.runs_total << " (" << outcome.runs_done_before << " found, "
                << outcome.runs_done_now << " run now)"
                << (outcome.interrupted ? ", interrupted" : "")
                << "\nno report: a shard writes none; when every shard is done, run\n  camplace "
                   "study "
                << options->study_file << " --out " << options->out_dir << " --report-only\n";
    } else {
      std::cout << "runs: " << outcome.runs_total << " (" << outcome.runs_done_before << " found, ";
      if (options->report_only) {
        std::cout << outcome.missing.size() << " missing)\n";
        for (const std::string& run : outcome.missing) std::cout << "missing: " << run << "\n";
      } else {
        std::cout << outcome.runs_done_now << " run now)"
                  << (outcome.interrupted ? ", interrupted" : "") << "\n";
      }
      std::cout << "report: " << options->out_dir << "/report.md\n";
    }
    if (outcome.interrupted || InterruptSignals::flag().load())
      throw Interrupted("study interrupted; rerun the same command to resume");
  });
}

}  // namespace camplace::app
