#pragma once
// A study file (data/studies/*.json) read into its examinations and budget. Private to compare.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camplace/core/names.hpp"
#include "camplace/scenes/generator.hpp"

namespace camplace::compare::detail {

/// One examination: a scene family of the generator and the parameters of its groups.
struct Examination {
  std::string name, family;
  std::vector<std::optional<int>> params;  ///< one empty entry for families without a param
  /// The study's `refine` and `objective` for this examination's runs, when it sets its own.
  std::optional<int> refine;
  std::optional<std::string> objective;
};

/// The study: its examinations and the budget of every run.
struct StudySpec {
  std::string name;  ///< the study file's name without its extension (the report's title)
  std::string description, algorithm = "gaco";
  std::string objective = "err";  ///< optimize::OptimizeOptions::objective of every run
  core::LabelMode mode = core::LabelMode::conservative;
  int refine = 0;  ///< voxel::VoxelOptions::refine of every run (conservative mode)
  int runs_per_group = 3, threads = 2;
  unsigned first_seed = 1, scene_seed = 1;
  double time_limit = 600.0;  ///< seconds per run
  long long max_evaluations = 10000;
  std::vector<Examination> examinations;
  /// The scene the families are applied to: null for the paper's basic setup (no "base").
  /// Its label is the study file's "base" as written (relative to the study file's folder).
  std::shared_ptr<const scenes::BaseScene> base;
  std::string base_file;  ///< the base's path as opened ("" without a base)
  std::string file;       ///< the study file as given
  std::string started;    ///< when the study file was read (core::now_iso8601): the study's start
};

/// Reads the study file `path`; the algorithm must be one of optimize::algorithm_names(), every
/// (family, param) one the scene generator makes (on the study's base scene, when it names one),
/// and `refine` one voxel::refine_problem() accepts for every group's scene. Throws
/// core::InputError naming the study file, the entry and the reason.
StudySpec parse_study(const std::string& path);

/// The refinement level of the examination's runs: its own `refine`, else the study's.
int refine_of(const StudySpec& spec, const Examination& e);
/// What the examination's runs minimise: its own `objective`, else the study's.
const std::string& objective_of(const StudySpec& spec, const Examination& e);

/// The group's name: "<family>-<param>", or the family alone.
std::string group_name(const Examination& e, const std::optional<int>& param);

}  // namespace camplace::compare::detail
