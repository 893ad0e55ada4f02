// `camplace evaluate`: Err of one camera configuration, per state, in the voxel and/or the
// exact pipeline.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <thread>

#include "camplace/compare/evaluation_json.hpp"
#include "camplace/core/camera.hpp"
#include "camplace/core/err.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/threads.hpp"
#include "camplace/jobs/interrupt.hpp"
#include "camplace/jobs/progress.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "cli_checks.hpp"
#include "commands.hpp"
#include "memory_estimate.hpp"
#include "scene_input.hpp"

namespace camplace::app {

namespace {

struct EvaluateArgs {
  std::string scene, cameras, mode = "conservative", resolution, pipeline = "voxel", export_dir;
  std::string voxels_out;
  bool voxels_out_given = false, export_given = false;
  bool json = false, exact_fractions = false, progress = false;
  double max_seconds = 0.0;  // 0 = no limit
  int threads = 0;           // 0 = one per core (both pipelines)
  int refine = 0;            // voxel::VoxelOptions::refine
};

void print_table(const nlohmann::json& r) {
  std::printf("pipeline %s", r["pipeline"].get<std::string>().c_str());
  if (r.contains("mode")) {
    if (r.contains("fov")) std::printf(", fov %s", r["fov"].get<std::string>().c_str());
    std::printf(", mode %s, resolution %dx%dx%d", r["mode"].get<std::string>().c_str(),
                r["resolution"][0].get<int>(), r["resolution"][1].get<int>(),
                r["resolution"][2].get<int>());
    if (r.value("refine", 0) > 0) std::printf(", refine %d", r["refine"].get<int>());
  }
  std::printf("\n%4s %5s %7s %9s %9s %11s %6s %7s\n", "step", "event", "weight", "d_true[m]",
              "d_model[m]", "volume[m³]", "comps", "removed");
  for (const auto& s : r["states"]) {
    std::printf("%4d %5d %7.3f %9.4f %10.4f %11.4f %6d %7d\n", s["time_step"].get<int>(),
                s["event"].get<int>(), s["weight"].get<double>(), s["d_true"].get<double>(),
                s["d_model"].get<double>(), s["model_volume"].get<double>(),
                s["components"].get<int>(), s["components_removed"].get<int>());
  }
  // --exact-fractions: the exact values below the table (long; --json has them per state).
  for (const auto& s : r["states"]) {
    if (!s.contains("d_model_sq_exact")) continue;
    std::printf("step %d event %d: d_true² = %s m², d_model² = %s m², volume = %s m³\n",
                s["time_step"].get<int>(), s["event"].get<int>(),
                s["d_true_sq_exact"].get<std::string>().c_str(),
                s["d_model_sq_exact"].get<std::string>().c_str(),
                s["model_volume_exact"].get<std::string>().c_str());
  }
  if (r.contains("diagnostics")) {
    const auto& d = r["diagnostics"];
    for (const auto& s : d["states"]) {
      const auto& c = s["nearest_component"];
      if (c.is_null()) continue;
      std::printf(
          "step %d event %d: nearest component %d (%ld voxels) at %.4f m, observed by %d "
          "of %zu cameras\n",
          s["time_step"].get<int>(), s["event"].get<int>(), c["index"].get<int>(),
          c["voxels"].get<long>(), c["distance"].get<double>(), c["cameras_observing"].get<int>(),
          d["cameras"].size());
    }
    for (const auto& c : d["cameras"]) {
      std::printf("camera %d: %.1f%% of S in its FOV", c["index"].get<int>(),
                  100.0 * c["fov_fraction"].get<double>());
      if (!c["target_seen_fraction"].is_null())
        std::printf(", sees %.1f%% of the targets",
                    100.0 * c["target_seen_fraction"].get<double>());
      std::printf("\n");
    }
    for (const auto& w : d["warnings"]) std::printf("warning: %s\n", w.get<std::string>().c_str());
  }
  std::printf("Err = %.6f m²", r["err"].get<double>());
  if (r.contains("tolerance")) std::printf("   (tolerance %.4f m²)", r["tolerance"].get<double>());
  if (r.value("err_lower_bound", 0.0) > 0.0) {
    std::printf(
        "\nno configuration has Err below %.4f m² in this mode and resolution (the voxels an "
        "occupying object reaches into stay in every model: docs/design/lower-bound.md)",
        r["err_lower_bound"].get<double>());
  }
  const auto& t = r["timing_ms"];
  std::printf("\ntime: %.3f ms", t["total"].get<double>());
  if (t.contains("labelling")) {
    std::printf(" (labelling %.3f, clustering %.3f, distance %.3f)", t["labelling"].get<double>(),
                t["clustering"].get<double>(), t["distance"].get<double>());
  }
  std::printf("\n");
}

/// The last line of the table: the voxel Err against the tolerance and the conservative lower
/// bound (equal to it: no configuration does better at this mode and resolution), and with
/// `voxel` and `exact` both given the exact Err of the same configuration. `r` is the voxel
/// result, `exact` null when only one pipeline ran.
void print_summary(const nlohmann::json& r, const nlohmann::json& exact) {
  const double err = r["err"].get<double>();
  std::printf("summary: Err %.4f m² (%s pipeline", err, r["pipeline"].get<std::string>().c_str());
  if (r.contains("mode")) {
    std::printf(", %s, %dx%dx%d", r["mode"].get<std::string>().c_str(),
                r["resolution"][0].get<int>(), r["resolution"][1].get<int>(),
                r["resolution"][2].get<int>());
    if (r.contains("fov")) std::printf(", FOV %s", r["fov"].get<std::string>().c_str());
  }
  std::printf(")");
  const double bound = r.value("err_lower_bound", 0.0);
  if (bound > 0.0) {
    std::printf("; lower bound %.4f m²%s", bound,
                err <= core::lower_bound_threshold(bound)
                    ? ": provably optimal at this mode and resolution"
                    : "");
  }
  if (r.contains("tolerance")) {
    const double tolerance = r["tolerance"].get<double>();
    std::printf("; tolerance %.4f m² %s", tolerance, err <= tolerance ? "reached" : "not reached");
  }
  if (!exact.is_null()) {
    const double exact_err = exact["err"].get<double>();
    std::printf("; exact Err %.4f m²", exact_err);
    if (r.contains("tolerance")) {
      std::printf(" (tolerance %s)",
                  exact_err <= r["tolerance"].get<double>() ? "reached" : "not reached");
    }
  }
  std::printf("\n");
}

// The filtered voxel models as NAME.npy + NAME.json + NAME.vtk (docs/files.md).
void write_voxels(const compare::EvaluationJson& evaluation, const std::string& path) {
  try {
    compare::write_voxel_models(evaluation, path);
  } catch (const core::WriteError&) {
    throw;  // names the file and the system's reason: not a command-line problem
  } catch (const std::runtime_error& e) {
    throw core::InputError("command line", "--voxels-out", e.what());
  }
}

/// "evaluate --max-seconds 5 --resolution ..." as the messages name the work.
std::string max_seconds_text(double seconds) {
  char text[64];
  std::snprintf(text, sizeof text, "%g", seconds);
  return text;
}

void run_evaluate(const EvaluateArgs& args) {
  // The first SIGINT, SIGTERM or SIGHUP ends the evaluation at once (nothing to keep yet), also
  // while the scene loads and an evaluator is set up (interrupt.hpp, jobs::StopAtOnce below).
  const jobs::InterruptSignals signals;
  // --max-seconds bounds the whole command, from the scene's loading on.
  jobs::set_deadline(args.max_seconds, "evaluate stopped: --max-seconds " +
                                           max_seconds_text(args.max_seconds) + " exceeded");
  const core::Scene scene = load_scene_and_report(args.scene);
  const core::CameraConfig config = core::load_camera_config(args.cameras, scene);
  // Keep-out boxes bind the optimizer only (docs/scene-format.md): evaluate warns and goes on.
  for (std::size_t i = 0; i < config.size(); ++i) {
    for (const core::KeepOut& k : scene.cameras.keep_out) {
      if (!k.contains(config[i].position)) continue;
      std::fprintf(stderr,
                   "warning: %s: /cameras/%zu/position: camera %zu lies in keep-out box \"%s\" "
                   "(%s); the optimizer never places a camera there\n",
                   args.cameras.c_str(), i, i, k.name.c_str(), k.entry.c_str());
    }
  }
  compare::EvaluationOptions options;
  options.mode = parse_enum<core::LabelMode>(args.mode);
  if (!args.resolution.empty())
    options.resolution = core::parse_resolution(args.resolution, "--resolution");
  options.threads = args.threads;
  options.pipeline = parse_enum<core::Pipeline>(args.pipeline);
  const bool want_voxel = options.pipeline != core::Pipeline::exact;
  const bool want_exact = options.pipeline != core::Pipeline::voxel;
  options.refine = args.refine;
  if (!want_exact && (args.export_given || args.exact_fractions)) {
    throw core::InputError("command line",
                           args.export_given ? "--export-mesh" : "--exact-fractions",
                           "needs --pipeline exact or both");
  }
  if (args.voxels_out_given) {
    const std::string problem = !want_voxel ? "needs --pipeline voxel or both"
                                            : compare::voxel_models_path_problem(args.voxels_out);
    if (!problem.empty()) throw core::InputError("command line", "--voxels-out", problem);
    if (std::filesystem::is_directory(args.voxels_out)) {
      throw core::InputError("command line", "--voxels-out",
                             args.voxels_out + ": is a directory, not a file");
    }
    if (!args.voxels_out.empty()) {
      const std::filesystem::path parent = std::filesystem::path(args.voxels_out).parent_path();
      core::probe_output_directory(parent.empty() ? "." : parent.string(), "--voxels-out");
    }
  }
  if (args.export_given) core::create_output_directory(args.export_dir, "--export-mesh");
  options.export_dir = args.export_dir;
  options.exact_fractions = args.exact_fractions;
  options.cameras_file = args.cameras;
  options.voxel_models = !args.voxels_out.empty();
  const std::string resolution_option =
      args.resolution.empty() ? "the scene's voxels" : "--resolution";
  const VoxelWork work = voxel_work(
      scene, options.resolution, args.refine,
      args.threads > 0 ? args.threads
                       : static_cast<int>(std::max(std::thread::hardware_concurrency(), 1u)),
      true);
  jobs::set_work_description("evaluate " + resolution_option + " " + std::to_string(work.n[0]) +
                             "x" + std::to_string(work.n[1]) + "x" + std::to_string(work.n[2]) +
                             " with " + std::to_string(config.size()) + " cameras" +
                             (args.refine > 0 ? ", --refine " + std::to_string(args.refine) : "") +
                             ", --pipeline " + args.pipeline);
  if (want_voxel) check_memory(work, resolution_option);
  if (want_exact) check_exact_memory(exact_work(scene, args.threads));
  jobs::ProgressLine progress("evaluate", args.progress);
  if (progress.enabled()) {
    options.on_progress = [&progress](const std::string& stage, int done, int total) {
      if (total > 0) {
        progress.update(
            stage + (stage == "exact evaluation" ? ", (state, camera) steps" : ", states"), done,
            total);
      } else {
        progress.stage(stage);
      }
    };
  }
  compare::EvaluationJson evaluation;
  {
    // Nothing is written until the evaluation ends: a signal or --max-seconds ends the process
    // at once, removing the temporary files of --export-mesh's unfinished writes.
    jobs::StopAtOnce::Options stop;
    stop.kept = args.export_given ? "the mesh files in " + args.export_dir + " may be incomplete"
                                  : "nothing was written";
    if (args.export_given) stop.temp_dirs.push_back(args.export_dir);
    const jobs::StopAtOnce at_once(stop);
    evaluation = compare::evaluate_json(scene, config, options);
  }
  progress.finish();
  if (jobs::InterruptSignals::flag().load()) {
    throw jobs::Interrupted("evaluate stopped before printing its result; nothing was written");
  }
  const nlohmann::json& out = evaluation.result;
  if (options.voxel_models) write_voxels(evaluation, args.voxels_out);
  if (args.json) {
    std::cout << out.dump(2) << "\n";
    return;
  }
  if (want_voxel && want_exact) {
    const auto& models = scene.cameras.models;
    const auto cone = std::find_if(models.begin(), models.end(), [](const core::CameraModel& m) {
      return m.fov == core::FovShape::cone;
    });
    if (cone != models.end()) {
      std::printf(
          "note: the scene's FOV is a cone; both pipelines use its inscribed %d-sided pyramid "
          "here so that they compare like with like (--pipeline voxel uses the cone)\n\n",
          cone->sides);
    }
    print_table(out["voxel"]);
    std::printf("\n");
    print_table(out["exact"]);
    std::printf("\nErr voxel - exact = %.6f m²\n",
                out["differences"]["err_voxel_minus_exact"].get<double>());
    print_summary(out["voxel"], out["exact"]);
  } else {
    print_table(out);
    print_summary(out, nullptr);
  }
  if (jobs::InterruptSignals::flag().load()) {
    throw jobs::Interrupted(
        "evaluate: a signal came while the results were written; they are complete");
  }
}

}  // namespace

void register_evaluate_command(CLI::App& app) {
  auto args = std::make_shared<EvaluateArgs>();
  CLI::App* cmd = app.add_subcommand("evaluate", "Err of one camera configuration, state by state");
  cmd->footer(
      "Progress on stderr when it is a terminal (or with --progress). Ctrl-C, SIGTERM or SIGHUP\n"
      "end an evaluation within a second (exit status 128 + the signal); nothing is written\n"
      "until it ends. Work that would need more memory than available is refused first.");
  cmd->add_option("scene", args->scene, "scene JSON file")->required();
  cmd->add_option("--cameras", args->cameras, "camera configuration JSON file")->required();
  cmd->add_option("--mode", args->mode, "voxel labelling mode")->check(one_of<core::LabelMode>());
  cmd->add_option("--resolution", args->resolution,
                  "voxel resolution NXxNYxNZ (default: the scene's)");
  cmd->add_option("--refine", args->refine,
                  "conservative mode: refine the model's voxels L levels (cells of 1/2^L of the "
                  "voxel's edge; default 0 = none)")
      ->check(in_range(0, voxel::kMaxRefine));
  cmd->add_option("--pipeline", args->pipeline, "voxel, exact or both")
      ->check(one_of<core::Pipeline>());
  cmd->add_flag("--json", args->json, "print one JSON object on stdout");
  cmd->add_flag("--progress", args->progress,
                "progress on stderr also when it is not a terminal (on a terminal: always)");
  cmd->add_option("--max-seconds", args->max_seconds,
                  "stop with exit status 1 when the command (loading the scene, the "
                  "evaluation) takes longer than S seconds (default 0: no limit)")
      ->check(in_range(1e-3, 1e9, "must be a number of seconds in [0.001, 1e9]"));
  cmd->add_flag("--exact-fractions", args->exact_fractions,
                "exact pipeline: add squared distances as exact fractions \"p/q\"");
  cmd->add_option(
         "--threads", args->threads,
         "states evaluated in parallel, both pipelines; the exact pipeline gives threads left over "
         "(fewer states than threads) to one state's cameras (default: one thread per core)")
      ->check(in_range(1, core::kMaxThreads));
  CLI::Option* export_mesh = cmd->add_option(
      "--export-mesh", args->export_dir,
      "exact pipeline: write each state's model and each camera's pyramid (OFF) to DIR");
  CLI::Option* voxels_out = cmd->add_option(
      "--voxels-out", args->voxels_out,
      "voxel pipeline: each state's filtered model voxels as FILE.npy (+ .json, .vtk)");
  cmd->callback([args, export_mesh, voxels_out] {
    args->export_given = export_mesh->count() > 0;
    args->voxels_out_given = voxels_out->count() > 0;
    run_evaluate(*args);
  });
}

}  // namespace camplace::app
