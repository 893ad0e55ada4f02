// `camplace study`: the paper's examinations (SPEC §9), each run a `camplace optimize` process
// of its own (so the run file's peak memory is the run's), started without a shell
// (camplace::jobs); under mpirun the runs are spread over the ranks (jobs::mpi).
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "camplace/compare/study.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/jobs/interrupt.hpp"
#include "camplace/jobs/mpi_runs.hpp"
#include "camplace/jobs/mpi_work.hpp"
#include "camplace/jobs/process.hpp"
#include "camplace/optimize/report.hpp"
#include "cli_checks.hpp"
#include "commands.hpp"

namespace camplace::app {

namespace {

/// The study's launch of `camplace optimize ARGS` as a process of `program` (this binary).
jobs::ProcessLaunch optimize_process(const compare::OptimizeLaunch& launch) {
  jobs::ProcessLaunch process;
  process.args = {"optimize"};
  process.args.insert(process.args.end(), launch.args.begin(), launch.args.end());
  process.output_file = launch.output_file;
  return process;
}

compare::LaunchOutcome launch_outcome(const jobs::ProcessOutcome& ended) {
  return {ended.interrupted, ended.failure};
}

/// Runs `camplace optimize` for the launch and waits for it (the serial study's launcher).
compare::LaunchOutcome launch_optimize(const std::string& program,
                                       const compare::OptimizeLaunch& launch) {
  return launch_outcome(jobs::run_process(program, optimize_process(launch)));
}

/// The study's runs carried out on every rank of the session (rank 0 included): each run as
/// the serial study does it (the same arguments and files).
compare::RunDispatcher mpi_dispatcher(const jobs::mpi::Session& session,
                                      const std::string& program) {
  return [&session, program](const std::vector<compare::PendingRun>& runs) {
    std::vector<jobs::mpi::RankRun> rank_runs;
    for (const compare::PendingRun& run : runs) {
      rank_runs.push_back({optimize_process(run.launch), run.run_file, run.label});
    }
    std::vector<compare::LaunchOutcome> outcomes;
    for (const jobs::ProcessOutcome& ended :
         jobs::mpi::run_on_ranks(session, program, rank_runs, "study")) {
      outcomes.push_back(launch_outcome(ended));
    }
    return outcomes;
  };
}

}  // namespace

void register_study_command(CLI::App& app) {
  auto options = std::make_shared<compare::StudyOptions>();
  auto shard = std::make_shared<std::string>();
  auto max_seconds = std::make_shared<double>(0.0);
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
  cmd->add_option("--max-seconds", *max_seconds,
                  "stop with exit status 1 when the command takes longer than S seconds (the "
                  "run under way is stopped and repeated by a rerun; the finished runs and exact "
                  "checks are kept; default 0: no limit)")
      ->check(in_range(0.0, 1e9, "must be a number of seconds in [0, 1e9] (0 = no limit)"));
  cmd->callback([options, shard, max_seconds] {
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
    const jobs::InterruptSignals signals;
    jobs::set_deadline(*max_seconds, "study stopped: --max-seconds " +
                                         core::format_number(*max_seconds) + " exceeded");
    core::create_output_directory(options->out_dir, "--out");
    // The running binary, so a study's runs use the same camplace as the study.
    std::error_code ec;
    std::string program = std::filesystem::read_symlink("/proc/self/exe", ec).string();
    if (ec || program.empty()) program = "/proc/self/exe";
    options->launch = [program](const compare::OptimizeLaunch& launch) {
      return launch_optimize(program, launch);
    };
    // Under mpirun with more than one rank: rank 0 plans and hands out, the others run.
    std::unique_ptr<jobs::mpi::Session> session;
    if (jobs::mpi::launched_by_mpirun()) session = std::make_unique<jobs::mpi::Session>();
    if (session && session->rank() > 0) {
      jobs::mpi::serve_runs(*session, program);
      return;
    }
    if (session && session->size() > 1) options->dispatch = mpi_dispatcher(*session, program);
    options->command = "camplace study " + options->study_file + " --out " + options->out_dir +
                       (options->validate ? " --validate" : "") +
                       (shard->empty() ? "" : " --shard " + *shard) +
                       (options->report_only ? " --report-only" : "");
    options->interrupt = &jobs::InterruptSignals::flag();
    if (options->validate) {
      options->on_validate_progress = [](const compare::ValidationProgress& p) {
        std::fprintf(stderr, "validate: %d/%d runs, %.0f s\n", p.done, p.total, p.seconds);
      };
    }
    const jobs::StopAtOnce at_once(runs_folder_deadline(options->out_dir));
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
    if (outcome.interrupted || jobs::InterruptSignals::flag().load())
      throw jobs::Interrupted("study interrupted; rerun the same command to resume");
  });
}

}  // namespace camplace::app
