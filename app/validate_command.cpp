// `camplace validate DIR`: every run file of an optimize or study folder checked against the
// exact pipeline (SPEC §8); cached, parallel, resumable after Ctrl-C.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "camplace/compare/run_validation.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/threads.hpp"
#include "camplace/jobs/interrupt.hpp"
#include "camplace/jobs/mpi_work.hpp"
#include "camplace/jobs/progress.hpp"
#include "cli_checks.hpp"
#include "commands.hpp"
#include "memory_estimate.hpp"

namespace camplace::app {

namespace {

struct ValidateArgs {
  compare::ValidateOptions options;
  bool progress = false;
  double max_seconds = 0.0;  ///< the whole command's bound; 0 = none
};

/// One run's check under way on this rank, in a thread of its own (the rank keeps polling).
class CheckTask : public jobs::mpi::Task {
 public:
  CheckTask(compare::RunChecker& checker, std::string file)
      : thread_([this, &checker, file] {
          try {
            checker.check(file);  // its result goes into the folder's cache
          } catch (const std::exception&) {
            // rank 0's own pass over the folder reports what could not be checked
          }
          done_.store(true);
        }) {}
  ~CheckTask() override {
    if (thread_.joinable()) thread_.join();
  }
  std::optional<std::string> poll() override {
    if (!done_.load()) return std::nullopt;
    thread_.join();
    return std::string("checked");
  }

 private:
  std::atomic<bool> done_{false};
  std::thread thread_;
};

jobs::mpi::Handlers check_handlers(const std::shared_ptr<compare::RunChecker>& checker) {
  jobs::mpi::Handlers handlers;
  handlers.start = [checker](const std::string& file) {
    return std::make_unique<CheckTask>(*checker, file);
  };
  handlers.interrupt = &jobs::InterruptSignals::flag();
  return handlers;
}

/// Rank 0 of `mpirun camplace validate DIR`: every run file's check spread over the ranks
/// (itself included), each into the folder's cache, from which validate_runs then takes them.
/// Returns false when a signal stopped it.
bool check_on_ranks(const jobs::mpi::Session& session, const compare::ValidateOptions& options) {
  const std::vector<std::string> files = compare::find_validation_runs(options.dir);
  jobs::mpi::Handlers handlers = check_handlers(std::make_shared<compare::RunChecker>(options.dir));
  const auto start = std::chrono::steady_clock::now();
  int done = 0;
  handlers.judge = [&](std::size_t, int, const std::string&) {
    ++done;
    if (options.on_progress) {
      options.on_progress(
          {done, static_cast<int>(files.size()), 0,
           std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
    }
    return jobs::InterruptSignals::flag().load() ? jobs::mpi::Verdict::stop
                                                 : jobs::mpi::Verdict::done;
  };
  jobs::mpi::distribute(session, files, handlers);
  return !jobs::InterruptSignals::flag().load();
}

void run_validate(ValidateArgs& args) {
  // The first SIGINT, SIGTERM or SIGHUP finishes the runs under way and writes the files
  // (interrupt.hpp).
  const jobs::InterruptSignals signals;
  jobs::set_deadline(args.max_seconds, "validate stopped: --max-seconds " +
                                           core::format_number(args.max_seconds) + " exceeded");
  compare::ValidateOptions& options = args.options;
  options.interrupt = &jobs::InterruptSignals::flag();
  const bool tty = ::isatty(STDERR_FILENO) == 1;
  if (tty || args.progress) {
    // A line after each run; between runs, as the exact checks under way advance by (state,
    // camera) steps, at most every second on a terminal and every 30 seconds otherwise.
    auto last_line = std::make_shared<std::pair<int, double>>(-1, 0.0);
    options.on_progress = [tty, last_line](const compare::ValidationProgress& p) {
      const bool run_done = p.done != last_line->first;
      if (!run_done && p.seconds - last_line->second < (tty ? 1.0 : 30.0)) return;
      *last_line = {p.done, p.seconds};
      // Runs read from the cache cost nothing: the rate comes from the runs evaluated now.
      const int evaluated = p.done - p.from_cache;
      const double eta = evaluated > 0 ? p.seconds / evaluated * (p.total - p.done) : 0.0;
      std::string steps;
      if (p.exact_total > 0) {
        steps = ", exact (state, camera) steps of the checks under way " +
                std::to_string(p.exact_done) + "/" + std::to_string(p.exact_total);
      }
      std::fprintf(stderr, "%svalidate: %d/%d runs%s, %s elapsed, ETA %s%s", tty ? "\r\033[K" : "",
                   p.done, p.total, steps.c_str(), jobs::duration_text(p.seconds).c_str(),
                   evaluated > 0 ? jobs::duration_text(eta).c_str() : "unknown", tty ? "" : "\n");
      std::fflush(stderr);
    };
  }
  // Each exact check is refused before it starts when its memory estimate (with the threads it
  // gets) exceeds what is available: that run becomes a row with the reason.
  options.before_exact = [](const core::Scene& scene, int exact_threads) {
    check_exact_memory(exact_work(scene, exact_threads));
  };
  options.command = "camplace validate " + options.dir;
  // validation.csv, validation.md and the cache go into the folder: a read-only or full one is
  // found before the checks, not after them.
  if (std::filesystem::is_directory(options.dir)) core::probe_writable(options.dir, "DIR");
  // Under mpirun with more than one rank: the checks are spread over the ranks and land in the
  // cache; rank 0 then writes the files from it as a serial validate does.
  std::unique_ptr<jobs::mpi::Session> session;
  if (jobs::mpi::launched_by_mpirun()) session = std::make_unique<jobs::mpi::Session>();
  // --max-seconds ends the process at its deadline, within a second, even in the middle of a
  // check (one exact check of a large cell can take minutes); the checks finished by then are
  // in the cache, from which a rerun resumes. A signal still stops after the checks under way
  // and writes the files (options.interrupt).
  jobs::StopAtOnce::Options at_deadline;
  at_deadline.end_on_signal = false;
  const std::string cache = (std::filesystem::path(options.dir) / "validation-cache").string();
  at_deadline.temp_dirs = {options.dir, cache};
  at_deadline.kept =
      "the exact checks finished so far are in " + cache + "; rerun the same command to resume";
  const jobs::StopAtOnce at_once(at_deadline);
  if (session && session->rank() > 0) {
    jobs::mpi::serve(*session, check_handlers(std::make_shared<compare::RunChecker>(options.dir)));
    return;
  }
  if (session && session->size() > 1 && !check_on_ranks(*session, options)) {
    // Stopped by a signal: the checks finished so far, from the cache.
    options.interrupt = nullptr;
    options.cache_only = true;
  }
  compare::ValidationOutcome outcome = compare::validate_runs(options);
  if (options.cache_only) outcome.interrupted = true;
  if (tty) std::fprintf(stderr, "\n");
  int false_successes = 0, over = 0, checked = 0;
  for (const auto& r : outcome.rows) {
    if (!r.error.empty()) {
      std::cerr << "error: " << r.error << "\n";
      continue;
    }
    ++checked;
    false_successes += r.reached_voxel && !r.reached_exact;
    over += r.max_overestimate > 0.0;
  }
  std::cout << "checked " << checked << " runs (" << outcome.from_cache << " from the cache), "
            << outcome.failed << " could not be checked; false successes: " << false_successes
            << "; runs with max_overestimate > 0: " << over << "\n"
            << "results: " << options.dir << "/validation.csv, " << options.dir
            << "/validation.md\n";
  if (outcome.interrupted) {
    throw jobs::Interrupted("validate interrupted; rerun the same command to resume");
  }
  if (outcome.failed > 0) {
    throw std::runtime_error(std::to_string(outcome.failed) +
                             " run(s) could not be checked (see above)");
  }
}

}  // namespace

void register_validate_command(CLI::App& app) {
  auto args = std::make_shared<ValidateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "validate", "check every run of an optimize or study folder against the exact pipeline");
  cmd->footer(
      "Writes DIR/validation.csv and DIR/validation.md. Results are cached per run file in\n"
      "DIR/validation-cache, so a rerun is instant and an interrupted one (Ctrl-C) resumes.");
  cmd->add_option("dir", args->options.dir, "folder of camplace optimize or camplace study")
      ->required();
  cmd->add_option("--threads", args->options.threads, "runs checked in parallel, 0 = all cores")
      ->check(
          in_range(0, core::kMaxThreads,
                   "must lie in [0, " + std::to_string(core::kMaxThreads) + "] (0 = all cores)"));
  cmd->add_flag("--progress", args->progress, "progress lines on stderr also when not a terminal");
  cmd->add_option("--max-seconds", args->max_seconds,
                  "stop with exit status 1 when the command takes longer than S seconds (the "
                  "checks finished by then stay in the cache; default 0: no limit)")
      ->check(in_range(0.0, 1e9, "must be a number of seconds in [0, 1e9] (0 = no limit)"));
  cmd->callback([args] { run_validate(*args); });
}

}  // namespace camplace::app
