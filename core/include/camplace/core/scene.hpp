#pragma once
/// The scene of SPEC §2: surveillance area, cameras and their domain, obstacles, time steps and
/// events. Loaded and validated from one JSON file.
#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "camplace/core/geometry.hpp"

namespace camplace::core {

enum class FovShape { cone, pyramid, frustum };
enum class DynamicMode { masked, modelled };

/// Closed interval [lo, hi].
struct Interval {
  double lo = 0.0;
  double hi = 0.0;
  bool fixed() const { return lo == hi; }
};

/// A mounting surface (`cameras.mounts`): the rectangle corner + s·u + t·v, (s, t) ∈ [0, 1]²,
/// with non-parallel edges u and v. Its normal n = (u × v)/|u × v| points into the half-space
/// the camera looks into. Viewing directions are given relative to the frame (n, e1, e2) with
/// e1 = u/|u| and e2 = n × e1: relative yaw ψ' (about e2, toward e1) and relative pitch θ'
/// (toward e2) give d = cos θ' cos ψ' n + cos θ' sin ψ' e1 + sin θ' e2; ψ' = θ' = 0 looks along n.
struct Mount {
  std::string name;
  std::string entry;  ///< JSON pointer of the mount in the scene file
  Vec3 corner = Vec3::Zero();
  Vec3 u = Vec3::UnitX();
  Vec3 v = Vec3::UnitY();
  Interval yaw{-kPi / 2, kPi / 2};    ///< relative yaw ψ' (radians), within [−π/2, π/2]
  Interval pitch{-kPi / 2, kPi / 2};  ///< relative pitch θ' (radians), within [−π/2, π/2]
  Interval roll{0.0, 0.0};            ///< roll (radians, as CameraDomain::roll)
  /// The unit normal n = (u × v)/|u × v|.
  Vec3 normal() const;
  /// The unit vectors e1 = u/|u| and e2 = n × e1 of the mount's frame.
  Vec3 e1() const;
  Vec3 e2() const;
  /// The point corner + s·u + t·v.
  Vec3 point(double s, double t) const;
  /// The (s, t) of the point of the rectangle's plane nearest to p (least squares; unclamped).
  std::pair<double, double> coordinates(const Vec3& p) const;
  /// The world unit direction of relative yaw ψ' and pitch θ' (radians).
  Vec3 direction(double rel_yaw, double rel_pitch) const;
  /// The relative (ψ', θ') of a world unit direction d (ψ' = atan2(d·e1, d·n), θ' = asin(d·e2)).
  std::pair<double, double> relative_angles(const Vec3& d) const;
};

/// Bounds on one camera's setting: position in metres (world frame), yaw, pitch and roll in
/// radians. Roll is fixed at 0 unless the scene frees it (`roll_deg`). A camera on a mount has
/// its mount here; x, y, z then hold the rectangle's bounding box and yaw, pitch the full
/// ranges (the mount's own ranges apply).
struct CameraDomain {
  Interval x, y, z;
  Interval yaw{-kPi, kPi};
  Interval pitch{-kPi / 2, kPi / 2};
  Interval roll{0.0, 0.0};
  std::optional<Mount> mount;
  /// The pitch range is the "ceiling" preset's [−90°, 0] (no `pitch_deg` of its own). Run files
  /// of formats 1–3 were made when that preset let cameras look up (pitch up to +90°): resuming
  /// such a run with such a domain is refused (optimize::settings_changes).
  bool ceiling_pitch = false;
};

/// A keep-out box (`cameras.keep_out`): no camera may be placed in its interior. Positions on
/// its faces are allowed; a position counts as inside when it lies more than kKeepOutSlack
/// inside every face.
struct KeepOut {
  std::string name;   ///< the box's "name", or its JSON pointer
  std::string entry;  ///< JSON pointer in the scene file
  Box3 box;
  /// True when p lies in the box's interior (by more than kKeepOutSlack on every axis).
  bool contains(const Vec3& p) const;
};

/// Tolerance (m) of the keep-out test: rounding of repaired and re-read positions.
constexpr double kKeepOutSlack = 1e-9;

/// One camera model (SPEC §1): the shape of its field of view and its depth range.
struct CameraModel {
  std::string name;  ///< the model's name in the scene ("" for the single-model form)
  FovShape fov = FovShape::cone;
  double half_angle = 0.0;      ///< cone, pyramid: radians, in (0, π/2)
  int sides = 16;               ///< pyramid: k sides; cone: k of the inscribed pyramid (exact)
  double horizontal = 0.0;      ///< frustum: full horizontal opening angle, radians in (0, π)
  double vertical = 0.0;        ///< frustum: full vertical opening angle, radians in (0, π)
  double near = 0.0;            ///< axial near plane in metres, 0 = none
  std::optional<double> range;  ///< axial far plane in metres, none = unlimited
  /// Price of one camera of this model (`cost`, in any one unit: the scene's models share it),
  /// none = not given. Only `camplace plan` uses it (Err against the cameras' total cost).
  std::optional<double> cost;
  /// Half angle (radians, < π/2) of the narrowest circular cone about the axis that holds the
  /// FOV: α for a cone or pyramid, atan(√(tan²(H/2) + tan²(V/2))) for a frustum.
  double bounding_half_angle() const;
  /// False for a cone, which roll leaves unchanged.
  bool has_roll() const { return fov != FovShape::cone; }
};

/// Camera block of the scene: count n, each camera's model, its domain.
struct CameraSpec {
  int count = 0;
  std::vector<CameraModel> models;    ///< one per camera (a shared model copied n times)
  std::vector<CameraDomain> domains;  ///< one per camera (shared domain copied n times)
  std::vector<Mount> mounts;          ///< the scene's named mounts (`cameras.mounts`)
  std::vector<KeepOut> keep_out;      ///< boxes no camera may be placed in
  /// Sets the count to n, keeping the first n cameras; new cameras copy the last one's model
  /// and domain (n ≥ 1, at least one camera before).
  void resize(int n);
  /// True when every camera has the same model (the single-model form).
  bool one_model() const;
};

/// Whether some camera's domain has the "ceiling" preset's pitch range (CameraDomain).
bool has_ceiling_pitch(const CameraSpec& cameras);

/// The model the exact pipeline uses for `model` (SPEC §1): a cone becomes its inscribed
/// regular `sides`-sided pyramid; pyramids and frusta stay as they are.
CameraModel exact_model(const CameraModel& model);
/// Every camera's model replaced by its exact_model (compare like with like, SPEC §6).
void use_exact_models(CameraSpec& cameras);
/// The FOV both pipelines use when they are compared, for reports: "the 16-sided pyramid
/// inscribed in each camera's 30° cone" for one cone model, else each model's exact FOV
/// ("model \"rgb\" (2 cameras): a 90° × 59° frustum", joined by "; ").
std::string fov_description(const CameraSpec& cameras);

/// One rigid object: a closed, outward-oriented triangle mesh and where it came from.
struct SceneObject {
  std::string name;   ///< the object's "name", or its JSON pointer
  std::string entry;  ///< JSON pointer of the object in the scene file
  TriangleMesh mesh;
  Box3 bounds;
};

/// One appearance a of the unmodelled collective: its weight ω and its target objects.
struct Event {
  double weight = 0.0;
  std::vector<SceneObject> targets;
};

/// One time step h: the robot's links, the critical objects and the events.
struct TimeStep {
  double t = 0.0;
  std::vector<SceneObject> dynamic_obstacles;
  std::vector<SceneObject> critical;  ///< defaults to the dynamic obstacles (SPEC §2)
  std::vector<Event> events;
};

/// Plausibility filter thresholds (SPEC §4); 0 disables each.
struct Plausibility {
  double min_volume = 0.0;  ///< m³
  double min_height = 0.0;  ///< m (z-extent)
  /// True when a model component of this volume (m³) and z-extent (m) could be human and stays
  /// in M (SPEC §4: removed when volume < min_volume or z-extent < min_height). T is double or
  /// an exact number type (the thresholds convert exactly).
  template <class T>
  bool keeps(const T& volume, const T& height) const {
    return !(volume < T(min_volume)) && !(height < T(min_height));
  }
};

/// A mesh the loader repaired instead of refusing it (an object's or the scene's "repair"):
/// which object, what was wrong with it and what it became. Reported by every command, since
/// an enclosing repair is conservative for targets and critical objects (distances can only
/// shrink) but changes what an obstacle occludes and where a person may be.
struct MeshRepair {
  std::string object;  ///< the object's name
  std::string entry;   ///< JSON pointer (and URDF element) of the object
  std::string role;    ///< "static obstacle", "dynamic obstacle", "critical object" or "target"
  std::string method;  ///< "wrap" or "hull"
  std::string defect;  ///< why the mesh failed the checks ("" when repaired although valid)
  int triangles_before = 0;
  int triangles_after = 0;
  double offset = 0.0;  ///< wrap: the offset (m) by which the wrap may stand off the input
};

struct Scene {
  std::string file;  ///< path the scene was loaded from
  Box3 area;         ///< surveillance area S
  std::array<int, 3> voxels{16, 12, 12};
  CameraSpec cameras;
  std::vector<SceneObject> static_obstacles;
  std::vector<TimeStep> time_steps;
  DynamicMode dynamic_mode = DynamicMode::masked;
  Plausibility plausibility;
  /// Mesh files the scene references, as opened (in order of first use; for provenance); also
  /// the URDF and trajectory files of its robots.
  std::vector<std::string> mesh_files;
  /// Every mesh repaired while loading, in the order loaded (an object repaired once and
  /// reused at several time steps, e.g. a robot link, is listed once).
  std::vector<MeshRepair> repairs;
};

/// One line per mesh repaired while loading (Scene::repairs, in order), for every command to
/// print: "FILE: ENTRY: mesh \"NAME\" repaired by wrap (offset 0.005 m, 412 → 1,980 triangles):
/// it failed the checks (mesh intersects itself); ..." and what the repair means for the
/// object's role (conservative for targets and critical objects; for obstacles it changes
/// what is occluded and what may hold a person).
std::vector<std::string> repair_warnings(const Scene& scene);

/// One state (time step h, event l) of the error functional, as indices into the scene.
struct StateIndex {
  int time_step = 0;
  int event = 0;
};

/// All states in order h = 0..H-1, l = 0..L_h-1.
std::vector<StateIndex> states(const Scene& scene);

/// The placement domain of a preset (SPEC §2) over the area S: "room" (all of S, yaw and pitch
/// unrestricted), "ceiling" (z fixed at S's top, pitch in [−90°, 0]: looking down or level) or
/// "upper_fourth" (the top quarter of S's height, yaw and pitch unrestricted: a camera there may
/// have parts of S above it; docs/scene-format.md). std::nullopt for any other name.
std::optional<CameraDomain> domain_preset(const Box3& area, const std::string& name);

/// The point of `domain` (its box, or its mount's rectangle) nearest to p (after clamping p
/// into the domain; for a mount, after projecting it onto the rectangle) that lies in no
/// keep-out box: p itself when it is free. std::nullopt when the keep-out boxes cover the whole
/// domain. Exact up to rounding: the free part of the domain is closed, and its point nearest
/// to p lies on an intersection of at most 3 (mount: 2) of the planes bounding the boxes and
/// the domain, all of which are tried.
std::optional<Vec3> keep_out_repair(const CameraDomain& domain,
                                    const std::vector<KeepOut>& keep_out, const Vec3& p);

/// Loads and validates a scene file (SPEC §2). Throws InputError naming the file, the entry
/// (JSON pointer) and the reason for every rejection the SPEC lists.
Scene load_scene(const std::string& path);

/// Largest |coordinate| (metres) of S's corners and of camera positions: far beyond any work
/// cell, small enough that squared distances and exact constructions stay finite.
constexpr double kMaxCoordinate = 1e6;

/// Largest Σ ω · diag(S)² (m²) a scene may have, summed over all events' weights ω. Every
/// state's |d_true − d_model| is at most S's diagonal (SPEC §4), so this bounds Err for every
/// configuration in both pipelines; at 1e150 m², Err, sums of up to 1e150 Err values and Err²
/// all stay finite doubles (a weight of 1e308 would make Err infinite).
constexpr double kMaxErr = 1e150;

/// Largest voxel grid camplace accepts (per-voxel data is kept per camera), and the largest
/// count along one axis.
constexpr long long kMaxVoxels = 1LL << 25;
constexpr int kMaxVoxelsPerAxis = 4096;

/// Why a voxel grid of n[0]·n[1]·n[2] voxels is not accepted, or "" when it is.
std::string resolution_problem(const std::array<int, 3>& n);

/// Parses a command-line value "NXxNYxNZ" (e.g. "16x12x12"); throws InputError naming the
/// option `what` on bad input or a grid resolution_problem() refuses.
std::array<int, 3> parse_resolution(const std::string& text, const std::string& what);

}  // namespace camplace::core
