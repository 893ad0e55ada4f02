// `camplace evaluate`: Err of one camera configuration, per state, in the voxel and/or the
// exact pipeline.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <thread>

#include "camplace/core/camera.hpp"
#include "camplace/core/err.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "cli_checks.hpp"
#include "commands.hpp"
#ifdef CAMPLACE_HAVE_EXACT
#include "camplace/exact/evaluator.hpp"
#endif

namespace camplace::app {

namespace {

struct EvaluateArgs {
  std::string scene, cameras, mode = "conservative", resolution, pipeline = "voxel", export_dir;
  std::string voxels_out;
  bool voxels_out_given = false, export_given = false;
  bool json = false, exact_fractions = false;
  int threads = 0;  // 0 = one per core (both pipelines)
  int refine = 0;   // voxel::VoxelOptions::refine
};

/// The per-state fields both pipelines report (voxel::StateResult, core::StateResult).
template <class StateResult>
nlohmann::json state_json(const StateResult& s) {
  return {{"time_step", s.time_step},   {"event", s.event},
          {"weight", s.weight},         {"d_true", s.d_true},
          {"d_model", s.d_model},       {"model_volume", s.model_volume},
          {"components", s.components}, {"components_removed", s.components_removed}};
}

nlohmann::json voxel_json(const voxel::VoxelEvaluator& evaluator, const voxel::Evaluation& e) {
  const auto& n = evaluator.grid().n;
  nlohmann::json states = nlohmann::json::array();
  for (const auto& s : e.states) states.push_back(state_json(s));
  return {{"pipeline", core::name_of(core::Pipeline::voxel)},
          {"mode", core::name_of(evaluator.options().mode)},
          {"resolution", {n[0], n[1], n[2]}},
          {"refine", evaluator.options().refine},
          {"voxel_diagonal", evaluator.grid().step.norm()},
          {"tolerance", core::default_tolerance(evaluator.scene().area, n)},
          {"err_lower_bound", evaluator.err_lower_bound()},
          {"err", e.err},
          {"states", states},
          {"timing_ms",
           {{"labelling", e.timing.labelling_ms},
            {"clustering", e.timing.clustering_ms},
            {"distance", e.timing.distance_ms},
            {"total", e.timing.total_ms}}}};
}

/// Every number in `j` is finite. nlohmann::json prints NaN and ±inf as null; the scene loader
/// bounds the weights so that Err stays finite (core::kMaxErr), so a non-finite number here is
/// an internal error, reported as such rather than printed. `pointer`: where `j` sits.
void require_finite(const nlohmann::json& j, const std::string& pointer = "") {
  if (j.is_number_float() && !std::isfinite(j.get<double>())) {
    throw std::logic_error("internal error: the result's " + pointer + " is " +
                           std::to_string(j.get<double>()) + ", not a finite number");
  }
  if (j.is_object()) {
    for (const auto& [key, value] : j.items()) require_finite(value, pointer + "/" + key);
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      require_finite(j[i], pointer + "/" + std::to_string(i));
    }
  }
}

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
              "d_model[m]", "volume[m3]", "comps", "removed");
  for (const auto& s : r["states"]) {
    std::printf("%4d %5d %7.3f %9.4f %10.4f %11.4f %6d %7d\n", s["time_step"].get<int>(),
                s["event"].get<int>(), s["weight"].get<double>(), s["d_true"].get<double>(),
                s["d_model"].get<double>(), s["model_volume"].get<double>(),
                s["components"].get<int>(), s["components_removed"].get<int>());
  }
  std::printf("Err = %.6f m^2", r["err"].get<double>());
  if (r.contains("tolerance")) std::printf("   (tolerance %.4f m^2)", r["tolerance"].get<double>());
  if (r.value("err_lower_bound", 0.0) > 0.0) {
    std::printf(
        "\nno configuration has Err below %.4f m^2 in this mode and resolution (voxels touching a "
        "target are always in M)",
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

#ifdef CAMPLACE_HAVE_EXACT
nlohmann::json exact_json(const exact::ExactEvaluation& e, bool fractions) {
  nlohmann::json states = nlohmann::json::array();
  for (const auto& s : e.states) {
    nlohmann::json j = state_json(s);
    if (fractions) {
      j["d_true_sq_exact"] = s.d_true_sq_exact;
      j["d_model_sq_exact"] = s.d_model_sq_exact;
      j["model_volume_exact"] = s.model_volume_exact;
    }
    states.push_back(j);
  }
  return {{"pipeline", core::name_of(core::Pipeline::exact)},
          {"err", e.err},
          {"states", states},
          {"timing_ms",
           {{"model", e.timing.labelling_ms},
            {"clustering", e.timing.clustering_ms},
            {"distance", e.timing.distance_ms},
            {"total", e.timing.total_ms}}}};
}

nlohmann::json differences(const nlohmann::json& vox, const nlohmann::json& ex) {
  nlohmann::json states = nlohmann::json::array();
  for (std::size_t i = 0; i < vox["states"].size(); ++i) {
    const auto& a = vox["states"][i];
    const auto& b = ex["states"][i];
    states.push_back(
        {{"time_step", a["time_step"]},
         {"event", a["event"]},
         {"d_model_voxel_minus_exact", a["d_model"].get<double>() - b["d_model"].get<double>()},
         {"model_volume_voxel_minus_exact",
          a["model_volume"].get<double>() - b["model_volume"].get<double>()}});
  }
  return {{"err_voxel_minus_exact", vox["err"].get<double>() - ex["err"].get<double>()},
          {"voxel_diagonal", vox["voxel_diagonal"]},
          {"states", states}};
}
#endif

// The filtered voxel model of every state, one character per voxel ('1' = in M) in index
// order i + nx·(j + ny·k), written atomically (temporary file, then rename).
void write_voxels(const voxel::VoxelEvaluator& evaluator, const core::CameraConfig& config,
                  const std::string& path) {
  const auto& n = evaluator.grid().n;
  nlohmann::json states = nlohmann::json::array();
  const auto all = core::states(evaluator.scene());
  for (std::size_t i = 0; i < all.size(); ++i) {
    std::string bits;
    for (std::uint8_t b : evaluator.model(config, static_cast<int>(i))) bits += b ? '1' : '0';
    states.push_back({{"time_step", all[i].time_step}, {"event", all[i].event}, {"model", bits}});
  }
  const nlohmann::json doc = {
      {"resolution", {n[0], n[1], n[2]}}, {"index_order", "i + nx*(j + ny*k)"}, {"states", states}};
  try {
    core::write_file_atomically(path, doc.dump() + "\n");
  } catch (const std::runtime_error& e) {
    throw core::InputError("command line", "--voxels-out", e.what());
  }
}

void run_evaluate(const EvaluateArgs& args) {
  const core::Scene scene = core::load_scene(args.scene);
  const core::CameraConfig config = core::load_camera_config(args.cameras, scene);
  voxel::VoxelOptions options;
  options.mode = parse_enum<core::LabelMode>(args.mode);
  if (!args.resolution.empty())
    options.resolution = core::parse_resolution(args.resolution, "--resolution");
  const unsigned cores = std::thread::hardware_concurrency();
  options.threads = args.threads > 0 ? args.threads : static_cast<int>(std::clamp(cores, 1u, 256u));
  options.refine = args.refine;
  const core::Pipeline pipeline = parse_enum<core::Pipeline>(args.pipeline);
  const bool want_voxel = pipeline != core::Pipeline::exact;
  const bool want_exact = pipeline != core::Pipeline::voxel;
  if (!want_exact && (args.export_given || args.exact_fractions)) {
    throw core::InputError("command line",
                           args.export_given ? "--export-mesh" : "--exact-fractions",
                           "needs --pipeline exact or both");
  }
  if (args.voxels_out_given && (!want_voxel || args.voxels_out.empty())) {
    throw core::InputError(
        "command line", "--voxels-out",
        args.voxels_out.empty() ? "needs a file name" : "needs --pipeline voxel or both");
  }
  if (args.export_given) core::create_output_directory(args.export_dir, "--export-mesh");
#ifndef CAMPLACE_HAVE_EXACT
  if (want_exact) {
    throw core::InputError("command line", "--pipeline", "this build has no exact pipeline");
  }
#endif
  nlohmann::json vox, ex;
  if (want_voxel) {
    // SPEC §1: when voxel and exact results are compared, the voxel pipeline also uses the
    // inscribed pyramid.
    core::Scene voxel_scene = scene;
    if (want_exact) voxel_scene.cameras.fov = core::FovShape::pyramid;
    const voxel::VoxelEvaluator evaluator(voxel_scene, options);
    vox = voxel_json(evaluator, evaluator.evaluate(config));
    vox["fov"] = core::name_of(voxel_scene.cameras.fov);
    if (!args.voxels_out.empty()) write_voxels(evaluator, config, args.voxels_out);
  }
#ifdef CAMPLACE_HAVE_EXACT
  if (want_exact) {
    exact::ExactOptions exact_options;
    exact_options.export_dir = args.export_dir;
    exact_options.threads = args.threads;
    ex = exact_json(exact::evaluate_exact(scene, config, exact_options), args.exact_fractions);
  }
#endif
  nlohmann::json out;
  if (want_voxel && want_exact) {
#ifdef CAMPLACE_HAVE_EXACT
    out = {{"pipeline", core::name_of(core::Pipeline::both)},
           {"voxel", vox},
           {"exact", ex},
           {"differences", differences(vox, ex)}};
#endif
  } else {
    out = want_voxel ? vox : ex;
  }
  out["scene"] = args.scene;
  out["cameras_file"] = args.cameras;
  require_finite(out);
  if (args.json) {
    std::cout << out.dump(2) << "\n";
    return;
  }
  if (want_voxel && want_exact) {
    print_table(vox);
    std::printf("\n");
    print_table(ex);
    std::printf("\nErr voxel - exact = %.6f m^2\n",
                out["differences"]["err_voxel_minus_exact"].get<double>());
  } else {
    print_table(out);
  }
}

}  // namespace

void register_evaluate_command(CLI::App& app) {
  auto args = std::make_shared<EvaluateArgs>();
  CLI::App* cmd = app.add_subcommand("evaluate", "Err of one camera configuration, state by state");
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
  cmd->add_flag("--exact-fractions", args->exact_fractions,
                "exact pipeline: add squared distances as exact fractions \"p/q\"");
  cmd->add_option("--threads", args->threads,
                  "states evaluated in parallel, both pipelines (default: one thread per core)")
      ->check(in_range(1, voxel::kMaxThreads));
  CLI::Option* export_mesh = cmd->add_option(
      "--export-mesh", args->export_dir,
      "exact pipeline: write each state's model and each camera's pyramid (OFF) to DIR");
  CLI::Option* voxels_out =
      cmd->add_option("--voxels-out", args->voxels_out,
                      "voxel pipeline: write each state's filtered model voxels to this JSON file");
  cmd->callback([args, export_mesh, voxels_out] {
    args->export_given = export_mesh->count() > 0;
    args->voxels_out_given = voxels_out->count() > 0;
    run_evaluate(*args);
  });
}

}  // namespace camplace::app
