#pragma once
// The voxel evaluator's private state (manifold's impl.h pattern): one Impl, its stages in
// separate files — set-up (setup.cpp), labelling (labelling.cpp), components (components.cpp),
// distances (distance.cpp) — and the public class in evaluator.cpp. Hot path: plain arrays and
// Eigen, no CGAL.
#include <array>
#include <chrono>
#include <cstdint>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/sensor_model.hpp"
#include "camplace/voxel/evaluator.hpp"

namespace camplace::voxel {

namespace detail {

using Clock = std::chrono::steady_clock;
inline double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// One object of the scene with its fixed role (SPEC §3: what a first hit on it means).
struct ObjectInfo {
  const core::TriangleMesh* mesh = nullptr;
  bool occupying = false;  ///< core::ObjectRole::occupying
  core::Vec3 center = core::Vec3::Zero();
  double radius = 0.0;  ///< bounding sphere
  int first_triangle = 0;
  int triangle_count = 0;
};

/// Per camera and object: the cone from the camera around the object's bounding sphere.
struct ObjectCone {
  core::Vec3 axis = core::Vec3::UnitX();
  double cos_b = -1.0, sin_b = 0.0;
  bool no_cull = true;           ///< camera inside the bounding sphere
  bool contains_camera = false;  ///< camera inside the solid: it is blind in this state
};

/// Per camera and triangle: the infinite cone from the camera over the triangle, as its three
/// edge rays (vertex − camera) and the inward unit normals of its three planes, and the
/// triangle's nearest distance.
struct TriangleCone {
  core::Vec3 edge[3];
  core::Vec3 normal[3];
  double near_distance = 0.0;
  bool flat = false;  ///< camera in the triangle's plane: the cone has no volume
};

/// Everything about one camera that does not depend on the state.
struct CameraView {
  core::CameraSetting setting;
  std::vector<std::uint8_t> in_fov;  ///< per voxel
  std::vector<core::Vec3> dir;       ///< unit direction camera → voxel centre
  std::vector<double> dist;          ///< camera → voxel centre
  std::vector<double> cos_b, sin_b;  ///< angular radius of the voxel's bounding ball (0 centre)
  std::vector<double> far;           ///< farthest voxel point from the camera
  std::vector<ObjectCone> objects;
  std::vector<TriangleCone> triangles;
};

struct StateInfo {
  int time_step = 0, event = 0;
  double weight = 0.0;
  double d_true = 0.0;
  std::vector<int> objects;  ///< indices into Impl::objects
};

}  // namespace detail

struct VoxelEvaluator::Impl {
  core::Scene scene;
  VoxelOptions options;
  Grid grid;
  bool conservative = true;
  core::Vec3 half_step = core::Vec3::Zero();
  double voxel_radius = 0.0;
  double voxel_volume = 0.0;
  std::vector<detail::ObjectInfo> objects;
  std::vector<std::array<core::Vec3, 3>> triangles;  ///< all objects' triangles, world frame
  std::vector<detail::StateInfo> states;
  std::vector<std::vector<std::uint8_t>> removed_by_step;  ///< obstacle interiors per step
  std::vector<std::vector<double>> critical_sq_by_step;    ///< d(C_h, voxel)² per step
  double err_lower_bound = 0.0;                            ///< conservative mode only

  // Set-up (setup.cpp): everything that does not depend on the cameras.
  void build();
  int add_object(const core::SceneObject& object, core::ObjectRole role);
  double lower_bound() const;
  std::vector<std::uint8_t> obstacle_interiors(const core::TimeStep& step) const;
  std::vector<double> critical_distances(const core::TimeStep& step) const;

  // Labelling (labelling.cpp): SPEC §3 per camera, voxel and state.
  std::vector<detail::CameraView> views(const core::CameraConfig& config) const;
  detail::CameraView view(const core::CameraSetting& camera) const;
  bool blind(const detail::CameraView& view, const detail::StateInfo& state) const;
  Label label(const detail::CameraView& view, const detail::StateInfo& state, int v,
              bool free_only) const;
  /// Model before filtering: 1 where no camera sees the voxel free, minus obstacle interiors.
  std::vector<std::uint8_t> raw_model(const std::vector<detail::CameraView>& views,
                                      const detail::StateInfo& state) const;

  // Distance (distance.cpp): d(C_h, M) and the model's volume for one state.
  struct ModelDistance {
    double d_model = 0.0;  ///< m; core::empty_model_distance when M is empty
    double volume = 0.0;   ///< m³
  };
  ModelDistance model_distance(const std::vector<std::uint8_t>& model, int time_step) const;

 private:
  bool box_in_fov(const core::Fov& fov, const core::Box3& box) const;
  bool may_meet(const detail::CameraView& view, int o, int v) const;
  Label label_center(const detail::CameraView& view, const detail::StateInfo& state, int v,
                     bool free_only) const;
  Label label_conservative(const detail::CameraView& view, const detail::StateInfo& state, int v,
                           bool free_only) const;
  bool cone_misses_box(const detail::TriangleCone& tc, const core::Vec3& w) const;
};

}  // namespace camplace::voxel
