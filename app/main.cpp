// The camplace command-line tool: parse, call the modules, print. Errors → message, exit 1.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <new>
#include <string>

#include "camplace/core/error.hpp"
#include "camplace/core/provenance.hpp"
#include "camplace/jobs/interrupt.hpp"
#include "commands.hpp"

namespace {

/// "error: out of memory: <the work> asked for more memory than the machine could give; ..."
void print_out_of_memory(const std::string& command) {
  const std::string& work = camplace::jobs::work_description();
  std::cerr << "error: out of memory: " << (work.empty() ? "camplace " + command : work)
            << " asked for more memory than the machine could give; use a coarser "
               "--resolution, fewer cameras or fewer --refine levels\n";
}

/// `camplace` alone: every command with its one-line description, the bundled example and
/// where to read on.
void print_overview(const CLI::App& app) {
  const camplace::core::BuildInfo build = camplace::core::build_info();
  std::printf(
      "camplace %s: where to mount the cameras of a human-robot work cell so that the\n"
      "person-robot distance measured on their visual hull is as close to the true one as\n"
      "possible, never larger.\n\nUsage: camplace COMMAND [OPTIONS]  (camplace COMMAND "
      "--help for its options)\n\nCommands:\n",
      build.version.c_str());
  for (const CLI::App* command : app.get_subcommands({})) {
    std::printf("  %-18s %s\n", command->get_name().c_str(), command->get_description().c_str());
  }
  const std::string example = std::string(CAMPLACE_DATA_DIR) + "/paper_basic.json";
  std::printf("\nBundled example (the paper's basic scene): %s\n", example.c_str());
  std::printf("  camplace optimize %s --out out/paper_basic\n", example.c_str());
  std::printf("  camplace export %s --cameras out/paper_basic/run-1.json --out out/view\n",
              example.c_str());
}

std::string g_command;                                 // argv[1], for the terminate handler
std::terminate_handler g_default_terminate = nullptr;  // the runtime's (prints the exception)

}  // namespace

int main(int argc, char** argv) {
  g_command = argc > 1 ? argv[1] : "";
  // std::bad_alloc in a worker thread (the pipelines evaluate states in parallel) ends in
  // std::terminate, not in the catch below: say the same there.
  g_default_terminate = std::set_terminate([] {
    if (const std::exception_ptr e = std::current_exception()) {
      try {
        std::rethrow_exception(e);
      } catch (const std::bad_alloc&) {
        print_out_of_memory(g_command);
        std::_Exit(1);
      } catch (...) {
      }
    }
    if (g_default_terminate != nullptr) g_default_terminate();
    std::abort();
  });
  CLI::App app{"camplace: camera placement for human-robot work cells (visual hull distance)"};
  app.require_subcommand(1);
  // Every option's help shows its default (inherited by the subcommands registered below).
  app.option_defaults()->always_capture_default();
  const camplace::core::BuildInfo build = camplace::core::build_info();
  app.set_version_flag("--version", "camplace " + build.version + " (commit " + build.commit +
                                        ", " + build.build_type + " build)");
  camplace::app::register_evaluate_command(app);
  camplace::app::register_export_command(app);
  camplace::app::register_expand_command(app);
  camplace::app::register_optimize_command(app);
  camplace::app::register_compare_command(app);
  camplace::app::register_compare_optimizer_command(app);
  camplace::app::register_study_command(app);
  camplace::app::register_validate_command(app);
  camplace::app::register_plan_command(app);
  camplace::app::register_robustness_command(app);
  camplace::app::register_generate_command(app);
  camplace::app::register_serve_command(app);
  if (argc == 1) {
    print_overview(app);
    return 0;
  }
  if (argc > 1 && argv[1][0] != '-') {
    std::string names;
    bool known = false;
    for (const CLI::App* command : app.get_subcommands({})) {
      known = known || command->get_name() == argv[1];
      names += (names.empty() ? "" : ", ") + command->get_name();
    }
    if (!known) {
      std::cerr << "error: command line: unknown command \"" << argv[1]
                << "\" (expected one of: " << names << ")\n";
      return 1;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::cerr << "error: command line: " << e.what() << "\n";
    return 1;
  } catch (const camplace::core::OptionError& e) {
    // Libraries name options as their structs do; on the command line each is its flag.
    // Positional arguments keep their upper-case name (FAMILY); options are --name.
    const std::string flag = e.option() == "family" ? "FAMILY" : "--" + e.option();
    std::cerr << "error: command line: " << flag << ": " << e.reason() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    // Commands name the work and the options that sized it (jobs::set_work_description).
    print_out_of_memory(g_command);
    return 1;
  } catch (const camplace::jobs::Interrupted& e) {
    std::cerr << "interrupted: " << e.what() << "\n";
    return camplace::jobs::interrupted_exit_status();
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
