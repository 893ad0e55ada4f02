#pragma once
/// Sub-commands of the `camplace` tool. Each registers its options and callback on the CLI11
/// app; the callback throws core::InputError (or std::exception) on failure, which main prints.
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
#ifdef CAMPLACE_HAVE_OPTIMIZE
void register_optimize_command(CLI::App& app);
#endif
#ifdef CAMPLACE_HAVE_COMPARE
void register_generate_command(CLI::App& app);
#endif
#ifdef CAMPLACE_HAVE_VALIDATION
void register_compare_command(CLI::App& app);
void register_compare_optimizer_command(CLI::App& app);
#endif
#ifdef CAMPLACE_HAVE_STUDY
void register_validate_command(CLI::App& app);
void register_study_command(CLI::App& app);
#endif

}  // namespace camplace::app
