#pragma once
/// Sub-commands of the `camplace` tool. Each registers its options and callback on the CLI11
/// app; the callback throws core::InputError (or std::exception) on failure, which main prints.
/// Every build declares and registers every command: a command whose module was not built
/// (optimize, compare, study, ...) fails with "camplace was built without ..." (unavailable.cpp).
#include <CLI/CLI.hpp>
#include <filesystem>
#include <string>

#include "camplace/jobs/interrupt.hpp"

namespace camplace::app {

/// The advice after a refused resume of the output folder `dir` (optimize, study).
inline std::string restart_hint(const std::string& dir) {
  return "rerun with --restart to discard the runs in " + dir +
         " (and what was made of them) and start afresh, or choose another --out folder";
}

/// The --max-seconds stop of a command that fills the folder `dir` with runs and exact checks
/// (study, plan): the deadline ends the process within a second (the run under way gets
/// SIGTERM, so its file says "interrupted" and a rerun repeats it; an exact check under way is
/// cut, the finished ones are in the cache), while a signal keeps the command's own stop after
/// the run under way.
inline jobs::StopAtOnce::Options runs_folder_deadline(const std::string& dir) {
  const std::filesystem::path out(dir);
  jobs::StopAtOnce::Options options;
  options.end_on_signal = false;
  options.temp_dirs = {out.string(), (out / "validation-cache").string(),
                       (out / "scenes").string()};
  options.kept = "the finished runs are in " + (out / "runs").string() +
                 " and the finished exact checks in " + (out / "validation-cache").string() +
                 "; rerun the same command to resume and write the report";
  return options;
}

void register_evaluate_command(CLI::App& app);
void register_expand_command(CLI::App& app);
void register_export_command(CLI::App& app);
void register_optimize_command(CLI::App& app);
void register_generate_command(CLI::App& app);
void register_compare_command(CLI::App& app);
void register_compare_optimizer_command(CLI::App& app);
void register_validate_command(CLI::App& app);
void register_study_command(CLI::App& app);
void register_plan_command(CLI::App& app);
void register_robustness_command(CLI::App& app);
void register_serve_command(CLI::App& app);

}  // namespace camplace::app
