// Study files (SPEC §9): the examinations of the paper and the budget of their runs.
#include "study_definition.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "camplace/core/error.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/provenance.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/optimize/optimizer.hpp"
#include "camplace/scenes/generator.hpp"
#include "camplace/voxel/evaluator.hpp"

namespace camplace::compare::detail {
namespace {

/// A `refine` entry (of the study or of one examination): a level voxel::kMaxRefine allows, and
/// only in conservative mode.
int read_refine(const core::JsonNode& node, core::LabelMode mode) {
  const int refine = node.integer_in(0, voxel::kMaxRefine);
  if (refine > 0 && mode != core::LabelMode::conservative) {
    node.fail("refinement needs \"mode\": \"conservative\"");
  }
  return refine;
}

/// An `objective` entry: one of optimize::objective_names().
std::string read_objective(const core::JsonNode& node) {
  const std::string objective = node.string();
  const std::vector<std::string>& names = optimize::objective_names();
  if (std::find(names.begin(), names.end(), objective) == names.end()) {
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    node.fail("unknown objective \"" + objective + "\" (expected one of: " + list + ")");
  }
  return objective;
}

}  // namespace

StudySpec parse_study(const std::string& path) {
  const nlohmann::json doc = core::read_json_file(path);
  const core::JsonNode root(doc, path, "");
  root.only_keys({"description", "base", "algorithm", "objective", "mode", "refine",
                  "runs_per_group", "threads", "first_seed", "scene_seed", "time_limit_s",
                  "max_evaluations", "examinations"});
  StudySpec s;
  s.name = std::filesystem::path(path).stem().string();
  s.file = path;
  s.started = core::now_iso8601();
  if (root.has("base")) {
    // Relative to the study file's folder, so the study runs from any working directory.
    const std::string label = root.at("base").string();
    const std::filesystem::path rel(label);
    s.base_file =
        rel.is_absolute()
            ? label
            : (std::filesystem::path(path).parent_path() / rel).lexically_normal().string();
    try {
      s.base =
          std::make_shared<const scenes::BaseScene>(scenes::load_base_scene(s.base_file, label));
    } catch (const core::InputError& err) {
      root.at("base").fail("the base scene does not load: " + std::string(err.what()));
    }
  }
  if (root.has("description")) s.description = root.at("description").string();
  if (root.has("algorithm")) {
    s.algorithm = root.at("algorithm").string();
    const std::vector<std::string>& algorithms = optimize::algorithm_names();
    if (std::find(algorithms.begin(), algorithms.end(), s.algorithm) == algorithms.end()) {
      std::string list;
      for (const std::string& a : algorithms) list += (list.empty() ? "" : ", ") + a;
      root.at("algorithm")
          .fail("unknown solver \"" + s.algorithm + "\" (expected one of: " + list + ")");
    }
  }
  if (root.has("mode")) {
    const std::string mode = root.at("mode").string();
    const auto parsed = core::from_name<core::LabelMode>(mode);
    if (!parsed) root.at("mode").fail("expected " + core::names_listed<core::LabelMode>());
    s.mode = *parsed;
  }
  if (root.has("refine")) s.refine = read_refine(root.at("refine"), s.mode);
  if (root.has("objective")) s.objective = read_objective(root.at("objective"));
  s.runs_per_group = root.at("runs_per_group").integer_in(1, 1000);
  if (root.has("threads")) s.threads = root.at("threads").integer_in(1, 256);
  if (root.has("first_seed")) s.first_seed = root.at("first_seed").integer_in(0, 1 << 30);
  if (root.has("scene_seed")) s.scene_seed = root.at("scene_seed").integer_in(0, 1 << 30);
  s.time_limit = root.at("time_limit_s").number_in(0.1, 1e7);
  s.max_evaluations = root.at("max_evaluations").integer_in(1, 2000000000);
  const core::JsonNode list = root.at("examinations");
  if (list.array_size() == 0) list.fail("a study needs at least one examination");
  // Each group (family and parameter) is one folder of runs: two examinations naming the same
  // group would run its seeds into the same files, and two of the same name would share a row
  // of the report.
  std::map<std::string, std::string> group_entry, name_entry;  // → the entry that gave it
  constexpr std::size_t kMaxExaminations = 1000, kMaxParams = 1000;
  if (list.array_size() > kMaxExaminations) {
    list.fail("at most " + std::to_string(kMaxExaminations) + " examinations, found " +
              std::to_string(list.array_size()));
  }
  for (std::size_t i = 0; i < list.array_size(); ++i) {
    const core::JsonNode e = list.at(i);
    e.only_keys({"name", "family", "params", "refine", "objective"});
    Examination ex;
    if (e.has("refine")) ex.refine = read_refine(e.at("refine"), s.mode);
    if (e.has("objective")) ex.objective = read_objective(e.at("objective"));
    ex.family = e.at("family").string();
    ex.name = e.has("name") ? e.at("name").string() : ex.family;
    const auto [named, fresh_name] = name_entry.emplace(ex.name, e.pointer());
    if (!fresh_name) {
      (e.has("name") ? e.at("name") : e)
          .fail("examination \"" + ex.name + "\" is named twice (also " + named->second +
                "): give each examination its own \"name\"");
    }
    if (e.has("params")) {
      const core::JsonNode p = e.at("params");
      if (p.array_size() > kMaxParams) {
        p.fail("at most " + std::to_string(kMaxParams) + " parameters, found " +
               std::to_string(p.array_size()));
      }
      for (std::size_t k = 0; k < p.array_size(); ++k)
        ex.params.push_back(p.at(k).integer_in(-1000, 1000));
    }
    if (ex.params.empty()) ex.params.push_back(std::nullopt);
    for (std::size_t k = 0; k < ex.params.size(); ++k) {
      const std::string group = group_name(ex, ex.params[k]);
      const std::string entry = e.has("params") ? e.at("params").at(k).pointer() : e.pointer();
      const auto [seen, fresh] = group_entry.emplace(group, entry);
      if (!fresh) {
        throw core::InputError(path, entry,
                               "group \"" + group + "\" is given twice (also " + seen->second +
                                   "): its runs would share one folder; list each family and "
                                   "parameter once");
      }
    }
    for (const std::optional<int>& param : ex.params) {
      std::string text;
      try {
        // Validates family and param, and that the family applies to the base.
        text = scenes::generate_scene_json(ex.family, param, s.scene_seed, s.base.get());
      } catch (const core::InputError& err) {
        e.fail(err.reason());
      }
      const int refine = refine_of(s, ex);
      if (refine > 0) {
        // The memory estimate at the group's resolution, before any run starts.
        // refine_problem() reads the resolution and the counts of time steps and events.
        const nlohmann::json generated = nlohmann::json::parse(text);
        core::Scene scene;
        for (int a = 0; a < 3; ++a) scene.voxels[a] = generated.at("voxels").at(a).get<int>();
        for (const auto& step : generated.at("time_steps")) {
          scene.time_steps.emplace_back();
          scene.time_steps.back().events.resize(step.at("events").size());
        }
        voxel::VoxelOptions options;
        options.mode = s.mode;
        options.refine = refine;
        const std::string problem = voxel::refine_problem(scene, options);
        if (!problem.empty()) {
          (ex.refine ? e : root).at("refine").fail(group_name(ex, param) + ": " + problem);
        }
      }
    }
    s.examinations.push_back(ex);
  }
  return s;
}

int refine_of(const StudySpec& spec, const Examination& e) {
  return e.refine.value_or(spec.refine);
}

const std::string& objective_of(const StudySpec& spec, const Examination& e) {
  return e.objective ? *e.objective : spec.objective;
}

std::string group_name(const Examination& e, const std::optional<int>& param) {
  return param ? e.family + "-" + std::to_string(*param) : e.family;
}

}  // namespace camplace::compare::detail
