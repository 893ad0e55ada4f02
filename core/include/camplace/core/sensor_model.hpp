#pragma once
/// The rules of SPEC §3–4 that both pipelines share: what each object of a state does to a
/// camera's rays, which objects' interiors leave the model, the distance to an empty model and
/// the plausibility filter (Plausibility::keeps in scene.hpp), and the configuration check.
/// Each rule is defined here once; the voxel and the exact pipeline call these functions.
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::core {

/// The three kinds of object a state holds (SPEC §2).
enum class ObjectKind { static_obstacle, dynamic_obstacle, target };

/// What a camera ray whose first hit is the object means (SPEC §3, step 2).
enum class ObjectRole {
  occluding,  ///< free strictly before the hit, undetectable behind: static obstacles, and
              ///< dynamic obstacles in `modelled` mode
  occupying   ///< the pixel changed, every point of the ray may hold the target: targets, and
              ///< dynamic obstacles in `masked` mode (the silhouette cone)
};

/// The role of an object of this kind under the scene's dynamic mode (SPEC §3).
ObjectRole role_of(ObjectKind kind, DynamicMode mode);

/// True for the objects whose interiors are subtracted from the model: the obstacles, static and
/// dynamic, but not the targets (SPEC §4).
bool is_obstacle(ObjectKind kind);

/// One object of a state with its kind and role.
struct StateObject {
  const SceneObject* object = nullptr;
  ObjectKind kind = ObjectKind::static_obstacle;
  ObjectRole role = ObjectRole::occluding;
};

/// Every object of the state, in the order static obstacles, the time step's dynamic
/// obstacles, the event's targets (a camera inside any of them is blind, SPEC §3.3).
std::vector<StateObject> state_objects(const Scene& scene, const StateIndex& state);

/// d(C, ∅) of SPEC §4: the length of S's diagonal (losing the target is penalised).
double empty_model_distance(const Box3& area);

/// The same rule squared, computed in the number type T from the exact corners of S (for the
/// exact pipeline: T = an exact rational type).
template <class T>
T empty_model_squared_distance(const Box3& area) {
  T sum(0);
  for (int i = 0; i < 3; ++i) {
    const T d = T(area.max[i]) - T(area.min[i]);
    sum += d * d;
  }
  return sum;
}

/// Checks that `config` holds one setting per camera of the scene; throws InputError naming
/// the scene file and /cameras/count otherwise.
void check_configuration(const Scene& scene, const CameraConfig& config);

}  // namespace camplace::core
