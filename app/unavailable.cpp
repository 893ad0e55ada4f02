// The commands of modules this build left out: each is registered as in a full build and fails
// with what to reconfigure, so every build knows every command (commands.hpp). The flags
// CAMPLACE_HAVE_* come from app/CMakeLists.txt; nothing here runs in a full build.
#include <stdexcept>
#include <string>

#include "commands.hpp"

namespace camplace::app {

namespace {

/// What the commands need: the part of camplace, its CMake option and what to install.
[[maybe_unused]] constexpr const char* kExact =
    "the exact pipeline (reconfigure with -DCAMPLACE_WITH_EXACT=ON; it needs CGAL with GMP and "
    "MPFR)";
[[maybe_unused]] constexpr const char* kOptimize =
    "the optimizer (reconfigure with -DCAMPLACE_WITH_OPTIMIZE=ON and install pagmo and TBB: "
    "libpagmo-dev, libtbb-dev)";
[[maybe_unused]] constexpr const char* kCompare =
    "camplace::compare (the compare/ folder; restore it and reconfigure)";

/// `name` as a command that takes any arguments and fails with "camplace was built without
/// <missing>".
[[maybe_unused]] void register_unavailable(CLI::App& app, const std::string& name,
                                           const std::string& description,
                                           const std::string& missing) {
  CLI::App* cmd = app.add_subcommand(name, description + " (not in this build)");
  cmd->allow_extras();
  cmd->prefix_command();
  cmd->callback([name, missing] {
    throw std::runtime_error("camplace " + name + ": camplace was built without " + missing);
  });
}

/// The parts of camplace::compare's validation (and, with `optimizer`, of its studies) this
/// build lacks, joined with " and ".
[[maybe_unused]] std::string missing_parts([[maybe_unused]] bool optimizer) {
  std::string missing;
#ifndef CAMPLACE_HAVE_COMPARE
  missing = kCompare;
#endif
#ifndef CAMPLACE_HAVE_EXACT
  missing += std::string(missing.empty() ? "" : " and ") + kExact;
#endif
#ifndef CAMPLACE_HAVE_OPTIMIZE
  if (optimizer) missing += std::string(missing.empty() ? "" : " and ") + kOptimize;
#endif
  return missing;
}

}  // namespace

#ifndef CAMPLACE_HAVE_OPTIMIZE
void register_optimize_command(CLI::App& app) {
  register_unavailable(app, "optimize",
                       "find camera settings that minimise the voxel Err (pagmo solvers)",
                       kOptimize);
}
#endif

#ifndef CAMPLACE_HAVE_COMPARE
void register_generate_command(CLI::App& app) {
  register_unavailable(app, "generate", "write a scene of the paper's examinations (SPEC §9)",
                       kCompare);
}
#endif

#ifndef CAMPLACE_HAVE_VALIDATION
void register_compare_command(CLI::App& app) {
  register_unavailable(app, "compare", "voxel pipeline against the exact pipeline, report in DIR",
                       missing_parts(false));
}
void register_compare_optimizer_command(CLI::App& app) {
  register_unavailable(app, "compare-optimizer",
                       "exact Err of optimizer results and voxel/exact rank agreement, report in "
                       "DIR",
                       missing_parts(false));
}
#endif

#ifndef CAMPLACE_HAVE_STUDY
void register_study_command(CLI::App& app) {
  register_unavailable(app, "study",
                       "run a study of the paper's examinations (resumable), report in DIR",
                       missing_parts(true));
}
void register_plan_command(CLI::App& app) {
  register_unavailable(app, "plan",
                       "how many cameras: optimise each count, exact-check, recommend, report in "
                       "DIR",
                       missing_parts(true));
}
void register_robustness_command(CLI::App& app) {
  register_unavailable(app, "robustness",
                       "Err of a camera configuration under mounting errors, report in DIR",
                       missing_parts(true));
}
void register_validate_command(CLI::App& app) {
  register_unavailable(app, "validate",
                       "check every run of an optimize or study folder against the exact pipeline",
                       missing_parts(true));
}
#endif

#ifndef CAMPLACE_HAVE_SERVE
void register_serve_command(CLI::App& app) {
  std::string missing;
#ifndef CAMPLACE_HAVE_COMPARE
  missing = kCompare;
#endif
#ifndef CAMPLACE_HAVE_OPTIMIZE
  missing += std::string(missing.empty() ? "" : " and ") + kOptimize;
#endif
  register_unavailable(app, "serve", "a local web planner: move cameras, see Err live",
                       missing.empty() ? "cpp-httplib (install libcpp-httplib-dev)" : missing);
}
#endif

}  // namespace camplace::app
