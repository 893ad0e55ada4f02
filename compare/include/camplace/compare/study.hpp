#pragma once
/// Studies of the paper's examinations (SPEC §8–9): groups of R optimiser runs on generated
/// scenes, one scene parameter varied per examination; resumable; a report with the paper's
/// plots.
#include <string>
#include <vector>

namespace camplace::compare {

struct StudyOptions {
  std::string study_file;  ///< the study JSON (see data/studies/paper.json)
  std::string out_dir;
  std::string camplace;  ///< path of the camplace executable that runs `optimize`
  std::string command;   ///< the command line, quoted in the report
  std::vector<std::string>
      algorithms;  ///< solver names `optimize` accepts (the study's is checked)
};

/// What a study run did.
struct StudyOutcome {
  int runs_total = 0;
  int runs_done_before = 0;  ///< found complete in out_dir and not repeated
  int runs_done_now = 0;
  bool interrupted = false;  ///< Ctrl-C: the report covers the runs finished so far
};

/// Runs every missing run of the study (each as `camplace optimize ... --runs 1`, so peak
/// memory is per run), then writes DIR/report.md, DIR/runs.csv, DIR/groups.csv and the plots.
/// A run counts as finished when DIR/runs/<group>/run-<seed>.json exists and was not
/// interrupted. Throws core::InputError for a bad study file.
StudyOutcome run_study(const StudyOptions& options);

}  // namespace camplace::compare
