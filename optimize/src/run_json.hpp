#pragma once
// The JSON of a run's cameras and context, as run files and summary.json hold them; shared by
// run_file.cpp and run_summary.cpp. Private to optimize.
#include <nlohmann/json.hpp>

#include "camplace/optimize/report.hpp"

namespace camplace::optimize {
namespace {

nlohmann::ordered_json cameras_json(const core::CameraConfig& config,
                                    const std::vector<std::string>& models) {
  // The same text `camplace evaluate --cameras` reads (core::load_camera_config), keys in
  // alphabetical order ("model" first when the models are named).
  nlohmann::json cameras = nlohmann::json::parse(core::camera_config_json(config)).at("cameras");
  if (models.size() == config.size()) {
    for (std::size_t i = 0; i < config.size(); ++i) cameras[i]["model"] = models[i];
  }
  return nlohmann::ordered_json::parse(cameras.dump());
}

nlohmann::ordered_json context_json(const RunContext& context) {
  nlohmann::ordered_json j = {
      {"scene", context.scene_file}, {"mode", context.mode}, {"resolution", context.resolution}};
  if (context.refine > 0) j["refine"] = context.refine;
  j["start"] = context.start;
  j["time_limit_s"] = context.time_limit;
  j["max_evaluations"] = context.max_evaluations;
  return j;
}

}  // namespace
}  // namespace camplace::optimize
