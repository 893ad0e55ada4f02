// The shared rules of SPEC §3–4 (see sensor_model.hpp).
#include "camplace/core/sensor_model.hpp"

#include <string>

#include "camplace/core/error.hpp"

namespace camplace::core {

ObjectRole role_of(ObjectKind kind, DynamicMode mode) {
  switch (kind) {
    case ObjectKind::target:
      return ObjectRole::occupying;
    case ObjectKind::dynamic_obstacle:
      // `masked`: the robot changes the background-subtracted image exactly like a target;
      // `modelled`: its appearance is predicted, so it occludes like furniture (SPEC §2).
      return mode == DynamicMode::masked ? ObjectRole::occupying : ObjectRole::occluding;
    case ObjectKind::static_obstacle:
      break;
  }
  return ObjectRole::occluding;
}

bool is_obstacle(ObjectKind kind) { return kind != ObjectKind::target; }

std::vector<StateObject> state_objects(const Scene& scene, const StateIndex& state) {
  const TimeStep& step = scene.time_steps.at(state.time_step);
  std::vector<StateObject> out;
  auto add = [&](const std::vector<SceneObject>& objects, ObjectKind kind) {
    for (const SceneObject& o : objects)
      out.push_back({&o, kind, role_of(kind, scene.dynamic_mode)});
  };
  add(scene.static_obstacles, ObjectKind::static_obstacle);
  add(step.dynamic_obstacles, ObjectKind::dynamic_obstacle);
  add(step.events.at(state.event).targets, ObjectKind::target);
  return out;
}

double empty_model_distance(const Box3& area) { return area.diagonal(); }

void check_configuration(const Scene& scene, const CameraConfig& config) {
  if (static_cast<int>(config.size()) != scene.cameras.count) {
    throw InputError(scene.file, "/cameras/count",
                     "the configuration has " + std::to_string(config.size()) +
                         " cameras, the scene " + std::to_string(scene.cameras.count));
  }
  // A scene built in code keeps one model per camera (CameraSpec::resize keeps it so).
  CAMPLACE_ASSERT(scene.cameras.models.size() == config.size());
}

}  // namespace camplace::core
