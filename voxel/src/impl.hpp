#pragma once
// The voxel evaluator's private state (manifold's impl.h pattern): one Impl, its stages in
// separate files — set-up (setup.cpp), labelling (labelling.cpp), components (components.cpp),
// distances (distance.cpp) — and the public class in evaluator.cpp. Hot path: plain arrays and
// Eigen, no CGAL.
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/sensor_model.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "solid_distance.hpp"

namespace camplace::voxel {

namespace detail {

using Clock = std::chrono::steady_clock;
inline double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// Runs body(0..count−1) on up to `threads` threads (the caller's among them), items taken in
/// order of index by whichever thread is free.
template <class Body>
void parallel_for(int count, int threads, const Body& body) {
  threads = std::min(threads, count);
  if (threads <= 1) {
    for (int i = 0; i < count; ++i) body(i);
    return;
  }
  std::atomic<int> next{0};
  auto work = [&] {
    for (int i = next++; i < count; i = next++) body(i);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
}

/// States are handled in chunks of at most 64, one bit each in a StateMask.
using StateMask = std::uint64_t;
constexpr int kChunk = 64;

/// One object of the scene with its fixed role (SPEC §3: what a first hit on it means).
struct ObjectInfo {
  const core::TriangleMesh* mesh = nullptr;
  bool occupying = false;  ///< core::ObjectRole::occupying
  core::Vec3 center = core::Vec3::Zero();
  double radius = 0.0;  ///< bounding sphere
  int first_triangle = 0;
  int triangle_count = 0;
  bool outward = false;  ///< signed volume > 0: the mesh is oriented outward (back-face culling)
};

/// Per camera and triangle: the infinite cone from the camera over the triangle, as its three
/// edge rays (vertex − camera) and the inward unit normals of its three planes, and the
/// triangle's nearest distance.
struct TriangleCone {
  core::Vec3 edge[3];
  core::Vec3 normal[3];
  core::Vec3 abs_normal[3];
  /// The separating-axis candidates beyond the 3 planes (3 box normals, then the 9 products of
  /// cone edges and box axes) that can separate: the cone lies on one side of them (`side`
  /// +1: axis·x ≥ 0 on the cone, −1: ≤ 0); `radius` = Σ|axis_i|·h_i of the voxel box.
  struct Axis {
    core::Vec3 axis;
    double radius;
    double side;
    double norm;  ///< |axis|
  };
  std::array<Axis, 12> axes;
  int axis_count = 0;
  double near_distance = 0.0;
  bool flat = false;  ///< camera in the triangle's plane: the cone has no volume
  /// Camera clearly behind the triangle's plane, outside its (outward, closed) object and
  /// clear of its surface: conservative mode skips the triangle (see labelling.cpp).
  bool back = false;
  bool touch = false;  ///< its object's back faces are culled for this camera
};

/// A triangle's projection as three lines a x + b y + c ≥ 0 (inside, padded).
struct EdgeLines {
  std::array<std::array<double, 3>, 3> line{};
  bool valid = false;
};

/// Everything about one camera that one evaluation needs and that does not depend on the
/// voxel: the FOV test, the triangles sorted into bins of the image plane (a triangle is a
/// candidate for a voxel only when their projections' bounding rectangles share a bin), the
/// triangle cones, and which objects hold the camera. A few kB, no per-voxel arrays.
struct CameraSetup {
  core::CameraSetting setting;
  std::optional<core::Fov> fov;
  core::Vec3 c = core::Vec3::Zero();
  core::Vec3 axis = core::Vec3::UnitX(), ex = core::Vec3::UnitY(), ey = core::Vec3::UnitZ();
  core::Vec3 abs_ex = core::Vec3::Zero(), abs_ey = core::Vec3::Zero(),
             abs_axis = core::Vec3::Zero();
  double box_x = 0.0, box_y = 0.0, box_z = 0.0;  ///< a voxel box's half extents in this frame
  bool pyramid = false;
  std::vector<core::Vec3> normals;  ///< pyramid side normals (core::Fov's)
  std::optional<double> range;
  double cos_half = 1.0, sin_half = 0.0;
  double row_cos_sq = 0.0;     ///< cos² of the half angle widened by 1e-6 (row_interval); 0: none
  int bins = 1;                ///< bins per image axis
  double image_half = 1.0;     ///< the bins cover [−image_half, image_half]² of (X/Z, Y/Z)
  double bin_scale = 1.0;      ///< bins per unit of image coordinate
  std::vector<int> bin_start;  ///< bins² + 1 offsets into bin_items
  std::vector<int> bin_items;  ///< triangle indices, ascending within a bin
  /// Conservative mode: a second, finer set of bins whose rectangles are widened by `widen`.
  int wide_bins = 1;
  double wide_scale = 1.0, widen = 0.0;
  std::vector<int> wide_start;  ///< wide_bins² + 1 offsets into wide_items
  std::vector<int> wide_items;
  std::vector<int> everywhere;  ///< triangles not wholly in front of the camera: in every bin
  /// Per triangle: its projection's bounding rectangle (x0, x1, y0, y1), padded; infinite for
  /// the triangles in `everywhere`.
  std::vector<std::array<double, 4>> rect;
  std::vector<EdgeLines> lines;  ///< per triangle, when projectable and not degenerate
  std::vector<TriangleCone> triangles;
  std::vector<std::uint8_t> inside_object;  ///< camera inside object o (blind in its states)
};

struct StateInfo {
  int time_step = 0, event = 0;
  double weight = 0.0;
  double d_true = 0.0;
  std::vector<int> objects;  ///< indices into Impl::objects
};

/// Per-call working memory of the labeller (evaluate() is const and runs on several threads).
struct Scratch {
  std::vector<std::uint32_t> stamp;  ///< per triangle: last voxel visit that tested it
  std::uint32_t visit = 0;
  struct Hit {
    double t;
    int triangle;
  };
  std::vector<Hit> hits;
};

/// The verdict of one camera on one voxel for a set of states: the states where the voxel is
/// occupied, and those where it is otherwise not free (undetectable). Occupied wins.
struct Verdict {
  StateMask occupied = 0;
  StateMask blocked = 0;
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
  /// Voxel box bounds and centres per axis, computed as Grid::voxel_box does (same bits).
  std::array<std::vector<double>, 3> box_min, box_max, box_center;
  std::vector<detail::ObjectInfo> objects;
  std::vector<std::array<core::Vec3, 3>> triangles;  ///< all objects' triangles, world frame
  std::vector<int> triangle_object;                  ///< object of each triangle
  std::vector<detail::StateInfo> states;
  /// Per chunk of 64 states: the states (bits) each object belongs to, and each time step's.
  std::vector<std::vector<detail::StateMask>> chunk_object_states;
  std::vector<std::vector<detail::StateMask>> chunk_step_states;
  std::vector<std::vector<std::uint8_t>> removed_by_step;  ///< obstacle interiors per step
  /// Per step and voxel: a lower bound of d(C_h, voxel)² (the centre's distance less the
  /// voxel's radius; in center mode the value itself), and in conservative mode the value,
  /// computed on first use by critical_sq (NaN until then; evaluate() is const and runs on
  /// several threads: racing threads store the same double).
  std::vector<std::vector<double>> critical_lb_by_step;
  std::vector<std::unique_ptr<std::atomic<double>[]>> critical_by_step;
  std::vector<std::vector<detail::IndexedSolid>> critical_solids_by_step;
  double err_lower_bound = 0.0;  ///< conservative mode only

  // Set-up (setup.cpp): everything that does not depend on the cameras.
  void build();
  int add_object(const core::SceneObject& object, core::ObjectRole role);
  /// The conservative lower bound of Err (err_lower_bound(); the proof is in setup.cpp).
  double lower_bound() const;
  /// How deep (m) an occupying object must reach into a voxel's box for lower_bound() to count
  /// the voxel as always in M: 1e-9 of S's diagonal plus its largest |coordinate|.
  double contact_depth() const;
  /// Voxels whose box, shrunk by contact_depth(), meets the closed solid `mesh`, ascending.
  std::vector<int> voxels_reached(const core::TriangleMesh& mesh) const;
  std::vector<std::uint8_t> obstacle_interiors(const core::TimeStep& step) const;
  /// The lower bounds of critical_lb_by_step for one step.
  std::vector<double> critical_distances(const std::vector<detail::IndexedSolid>& solids) const;
  /// d(C_h, voxel v)² as core::box_solid_sq_distance (conservative) or
  /// core::point_solid_sq_distance (center) gives it, min over C_h.
  double critical_sq(int time_step, int v) const;

  // Labelling (labelling.cpp): SPEC §3 per camera, voxel and state.
  detail::CameraSetup camera_setup(const core::CameraSetting& camera) const;
  /// Unfiltered models of all states (1 = no camera sees the voxel free, minus obstacle
  /// interiors), for voxel slices k ∈ [k_begin, k_end); `models[s]` holds grid.count() bytes.
  void raw_models(const std::vector<detail::CameraSetup>& cameras, int k_begin, int k_end,
                  std::vector<std::vector<std::uint8_t>>& models) const;
  /// The unfiltered models of all states for a configuration (checked against the scene), into
  /// `models` (resized; its memory is reused from call to call).
  void all_raw_models(const core::CameraConfig& config,
                      std::vector<std::vector<std::uint8_t>>& models) const;
  /// κ of every voxel for one camera in one state.
  std::vector<Label> labels(const detail::CameraSetup& camera, int state) const;

  // Distance (distance.cpp): d(C_h, M) and the model's volume for one state.
  struct ModelDistance {
    double d_model = 0.0;  ///< m; core::empty_model_distance when M is empty
    double volume = 0.0;   ///< m³
  };
  ModelDistance model_distance(const std::vector<std::uint8_t>& model, int time_step) const;

 private:
  void row_interval(const detail::CameraSetup& cam, int j, int k, int& lo, int& hi, int& in_lo,
                    int& in_hi) const;
  bool in_fov(const detail::CameraSetup& cam, int i, int j, int k, const core::Vec3& w,
              double d) const;
  void judge(const detail::CameraSetup& cam, const core::Vec3& w, double d,
             detail::StateMask interest, const detail::StateMask* object_states,
             detail::Scratch& scratch, detail::Verdict& out, bool free_only) const;
  enum class Cone { meet, miss, near_miss };
  Cone cone_test(const detail::TriangleCone& tc, const core::Vec3& w) const;
};

}  // namespace camplace::voxel
