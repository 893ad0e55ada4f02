#pragma once
/// Sub-commands of the `camplace` tool. Each registers its options and callback on the CLI11
/// app; the callback throws core::InputError (or std::exception) on failure, which main prints.
/// Every build declares and registers every command: a command whose module was not built
/// (optimize, compare, study, ...) fails with "camplace was built without ..." (unavailable.cpp).
#include <CLI/CLI.hpp>
#include <string>

namespace camplace::app {

/// The advice after a refused resume of the output folder `dir` (optimize, study).
inline std::string restart_hint(const std::string& dir) {
  return "rerun with --restart to discard the runs in " + dir +
         " (and what was made of them) and start afresh, or choose another --out folder";
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
