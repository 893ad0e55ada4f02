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
// Once a box around the model fills at most half the clip box (ExactOptions::model_box_fraction),
// each camera's free region is built only within that box, from FOV ∩ box and the parts of U and
// V that rays from c through the box can meet (state_free_within; the same model,
// docs/design/exact-model.md E3).
//
// What is computed once and reused (per Pipeline, i.e. per worker thread; the scene objects'
// exact solids and the cameras' FOVs are built on first use, so a pipeline that serves one state
// or one camera costs little to set up):
//   hidden parts  the static obstacles' shadows per camera, the dynamic obstacles' shadows or
//                 cones per camera and step;
//   static part   FOV ∩ clip box minus the static obstacles' shadows, per camera;
//   step part     that minus the step's dynamic obstacles' shadows or cones, per camera and step
//                 (the step's parts dropped when the pipeline moves on to another step);
//   target cones  the union V of a state's targets, per camera and per pose: states whose targets
//                 have the same meshes (vertex for vertex) and whose occluders have the same
//                 meshes share it (a person standing at the same place in every time step);
//   free region   Free_c of a state, per camera and state, only when built ahead (below);
//   step obstacles the union of the step's obstacles, and in the former order S minus it, per
//                 step (dropped likewise).
//
// Helper threads (ExactOptions::threads, when there are fewer states' tasks than threads) build
// ahead, each unit (state, camera) in a Pipeline of its own (prefill), the parts above that do not
// depend on the model: while the model still fills the clip box (no model box yet), the whole free
// region of the camera with the parts it is built from; after that, the hidden parts whose sight
// may meet FOV ∩ the model box (the box only shrinks). The helper's pipeline is destroyed before
// the parts are handed over (take_parts); the consuming pipeline only moves them into its caches
// (adopt), so no Nef polyhedron or lazy exact number is ever used by two threads at once (the
// parts' handles keep what they share with the helper's solids alive, reference counts being atomic
// with CGAL_HAS_THREADS). Each state's model stays one sequential loop over the cameras, and a part
// is the same point set whoever builds it, so no result depends on the number of threads
// (docs/design/exact-model.md E4).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <functional>
#include <iterator>
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
  /// choices of construction: face_cones, face_shadows, reuse_poses, obstacles_last,
  /// model_box_fraction (ExactOptions).
  Pipeline(const core::Scene& scene, const core::CameraConfig& config,
           const ExactOptions& options = {})
      : scene_(scene),
        config_(config),
        face_cones_(options.face_cones),
        face_shadows_(options.face_shadows),
        reuse_poses_(options.reuse_poses),
        obstacles_last_(options.obstacles_last),
        model_box_fraction_(options.model_box_fraction) {
    core::check_configuration(scene, config);
    area_ = box_nef(scene.area);
    // The FOVs are clipped to a box a little larger than S rather than to S itself: the model's
    // facets on S's faces then never coincide with a free region's facets, and each Nef boolean
    // does the costly local overlay only where the boundaries really cross (about 20% of the
    // booleans' time on paper_basic). Free space outside S changes nothing in M ⊂ S.
    const double margin = std::exp2(std::floor(std::log2(scene.area.diagonal() / 16.0)));
    const core::Box3 clip{scene.area.min - core::Vec3::Constant(margin),
                          scene.area.max + core::Vec3::Constant(margin)};
    clip_ = clip;
    margin_ = margin;
    clip_box_ = box_nef(clip);
    auto add = [this](const std::vector<core::SceneObject>& objects) {
      for (const auto& o : objects) shape_.emplace(&o, shape_id(o.mesh));
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
      cam.image = image_plane(setting, scene.cameras.models.at(i));
      cameras_.push_back(std::move(cam));
    }
    step_free_.resize(cameras_.size());
    step_hidden_.resize(cameras_.size());
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
  /// for the cameras skipped because the model is already empty. `before_camera` (may be empty)
  /// is called before each camera's step that is not skipped, with the camera and the box its
  /// free region will be built within (none: the whole region), e.g. to adopt parts built ahead.
  StateModel model(const core::StateIndex& s, const std::function<void()>& camera_done = {},
                   const std::function<void(std::size_t, const std::optional<core::Box3>&)>&
                       before_camera = {}) {
    const auto objects = core::state_objects(scene_, s);
    enter_step(s.time_step);
    StateModel out;
    Nef m = obstacles_last_ ? area_ : step_area(s.time_step, objects);
    std::size_t c = 0;
    for (; c < cameras_.size() && !m.is_empty(); ++c) {
      // Once the model's box fills at most model_box_fraction_ of the clip box (by default half),
      // only the free region's part in that box is built and subtracted: the same set, and the
      // later booleans skip the static and step parts' facets far from the model (E3).
      const std::optional<core::Box3> box = model_box(m);
      if (before_camera) before_camera(c, box);
      const Nef free = free_region(c, s, objects, box);
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
  Nef fov(std::size_t c) const { return fov_of(c) * area_; }
  std::size_t camera_count() const { return cameras_.size(); }

  /// The parts of camera c for state s that do not depend on the model, moved out of a
  /// pipeline's caches (take_parts) to be moved into another's (adopt).
  struct CameraParts {
    std::size_t camera = 0;
    core::StateIndex state;
    std::optional<Nef> static_hidden, static_free, step_hidden, step_free, target_cones, free;
    /// The number of parts held.
    int count() const {
      return int(bool(static_hidden)) + bool(static_free) + bool(step_hidden) + bool(step_free) +
             bool(target_cones) + bool(free);
    }
  };

  /// Builds into the caches the parts of camera c for state s that do not depend on the model, as
  /// model() would build them (SPEC §3). `box`: a box that holds the model whenever camera c's step
  /// comes (none: unknown). Without one, the whole free region Free_c (state_free, with the static
  /// and step parts and the hidden parts it is built from), which model() uses while the model
  /// still fills the clip box. With one, only the hidden parts (hidden_cached) of the kinds whose
  /// sight may meet FOV ∩ box: state_free_within needs no others, since the model's box only
  /// shrinks (sight_may_meet). Parts that end up unused cost time, never correctness: model()
  /// builds whatever is missing. (On paper_basic with 12 cameras, and with a person of 3,200
  /// triangles, this left the worker less to do than building only the hidden parts, for less CPU
  /// time than building every camera's whole free region.)
  void prefill(std::size_t c, const core::StateIndex& s, const std::optional<core::Box3>& box) {
    const auto objects = core::state_objects(scene_, s);
    enter_step(s.time_step);
    if (!box) {
      whole_free_.insert_or_assign(unit_key(c, s), state_free(c, s, objects));
      return;
    }
    constexpr core::ObjectKind kinds[] = {core::ObjectKind::static_obstacle,
                                          core::ObjectKind::dynamic_obstacle,
                                          core::ObjectKind::target};
    // A camera inside an object sees nothing (state_free_within builds nothing).
    for (const auto kind : kinds)
      if (camera_inside(cameras_[c].view, of_kind(objects, kind))) return;
    const Nef region = fov_of(c) * box_nef(*box);
    if (region.is_empty()) return;
    std::vector<Point> corners;  // of the convex FOV ∩ box
    for (auto v = region.vertices_begin(); v != region.vertices_end(); ++v)
      corners.push_back(v->point());
    for (const auto kind : kinds) {
      // Without reuse_poses the targets' cones are built for each state when needed, not cached.
      if (kind == core::ObjectKind::target && !reuse_poses_) continue;
      if (sight_may_meet(cameras_[c].image, of_kind(objects, kind), corners))
        hidden_cached(c, s, objects, kind);
    }
  }

  /// Moves the parts of camera c for state s out of the caches.
  CameraParts take_parts(std::size_t c, const core::StateIndex& s) {
    const auto objects = core::state_objects(scene_, s);
    const std::size_t h = std::size_t(s.time_step);
    CameraParts out;
    out.camera = c;
    out.state = s;
    out.static_hidden = take(cameras_[c].static_hidden);
    out.static_free = take(cameras_[c].static_free);
    if (h < step_hidden_[c].size()) out.step_hidden = take(step_hidden_[c][h]);
    if (h < step_free_[c].size()) out.step_free = take(step_free_[c][h]);
    const auto it = target_cones_.find(target_key(c, objects));
    if (it != target_cones_.end()) {
      out.target_cones = std::move(it->second);
      target_cones_.erase(it);
    }
    const auto whole = whole_free_.find(unit_key(c, s));
    if (whole != whole_free_.end()) {
      out.free = std::move(whole->second);
      whole_free_.erase(whole);
    }
    return out;
  }

  /// Moves parts built by another pipeline (take_parts) into the caches, where they are missing;
  /// the parts' state must be of the time step the pipeline is in (model() or prefill).
  void adopt(CameraParts&& parts) {
    const std::size_t c = parts.camera;
    const core::StateIndex& s = parts.state;
    CAMPLACE_ASSERT(current_step_ == s.time_step);
    const std::size_t h = std::size_t(s.time_step);
    auto put = [](std::optional<Nef>& slot, std::optional<Nef>& part) {
      if (!slot && part) slot = std::move(part);
      part.reset();
    };
    put(cameras_[c].static_hidden, parts.static_hidden);
    put(cameras_[c].static_free, parts.static_free);
    for (auto* slots : {&step_hidden_, &step_free_})
      if ((*slots)[c].size() < scene_.time_steps.size())
        (*slots)[c].resize(scene_.time_steps.size());
    put(step_hidden_[c][h], parts.step_hidden);
    put(step_free_[c][h], parts.step_free);
    if (parts.target_cones) {
      target_cones_.try_emplace(target_key(c, core::state_objects(scene_, s)),
                                std::move(*parts.target_cones));
      parts.target_cones.reset();
    }
    if (parts.free) {
      whole_free_.try_emplace(unit_key(c, s), std::move(*parts.free));
      parts.free.reset();
    }
  }

 private:
  struct Camera {
    ViewPoint view;
    mutable std::optional<Nef> fov;  ///< pyramid ∩ clip box (fov_of)
    ImagePlane image;  ///< for the outlines of occupying objects and the shadows' patches
    std::optional<Nef> static_hidden;  ///< the static obstacles' shadows
    std::optional<Nef> static_free;
  };

  /// The object's exact solid, built on first use (a pipeline that serves one state builds only
  /// that state's).
  const Solid& solid(const core::SceneObject& o) const {
    return solids_.try_emplace(&o, o.mesh).first->second;
  }

  /// Camera c's pyramid ∩ clip box, built on first use.
  const Nef& fov_of(std::size_t c) const {
    const Camera& cam = cameras_[c];
    if (!cam.fov)
      cam.fov.emplace(fov_nef(cam.view, config_[c], scene_.cameras.models.at(c)) * clip_box_);
    return *cam.fov;
  }

  /// The part in `slot`, which is left empty.
  static std::optional<Nef> take(std::optional<Nef>& slot) {
    std::optional<Nef> out = std::move(slot);
    slot.reset();
    return out;
  }

  /// The key of camera c's free region for state s in whole_free_.
  static std::array<int, 3> unit_key(std::size_t c, const core::StateIndex& s) {
    return {int(c), s.time_step, s.event};
  }

  /// The key of the targets' cones of camera c in target_cones_: the camera, the targets' shapes
  /// in order, a separator, the occluders' shapes.
  std::vector<int> target_key(std::size_t c, const std::vector<core::StateObject>& objects) const {
    std::vector<int> key{int(c)};
    for (const auto& o : objects)
      if (o.kind == core::ObjectKind::target) key.push_back(shape_.at(o.object));
    key.push_back(-1);
    for (const auto& o : objects)
      if (o.role == core::ObjectRole::occluding) key.push_back(shape_.at(o.object));
    return key;
  }

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

  /// What camera c cannot see past among the state's objects of one kind (hidden), cached: the
  /// static obstacles' per camera, the dynamic obstacles' per camera and step, the targets' per
  /// camera and pose (target_cones_; built for every state without reuse_poses_).
  Nef hidden_cached(std::size_t c, const core::StateIndex& s,
                    const std::vector<core::StateObject>& objects, core::ObjectKind kind) {
    if (kind == core::ObjectKind::static_obstacle) {
      // Static obstacles always occlude (SPEC §3), so this part depends on no time step.
      CAMPLACE_ASSERT(core::role_of(core::ObjectKind::static_obstacle, scene_.dynamic_mode) ==
                      core::ObjectRole::occluding);
      auto& slot = cameras_[c].static_hidden;
      if (!slot) slot = hidden(c, objects, kind);
      return *slot;
    }
    if (kind == core::ObjectKind::dynamic_obstacle) {
      auto& slot = step_hidden_[c];
      if (slot.size() < scene_.time_steps.size()) slot.resize(scene_.time_steps.size());
      if (!slot[s.time_step]) slot[s.time_step] = hidden(c, objects, kind);
      return *slot[s.time_step];
    }
    // The targets' cones depend only on the camera, the targets' meshes and the occluders' meshes
    // (hidden; targets never occlude), so states of the same pose share them (target_key).
    if (!reuse_poses_) return hidden(c, objects, kind);
    const std::vector<int> key = target_key(c, objects);
    auto it = target_cones_.find(key);
    if (it == target_cones_.end()) it = target_cones_.emplace(key, hidden(c, objects, kind)).first;
    return it->second;
  }

  /// `free` minus what camera c cannot see past among the state's objects of one kind
  /// (hidden_cached). Empty when c lies inside one of them.
  Nef remove_hidden(std::size_t c, Nef free, const core::StateIndex& s,
                    const std::vector<core::StateObject>& objects, core::ObjectKind kind) {
    if (free.is_empty()) return free;
    if (camera_inside(cameras_[c].view, of_kind(objects, kind))) return Nef();
    const Nef removed = hidden_cached(c, s, objects, kind);
    if (!removed.is_empty()) free -= removed;
    return free;
  }

  /// FOV ∩ clip box minus the static obstacles' shadows (cached per camera).
  const Nef& static_free(std::size_t c, const core::StateIndex& s,
                         const std::vector<core::StateObject>& objects) {
    Camera& cam = cameras_[c];
    if (!cam.static_free)
      cam.static_free.emplace(
          remove_hidden(c, fov_of(c), s, objects, core::ObjectKind::static_obstacle));
    return *cam.static_free;
  }

  /// static_free minus the dynamic obstacles' shadows or cones (cached per camera and step).
  const Nef& step_free(std::size_t c, const core::StateIndex& s,
                       const std::vector<core::StateObject>& objects) {
    auto& slot = step_free_[c];
    if (slot.size() < scene_.time_steps.size()) slot.resize(scene_.time_steps.size());
    if (!slot[s.time_step])
      slot[s.time_step] = remove_hidden(c, static_free(c, s, objects), s, objects,
                                        core::ObjectKind::dynamic_obstacle);
    return *slot[s.time_step];
  }

  /// Camera c's free region for state s within `box` (state_free_within), or whole (state_free,
  /// taken from whole_free_ when it was built ahead: prefill) when there is none.
  Nef free_region(std::size_t c, const core::StateIndex& s,
                  const std::vector<core::StateObject>& objects,
                  const std::optional<core::Box3>& box) {
    std::optional<Nef> ahead;
    const auto it = whole_free_.find(unit_key(c, s));
    if (it != whole_free_.end()) {
      ahead = std::move(it->second);
      whole_free_.erase(it);
    }
    if (box) return state_free_within(c, s, objects, *box);
    return ahead ? std::move(*ahead) : state_free(c, s, objects);
  }

  /// Free_c of SPEC §3 for one state: step_free minus the targets' cones.
  Nef state_free(std::size_t c, const core::StateIndex& s,
                 const std::vector<core::StateObject>& objects) {
    return remove_hidden(c, step_free(c, s, objects), s, objects, core::ObjectKind::target);
  }

  /// A box around the model `m` (bounded, in S) with short coordinates: multiples of margin_ / 16,
  /// at least one such step beyond the intervals of its vertices' coordinates, cut to the clip
  /// box; none when that box fills more than model_box_fraction_ of the clip box (then clipping
  /// saves little).
  std::optional<core::Box3> model_box(const Nef& m) const {
    core::Vec3 lo = core::Vec3::Constant(HUGE_VAL), hi = core::Vec3::Constant(-HUGE_VAL);
    for (auto v = m.vertices_begin(); v != m.vertices_end(); ++v) {
      const Point& p = v->point();
      const std::pair<double, double> iv[3] = {CGAL::to_interval(p.x()), CGAL::to_interval(p.y()),
                                               CGAL::to_interval(p.z())};
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], iv[k].first);
        hi[k] = std::max(hi[k], iv[k].second);
      }
    }
    if (!(lo.x() <= hi.x())) return std::nullopt;
    // A tight box leaves out more of the other objects' shadows and cones (sight_may_meet);
    // multiples of a power of two keep its coordinates short.
    const double step = margin_ / 16.0;
    core::Box3 box;
    for (int k = 0; k < 3; ++k) {
      box.min[k] = std::max(clip_.min[k], std::floor(lo[k] / step) * step - step);
      box.max[k] = std::min(clip_.max[k], std::ceil(hi[k] / step) * step + step);
    }
    const core::Vec3 size = box.max - box.min, clip_size = clip_.max - clip_.min;
    if (size.prod() > model_box_fraction_ * clip_size.prod()) return std::nullopt;
    return box;
  }

  /// Free_c ∩ box for one state, `box` holding the model: FOV ∩ box minus the static obstacles'
  /// shadows, the dynamic obstacles' shadows or cones and the targets' cones, each kind left out
  /// when no ray from c through its objects meets FOV ∩ box (sight_may_meet). The same set as
  /// state_free ∩ box (docs/design/exact-model.md E3).
  Nef state_free_within(std::size_t c, const core::StateIndex& s,
                        const std::vector<core::StateObject>& objects, const core::Box3& box) {
    constexpr core::ObjectKind kinds[] = {core::ObjectKind::static_obstacle,
                                          core::ObjectKind::dynamic_obstacle,
                                          core::ObjectKind::target};
    for (const auto kind : kinds)
      if (camera_inside(cameras_[c].view, of_kind(objects, kind))) return Nef();
    Nef free = fov_of(c) * box_nef(box);
    if (free.is_empty()) return free;
    std::vector<Point> corners;  // of the convex FOV ∩ box
    for (auto v = free.vertices_begin(); v != free.vertices_end(); ++v)
      corners.push_back(v->point());
    for (const auto kind : kinds) {
      if (!sight_may_meet(cameras_[c].image, of_kind(objects, kind), corners)) continue;
      const Nef removed = hidden_cached(c, s, objects, kind);
      if (!removed.is_empty()) free -= removed;
      if (free.is_empty()) break;
    }
    return free;
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

  /// Moves the pipeline to time step h: the caches of the step it was in are dropped. The worker
  /// threads take whole time steps (or slices of one), so a pipeline holds one step's at a time,
  /// not every step's (at worst a step is visited again and its part recomputed: the same sets).
  void enter_step(int h) {
    if (current_step_ >= 0 && current_step_ != h) release_step(current_step_);
    current_step_ = h;
  }

  /// Drops the caches of time step h.
  void release_step(int h) {
    for (auto& slots : {&step_free_, &step_hidden_})
      for (auto& slot : *slots)
        if (std::size_t(h) < slot.size()) slot[h].reset();
    step_obstacles_[h].reset();
    step_area_[h].reset();
    for (auto it = whole_free_.begin(); it != whole_free_.end();)
      it = (*it).first[1] == h ? whole_free_.erase(it) : std::next(it);
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
  core::CameraConfig config_;
  bool face_cones_ = false;
  bool face_shadows_ = false;
  bool reuse_poses_ = true;
  bool obstacles_last_ = true;
  double model_box_fraction_ = 0.5;
  std::unordered_map<const core::SceneObject*, int> shape_;
  std::unordered_map<std::size_t, std::vector<std::pair<const core::TriangleMesh*, int>>>
      shapes_by_hash_;
  int next_shape_ = 0;
  std::map<std::vector<int>, Nef> target_cones_;
  std::map<std::array<int, 3>, Nef> whole_free_;  ///< state_free built ahead (prefill), by unit_key
  Nef area_;
  Nef clip_box_;         ///< the box clip_
  core::Box3 clip_;      ///< S enlarged by margin_ (m)
  double margin_ = 0.0;  ///< a power of two (m)
  mutable std::unordered_map<const core::SceneObject*, Solid> solids_;
  std::vector<Camera> cameras_;
  std::vector<std::vector<std::optional<Nef>>> step_free_, step_hidden_;
  std::vector<std::optional<Nef>> step_obstacles_, step_area_;
  int current_step_ = -1;
};

}  // namespace camplace::exact::internal
