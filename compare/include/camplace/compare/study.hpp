#pragma once
/// Studies of the paper's examinations (SPEC §8–9): groups of R optimiser runs on generated
/// scenes, one scene parameter varied per examination; resumable; a report with the paper's
/// plots.
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "camplace/compare/run_validation.hpp"

namespace camplace::compare {

/// One run of a study, to be carried out as `camplace optimize ARGS` in a process of its own
/// (the run file records the process's peak memory, a figure of the report).
struct OptimizeLaunch {
  std::vector<std::string> args;  ///< the arguments after `camplace optimize`, one per entry
  std::string output_file;        ///< file that receives the run's standard output (replaced)
};

/// How a launched run ended.
struct LaunchOutcome {
  /// Ctrl-C (SIGINT) arrived while the run was going: the run then writes its best result as
  /// "interrupted", or died of the signal. The study stops after this run.
  bool interrupted = false;
  /// Empty when the run exited with status 0; else how it ended, for messages ("exit status 1",
  /// "killed by signal 9", "could not be started: ...").
  std::string failure;
};

/// Carries out one run and waits for it. A Ctrl-C while it runs must reach the run without
/// ending the caller (as std::system does); the launcher reports it in LaunchOutcome.
using RunLauncher = std::function<LaunchOutcome(const OptimizeLaunch& launch)>;

/// A run of the study still to do, as a RunDispatcher receives it.
struct PendingRun {
  OptimizeLaunch launch;  ///< exactly what the serial study hands its launcher
  std::string run_file;   ///< the run file it writes (DIR/runs/<group>/run-<seed>.json)
  std::string label;      ///< "<group> seed <seed>", for messages
  /// Expected cost, for handing out the longest runs first: voxels × cameras × max(1, events)
  /// of the group's scene (what one evaluation costs; every run has the same budget).
  double cost = 0.0;
};

/// Carries out the pending runs elsewhere (on MPI ranks: app/study_command.cpp,
/// jobs/src/mpi_runs.cpp) and returns how each ended, in the order given (a run never started,
/// after an interrupt or an error: interrupted, no failure). run_study gives them longest expected
/// first, with their folders made and no stale run file, and judges each by its run file as after
/// `launch`.
using RunDispatcher = std::function<std::vector<LaunchOutcome>(const std::vector<PendingRun>&)>;

struct StudyOptions {
  std::string study_file;  ///< the study JSON (see data/studies/paper.json)
  std::string out_dir;     ///< must exist
  std::string command;     ///< the command line, quoted in the report
  RunLauncher launch;      ///< runs `camplace optimize`
  /// After the runs, check each against the exact pipeline (validate_runs) and add the check to
  /// the report. Without it, the report still shows an earlier `camplace validate DIR`.
  bool validate = false;
  /// Discard what earlier invocations wrote into out_dir (run files, the groups' scenes, the
  /// report, runs.csv, the plots, the exact checks; nothing else) and run the study afresh,
  /// instead of refusing runs that are not of this study.
  bool restart = false;
  int validate_threads = 0;  ///< 0 = all cores
  /// Set (e.g. by Ctrl-C): the exact checks stop after those under way, as validate_runs does;
  /// the report covers the runs checked by then. (The runs themselves stop by their signal.)
  const std::atomic<bool>* interrupt = nullptr;
  std::function<void(const ValidationProgress&)> on_validate_progress;
  /// When set, carries out the missing runs instead of `launch` one after another (MPI).
  RunDispatcher dispatch;
  /// Shards (Slurm job arrays): with shard_count N > 0, only the runs whose index k in the
  /// canonical order (groups as in the study file, seeds ascending; k from 0) has
  /// k mod N == shard_index − 1 are run, and no report is written. Shards of one study may run
  /// at the same time into the same folder. 1 ≤ shard_index ≤ shard_count.
  int shard_index = 0, shard_count = 0;
  /// Run nothing: write the report from the run files there and list the missing runs.
  bool report_only = false;
};

/// What a study run did.
struct StudyOutcome {
  int runs_total = 0;
  int runs_done_before = 0;  ///< found complete in out_dir and not repeated
  int runs_done_now = 0;
  int runs_discarded = 0;    ///< run files removed by StudyOptions::restart
  bool interrupted = false;  ///< Ctrl-C: the report covers the runs finished so far
  int runs_in_shard = 0;     ///< the runs this invocation covers (the shard's, or all)
  /// With report_only: the runs without a finished run file ("<group> seed <seed>"), in the
  /// canonical order; the report lists them too.
  std::vector<std::string> missing;
};

/// Which shard (1..shard_count) runs the run of canonical index k (from 0).
inline int shard_of(int k, int shard_count) { return k % shard_count + 1; }

/// Runs every missing run of the study through options.launch (each as
/// `optimize SCENE ... --runs 1`, so peak memory is per run; its standard output in
/// DIR/runs/<group>/output-<seed>.txt), or all of them at once through options.dispatch, or only
/// a shard's (then no report), or none (report_only), then writes DIR/report.md,
/// DIR/runs.csv and the plots. A run counts as finished when
/// DIR/runs/<group>/run-<seed>.json exists and was not interrupted; an interrupted one is run
/// again. Before any run starts, every run file found must be one of this study:
/// made with its settings (optimize::settings_changes: scene content, mode, solver, budget,
/// threads, seed) and of one of its groups and seeds; a study that grows (more runs per group,
/// more groups) keeps its runs. Otherwise it throws optimize::SettingsChanged and leaves the
/// folder as it was, unless options.restart. Throws core::InputError for a bad study file and
/// for a run file that is damaged or of a format this version does not read
/// (optimize::read_run_file), std::runtime_error when a run fails.
StudyOutcome run_study(const StudyOptions& options);

}  // namespace camplace::compare
