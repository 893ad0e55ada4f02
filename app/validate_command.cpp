// `camplace validate DIR`: every run file of an optimize or study folder checked against the
// exact pipeline (SPEC §8); cached, parallel, resumable after Ctrl-C.
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "camplace/compare/run_validation.hpp"
#include "cli_checks.hpp"
#include "commands.hpp"
#include "interrupt.hpp"

namespace camplace::app {

namespace {

struct ValidateArgs {
  compare::ValidateOptions options;
  bool progress = false;
};

std::string duration_text(double seconds) {
  char text[32];
  if (seconds < 60) {
    std::snprintf(text, sizeof text, "%.0fs", seconds);
  } else if (seconds < 3600) {
    std::snprintf(text, sizeof text, "%dm%02ds", int(seconds) / 60, int(seconds) % 60);
  } else {
    std::snprintf(text, sizeof text, "%dh%02dm", int(seconds) / 3600, int(seconds) / 60 % 60);
  }
  return text;
}

void run_validate(ValidateArgs& args) {
  // The first SIGINT, SIGTERM or SIGHUP finishes the runs under way and writes the files
  // (interrupt.hpp).
  const InterruptSignals signals;
  compare::ValidateOptions& options = args.options;
  options.interrupt = &InterruptSignals::flag();
  const bool tty = ::isatty(STDERR_FILENO) == 1;
  if (tty || args.progress) {
    options.on_progress = [tty](const compare::ValidationProgress& p) {
      // Runs read from the cache cost nothing: the rate comes from the runs evaluated now.
      const int evaluated = p.done - p.from_cache;
      const double eta = evaluated > 0 ? p.seconds / evaluated * (p.total - p.done) : 0.0;
      std::fprintf(stderr, "%svalidate: %d/%d runs, %s elapsed, ETA %s%s", tty ? "\r\033[K" : "",
                   p.done, p.total, duration_text(p.seconds).c_str(), duration_text(eta).c_str(),
                   tty ? "" : "\n");
      std::fflush(stderr);
    };
  }
  options.command = "camplace validate " + options.dir;
  const compare::ValidationOutcome outcome = compare::validate_runs(options);
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
    throw Interrupted("validate interrupted; rerun the same command to resume");
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
      ->check(in_range(0, 256, "must lie in [0, 256] (0 = all cores)"));
  cmd->add_flag("--progress", args->progress, "progress lines on stderr also when not a terminal");
  cmd->callback([args] { run_validate(*args); });
}

}  // namespace camplace::app
