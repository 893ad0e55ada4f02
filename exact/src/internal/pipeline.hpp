#pragma once
// The model of each state from the cameras (SPEC §3–4), with the parts shared between states
// cached per camera: the static part, and the time step's part. Private to exact_pipeline.cpp.
//
// For camera c and one state (SPEC §3):
//   Free_c = (FOV_c ∩ S) ∖ (U ∪ V)
//   U = ∪ shadow volumes of the occluding objects (core::role_of): points p whose segment
//       [c, p] meets the object; for a non-convex one, the sweeps of patches of its front faces
//       found in the image plane (shadow_patches, shadow), or the union of one shadow per front
//       face as a reference (ExactOptions::face_shadows);
//   V = ∪ silhouette cones of the occupying objects, each cut where an occluding object hides
//       it: cones over their outlines in the camera's image plane (occupied_outline,
//       outline_cone); a convex solid nothing hides, or every solid as a reference
//       (ExactOptions::face_cones), by occupied_cone (one hull, or one cone per face).
//   M = reg(S ∖ ∪_c Free_c ∖ obstacles) (SPEC §4, regularised: closure of the interior), the
//       obstacles subtracted once, last (ExactOptions::obstacles_last; the former order starts
//       from S ∖ obstacles, so every camera's boolean carries the obstacles' facets).
//
// What is computed once and reused (per Pipeline, i.e. per worker thread):
//   static part   FOV ∩ clip box minus the static obstacles' shadows, per camera;
//   step part     that minus the step's dynamic obstacles' shadows or cones, per camera and step
//                 (dropped when the pipeline moves on to another step);
//   target cones  the union V of a state's targets, per camera and per pose: states whose targets
//                 have the same meshes (vertex for vertex) and whose occluders have the same
//                 meshes share it (a person standing at the same place in every time step);
//   step obstacles the union of the step's obstacles, and in the former order S minus it, per
//                 step (dropped likewise).
#include <cmath>
#include <cstddef>
#include <cstring>
#include <functional>
#include <map>
#include <optional>
#include <unordered_map>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/sensor_model.hpp"
#include "camplace/exact/evaluator.hpp"
#include "internal/cones.hpp"
#include "internal/kernel.hpp"
#include "internal/model.hpp"
#include "internal/solids.hpp"

namespace camplace::exact::internal {

class Pipeline {
 public:
  /// Throws core::InputError when the configuration does not match the scene. Of `options`, the
  /// choices of construction: face_cones, face_shadows, reuse_poses, obstacles_last
  /// (ExactOptions).
  Pipeline(const core::Scene& scene, const core::CameraConfig& config,
           const ExactOptions& options = {})
      : scene_(scene),
        face_cones_(options.face_cones),
        face_shadows_(options.face_shadows),
        reuse_poses_(options.reuse_poses),
        obstacles_last_(options.obstacles_last) {
    core::check_configuration(scene, config);
    area_ = box_nef(scene.area);
    // The FOVs are clipped to a box a little larger than S rather than to S itself: the model's
    // facets on S's faces then never coincide with a free region's facets, and each Nef boolean
    // does the costly local overlay only where the boundaries really cross (about 20% of the
    // booleans' time on paper_basic). Free space outside S changes nothing in M ⊂ S.
    const double margin = std::exp2(std::floor(std::log2(scene.area.diagonal() / 16.0)));
    const core::Box3 clip{scene.area.min - core::Vec3::Constant(margin),
                          scene.area.max + core::Vec3::Constant(margin)};
    const Nef clip_box = box_nef(clip);
    auto add = [this](const std::vector<core::SceneObject>& objects) {
      for (const auto& o : objects) {
        solids_.try_emplace(&o, o.mesh);
        shape_.emplace(&o, shape_id(o.mesh));
      }
    };
    add(scene.static_obstacles);
    for (const auto& step : scene.time_steps) {
      add(step.dynamic_obstacles);
      add(step.critical);
      for (const auto& ev : step.events) add(ev.targets);
    }
    for (std::size_t i = 0; i < config.size(); ++i) {
      const core::CameraSetting& setting = config[i];
      Camera cam;
      cam.view = view_point(setting, clip);
      cam.fov = fov_nef(cam.view, setting, scene.cameras.models.at(i)) * clip_box;
      cam.image = image_plane(setting, scene.cameras.models.at(i));
      cameras_.push_back(std::move(cam));
    }
    step_free_.resize(cameras_.size());
    step_obstacles_.resize(scene.time_steps.size());
    step_area_.resize(scene.time_steps.size());
  }

  /// The model of a state before the filter, regularised, and the number of pieces the filter
  /// certainly removes that were discarded on the way (discard_implausible).
  struct StateModel {
    Nef nef;
    int discarded = 0;
  };

  /// S minus each camera's free region in turn, then minus the obstacles. Subtracting the free
  /// regions one by one from the shrinking model costs less than their balanced union followed by
  /// one subtraction (each Nef boolean visits every vertex of both operands, and the model stays
  /// smaller than the union). The obstacles come last, once: subtracted first (the former order,
  /// ExactOptions::obstacles_last off), their facets (a fine robot's thousands) ride through every
  /// camera's boolean. The same kept model either way (docs/design/exact-model.md E1). After each
  /// camera but the last, the pieces that the filter will certainly remove are discarded (on
  /// paper_basic most of the model's vertices, so the later booleans cost ~40% less); the kept
  /// model does not depend on the order, but the count of removed components may
  /// (discard_implausible). `camera_done` (may be empty) is called after each camera's step, also
  /// for the cameras skipped because the model is already empty.
  StateModel model(const core::StateIndex& s, const std::function<void()>& camera_done = {}) {
    const auto objects = core::state_objects(scene_, s);
    // A step's caches are dropped when the pipeline moves on to another step: the worker threads
    // take whole time steps (or slices of one), so a thread holds one step's at a time, not every
    // step's (at worst a step is visited again and its part recomputed: the same sets).
    if (current_step_ >= 0 && current_step_ != s.time_step) release_step(current_step_);
    current_step_ = s.time_step;
    StateModel out;
    Nef m = obstacles_last_ ? area_ : step_area(s.time_step, objects);
    std::size_t c = 0;
    for (; c < cameras_.size() && !m.is_empty(); ++c) {
      const Nef free = state_free(c, s, objects);
      if (!free.is_empty()) m -= free;
      if (c + 1 < cameras_.size()) out.discarded += discard_implausible(m, scene_.plausibility);
      if (camera_done) camera_done();
    }
    for (; c < cameras_.size(); ++c)
      if (camera_done) camera_done();
    if (obstacles_last_ && !m.is_empty()) {
      const Nef& obstacles = step_obstacles(s.time_step, objects);
      if (!obstacles.is_empty()) m -= obstacles;
    }
    out.nef = m.regularization();
    return out;
  }

  /// The critical objects C_h of time step h (SPEC §2).
  std::vector<const Solid*> critical(int h) const {
    std::vector<const Solid*> out;
    for (const auto& o : scene_.time_steps[h].critical) out.push_back(&solid(o));
    return out;
  }

  /// FOV ∩ S of camera c (for export).
  Nef fov(std::size_t c) const { return cameras_[c].fov * area_; }
  std::size_t camera_count() const { return cameras_.size(); }

 private:
  struct Camera {
    ViewPoint view;
    Nef fov;           ///< pyramid ∩ clip box
    ImagePlane image;  ///< for the outlines of occupying objects and the shadows' patches
    std::optional<Nef> static_free;
  };

  const Solid& solid(const core::SceneObject& o) const { return solids_.at(&o); }

  /// The state's objects of this kind.
  std::vector<const Solid*> of_kind(const std::vector<core::StateObject>& objects,
                                    core::ObjectKind kind) const {
    std::vector<const Solid*> out;
    for (const auto& o : objects)
      if (o.kind == kind) out.push_back(&solid(*o.object));
    return out;
  }

  /// The state's occluding objects, which cut the silhouette cones of occupying ones. Targets
  /// never occlude (SPEC §3), so they are the same for every event of a time step.
  std::vector<const Solid*> occluders(const std::vector<core::StateObject>& objects) const {
    std::vector<const Solid*> out;
    for (const auto& o : objects) {
      CAMPLACE_ASSERT(o.kind != core::ObjectKind::target || o.role == core::ObjectRole::occupying);
      if (o.role == core::ObjectRole::occluding) out.push_back(&solid(*o.object));
    }
    return out;
  }

  /// What camera c cannot see past among the state's objects of one kind: shadows of the
  /// occluding ones, silhouette cones of the occupying ones (c outside all of them).
  Nef hidden(std::size_t c, const std::vector<core::StateObject>& objects,
             core::ObjectKind kind) const {
    const ViewPoint& cam = cameras_[c].view;
    const auto blockers = occluders(objects);
    std::vector<Nef> parts;
    std::vector<const Faces*> occupying;
    for (const auto& o : objects) {
      if (o.kind != kind) continue;
      const Solid& s = solid(*o.object);
      // A convex solid nothing hides has a convex cone: one hull (occupied_cone) of points with
      // short coordinates, cheaper in the later booleans than a cone over an outline, whose
      // image-plane points are long rationals.
      if (o.role == core::ObjectRole::occluding)
        parts.push_back(shadow(cam, cameras_[c].image, s, face_shadows_));
      else if (face_cones_ || (s.convex && !may_be_hidden(cam, s, blockers)))
        parts.push_back(occupied_cone(cam, s, blockers));
      else
        occupying.push_back(&s);
    }
    if (!occupying.empty()) {
      const std::vector<const Faces*> blocking(blockers.begin(), blockers.end());
      parts.push_back(outline_cone(cam, occupied_outline(cameras_[c].image, occupying, blocking)));
    }
    return union_all(std::move(parts));
  }

  /// `free` minus what camera c cannot see past among the state's objects of one kind (hidden).
  /// Empty when c lies inside one of them.
  Nef remove_hidden(std::size_t c, Nef free, const std::vector<core::StateObject>& objects,
                    core::ObjectKind kind) const {
    if (free.is_empty()) return free;
    if (camera_inside(cameras_[c].view, of_kind(objects, kind))) return Nef();
    const Nef removed = hidden(c, objects, kind);
    if (!removed.is_empty()) free -= removed;
    return free;
  }

  /// FOV ∩ clip box minus the static obstacles' shadows (cached per camera). Static obstacles
  /// always occlude (SPEC §3), so this part depends on no time step.
  const Nef& static_free(std::size_t c, const std::vector<core::StateObject>& objects) {
    Camera& cam = cameras_[c];
    if (!cam.static_free) {
      CAMPLACE_ASSERT(core::role_of(core::ObjectKind::static_obstacle, scene_.dynamic_mode) ==
                      core::ObjectRole::occluding);
      cam.static_free.emplace(
          remove_hidden(c, cam.fov, objects, core::ObjectKind::static_obstacle));
    }
    return *cam.static_free;
  }

  /// static_free minus the dynamic obstacles' shadows or cones (cached per camera and step).
  const Nef& step_free(std::size_t c, int h, const std::vector<core::StateObject>& objects) {
    auto& slot = step_free_[c];
    if (slot.size() < scene_.time_steps.size()) slot.resize(scene_.time_steps.size());
    if (!slot[h])
      slot[h] =
          remove_hidden(c, static_free(c, objects), objects, core::ObjectKind::dynamic_obstacle);
    return *slot[h];
  }

  /// Free_c of SPEC §3 for one state: step_free minus the targets' cones, which depend only on
  /// the camera, the targets' meshes and the occluders' meshes (hidden; targets never occlude),
  /// so states of the same pose share them (target_cones_).
  Nef state_free(std::size_t c, const core::StateIndex& s,
                 const std::vector<core::StateObject>& objects) {
    const Nef& free = step_free(c, s.time_step, objects);
    if (!reuse_poses_) return remove_hidden(c, free, objects, core::ObjectKind::target);
    if (free.is_empty()) return free;
    if (camera_inside(cameras_[c].view, of_kind(objects, core::ObjectKind::target))) return Nef();
    // The key: the camera, the targets' shapes in order, a separator, the occluders' shapes.
    std::vector<int> key{int(c)};
    for (const auto& o : objects)
      if (o.kind == core::ObjectKind::target) key.push_back(shape_.at(o.object));
    key.push_back(-1);
    for (const auto& o : objects)
      if (o.role == core::ObjectRole::occluding) key.push_back(shape_.at(o.object));
    auto it = target_cones_.find(key);
    if (it == target_cones_.end())
      it = target_cones_.emplace(key, hidden(c, objects, core::ObjectKind::target)).first;
    if (it->second.is_empty()) return free;
    return free - it->second;
  }

  /// The id of a mesh's shape: meshes with the same vertices (bit for bit) and triangles get the
  /// same id.
  int shape_id(const core::TriangleMesh& mesh) {
    std::size_t h = mesh.vertices.size() * 1000003u + mesh.triangles.size();
    auto mix = [&h](const void* data, std::size_t bytes) {
      for (std::size_t i = 0; i < bytes; ++i)
        h = (h ^ static_cast<const unsigned char*>(data)[i]) * 1099511628211ull;
    };
    for (const auto& v : mesh.vertices) {
      const double xyz[3] = {v.x(), v.y(), v.z()};
      mix(xyz, sizeof xyz);
    }
    for (const auto& t : mesh.triangles) mix(t.data(), sizeof(int) * 3);
    auto& bucket = shapes_by_hash_[h];
    for (const auto& [other, id] : bucket) {
      if (other->triangles != mesh.triangles || other->vertices.size() != mesh.vertices.size())
        continue;
      bool same = true;
      for (std::size_t i = 0; i < mesh.vertices.size() && same; ++i)
        same = std::memcmp(mesh.vertices[i].data(), other->vertices[i].data(),
                           3 * sizeof(double)) == 0;
      if (same) return id;
    }
    bucket.emplace_back(&mesh, next_shape_);
    return next_shape_++;
  }

  /// Drops the caches of time step h.
  void release_step(int h) {
    for (auto& slot : step_free_)
      if (std::size_t(h) < slot.size()) slot[h].reset();
    step_obstacles_[h].reset();
    step_area_[h].reset();
  }

  /// The union of the obstacles of step h (cached per step; targets are no obstacles, SPEC §4).
  const Nef& step_obstacles(int h, const std::vector<core::StateObject>& objects) {
    if (!step_obstacles_[h]) {
      std::vector<Nef> parts;
      for (const auto& o : objects)
        if (core::is_obstacle(o.kind)) parts.push_back(solid(*o.object).as_nef());
      step_obstacles_[h] = union_all(std::move(parts));
    }
    return *step_obstacles_[h];
  }

  /// S minus the obstacles of step h (cached per step), where the former order starts.
  const Nef& step_area(int h, const std::vector<core::StateObject>& objects) {
    if (!step_area_[h]) {
      Nef a = area_;
      const Nef& obstacles = step_obstacles(h, objects);
      if (!obstacles.is_empty()) a -= obstacles;
      step_area_[h] = std::move(a);
    }
    return *step_area_[h];
  }

  const core::Scene& scene_;
  bool face_cones_ = false;
  bool face_shadows_ = false;
  bool reuse_poses_ = true;
  bool obstacles_last_ = true;
  std::unordered_map<const core::SceneObject*, int> shape_;
  std::unordered_map<std::size_t, std::vector<std::pair<const core::TriangleMesh*, int>>>
      shapes_by_hash_;
  int next_shape_ = 0;
  std::map<std::vector<int>, Nef> target_cones_;
  Nef area_;
  std::unordered_map<const core::SceneObject*, Solid> solids_;
  std::vector<Camera> cameras_;
  std::vector<std::vector<std::optional<Nef>>> step_free_;
  std::vector<std::optional<Nef>> step_obstacles_, step_area_;
  int current_step_ = -1;
};

}  // namespace camplace::exact::internal
