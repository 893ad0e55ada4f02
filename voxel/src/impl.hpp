#pragma once
// The voxel evaluator's private state: the tables of each stage (SceneTables, CriticalTables,
// RefinementTables), the per-camera tables (CameraSetup) and the working memory of one call
// (Scratch, RefineContext), with the stages' functions in one file each — set-up (setup.cpp,
// refine_setup.cpp), labelling (camera_setup.cpp, fov.cpp, judge.cpp, labelling.cpp, refine.cpp
// for cells), components (components.cpp, cells.hpp), distances (distance.cpp), the lower bound
// (lower_bound.cpp) — and the public class in evaluator.cpp. Hot path: plain arrays and Eigen,
// no CGAL.
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/sensor_model.hpp"
#include "camplace/voxel/components.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "cells.hpp"
#include "rows.hpp"
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

/// A ball (world frame, m) holding a triangle or a cluster of triangles.
struct Ball {
  core::Vec3 center = core::Vec3::Zero();
  double radius = 0.0;
};

/// A lower bound of the distance from c (m) of the triangles in `ball`, as
/// core::point_triangle_sq_distance gives it (its root): the ball's distance less a margin far
/// above the rounding of either.
inline double nearest_in_ball(const Ball& ball, const core::Vec3& c) {
  const double to_center = (ball.center - c).norm();
  const double margin = 1e-9 * (to_center + ball.radius + c.norm() + ball.center.norm());
  return to_center - ball.radius - margin;
}

/// Whether triangle `tri` is a back face for a camera at c: the camera behind its plane, its
/// tilt det / scale > 0 with det = (a − c)·((b − c) × (e − c)) and scale the product of the
/// corners' distances, not flat (|det| > 1e-12 scale); the very arithmetic of camera set-up's
/// tilts (camera_setup.cpp), so both find the same back faces. A culled object's back faces
/// have no slots; judge_conservative() tests them on a near miss of a front face.
inline bool back_face(const std::array<core::Vec3, 3>& tri, const core::Vec3& c) {
  const core::Vec3 a = tri[0] - c, b = tri[1] - c, e = tri[2] - c;
  const double det = a.dot(b.cross(e));
  const double scale = a.norm() * b.norm() * e.norm();
  const bool flat = !(std::abs(det) > 1e-12 * scale);
  return !flat && det / scale > 0;
}

/// A cluster of an object's triangles near each other (set-up, cluster_triangles): its range of
/// ObjectInfo::cluster_order and a ball holding every one of its vertices.
struct TriangleCluster {
  int begin = 0, end = 0;
  Ball ball;
  /// The triangles' unit normals (of cross = (b − a) × (e − a)) lie within the cone about
  /// normal_axis whose half angle has cosine normal_cos (≤ 0: no such cone); min_cross: the
  /// least |cross|.
  core::Vec3 normal_axis = core::Vec3::Zero();
  double normal_cos = -1.0;
  double min_cross = 0.0;
};

/// A node of the tree over an object's clusters (ObjectInfo::nodes, pre-order): the bounds of
/// all its triangles (as a cluster's: ball, normal cone, least |cross|; `bounds.begin, end` their
/// range of cluster_order), its clusters cluster_begin .. cluster_end − 1 (one: a leaf, whose
/// bounds are its cluster's), and the index of the node after its subtree (its first child, if
/// any, is the next node). Camera set-up rules out whole subtrees: behind the camera's side of
/// every plane (back faces), or facing it and projecting outside the FOV (L10).
struct ClusterNode {
  TriangleCluster bounds;
  int cluster_begin = 0, cluster_end = 0;
  int next = 0;
};

/// One object of the scene with its fixed role (SPEC §3: what a first hit on it means).
struct ObjectInfo {
  const core::TriangleMesh* mesh = nullptr;
  bool occupying = false;  ///< core::ObjectRole::occupying
  core::Vec3 center = core::Vec3::Zero();
  double radius = 0.0;  ///< bounding sphere
  int first_triangle = 0;
  int triangle_count = 0;
  bool outward = false;  ///< signed volume > 0: the mesh is oriented outward (back-face culling)
  /// The object's triangles (indices into mesh->triangles) cluster by cluster, and the clusters:
  /// each camera numbers its slots in this order and bins them per cluster (camera_setup).
  std::vector<int> cluster_order;
  /// The corners of those triangles in that order (the scene's numbers): a cluster's slots are
  /// projected from one block of memory (project_group), not from triangles spread over the mesh.
  std::vector<std::array<core::Vec3, 3>> cluster_corners;
  std::vector<TriangleCluster> clusters;
  std::vector<ClusterNode> nodes;  ///< the tree over the clusters, pre-order, root first
  /// The first object with the same role and the same triangles (vertex indices) whose vertices
  /// lie near this one's (add_object): a copy of the mesh moved a little, as a robot link in
  /// another time step. Conservative mode bundles such copies' slot groups (SlotBundle).
  int family = 0;
};

/// Per camera and candidate triangle (conservative mode): the infinite cone from the camera over
/// the triangle, as the inward unit normals of its three planes, the separating-axis candidates,
/// and the triangle's nearest distance (an occluding object's; 0 for an occupying object's,
/// which no test reads). 376 bytes; what the tests derive from these (|normal|,
/// an axis's box radius and length) is computed where used, from the same numbers.
struct TriangleCone {
  core::Vec3 normal[3];
  /// The separating-axis candidates beyond the 3 planes (3 box normals, then the 9 products of
  /// cone edges and box axes) that can separate: the cone lies on one side of them, each turned
  /// (negated, which is exact) so that axis·x ≥ 0 on the cone.
  std::array<core::Vec3, 12> axes;
  int axis_count;  // (no initialisers: an array of cones is allocated untouched)
  double near_distance;
};

/// Center mode: how many rays test a group's triangles directly (their balls, then the ray
/// test) before the group is projected (its slots' rectangles and edge lines then rule out most
/// triangles before the ray test). Projecting a group costs about as much as this many direct
/// tests of it: fine meshes have many groups that few rays meet, coarse ones few that many rays
/// meet. Only when a camera has more than one group per kRaysPerGroup voxels (else every group
/// is projected on its first ray). Chosen, measured only against projecting every group at once
/// (bench/scale_bench, robot family: 3k triangles slower with direct rays, 10k faster).
inline constexpr int kDirectRays = 8;
inline constexpr int kRaysPerGroup = 32;

/// The states of a slot's cone in CameraSetup::cone_state.
inline constexpr std::uint8_t kConeMissing = 0, kConeMaking = 1, kConeReady = 2;

/// A triangle's projection as three lines a x + b y + c ≥ 0 (inside, padded).
struct EdgeLines {
  std::array<std::array<double, 3>, 3> line{};
  bool valid = false;
};

/// A regular grid of bins over a rectangle of the image plane (X/Z, Y/Z): bin (bx, by) covers
/// [origin + b / scale, origin + (b + 1) / scale) on each axis.
struct BinGrid {
  std::array<double, 2> origin{0.0, 0.0};
  std::array<double, 2> scale{1.0, 1.0};  ///< bins per unit of image coordinate, per axis
  std::array<int, 2> n{1, 1};             ///< bins per axis
  int count() const { return n[0] * n[1]; }
};

/// The candidate lists of one chunk of 64 states: per bin of a BinGrid the slot groups
/// (ascending) whose rectangle covers it, as offsets (count() + 1) into items.
struct BinLists {
  std::vector<int> start;
  std::vector<int> items;
};

/// Conservative mode: slot groups of one chunk tested as a whole first (judge_conservative(),
/// block_clear()): the groups bundle_groups[first .. last − 1] of ChunkCandidates, the same
/// cluster of copies of one mesh (ObjectInfo::family) in consecutive time steps, with what holds
/// for each of them: the union of their rectangles, the least of their `near`, the union of
/// their objects' states in the chunk, and their objects' role (one family, one role). A box
/// that misses the rectangle, or lies nearer than `near` to a non-occupying bundle, or whose
/// open states miss `states`, has none of their slots as a candidate.
struct SlotBundle {
  std::array<double, 4> rect{};
  double near = 0.0;
  std::uint64_t states = 0;
  int first = 0, last = 0;
  bool occupying = false;
};

/// One chunk's candidates: the coarse bins of slot groups (center mode), or the coarse bins and
/// the wide bins of slot bundles (conservative mode), and the slots not wholly in front of the
/// camera, which are candidates everywhere. Only slots of objects that belong to a state of the
/// chunk.
struct ChunkCandidates {
  /// Of groups (CameraSetup::groups; center mode) or of bundles (`bundles`; conservative mode).
  BinLists coarse, wide;
  std::vector<SlotBundle> bundles;
  std::vector<int> bundle_groups;  ///< the bundles' groups, bundle by bundle
  std::vector<int> everywhere;
};

/// The binned slots of one cluster of triangles (consecutive slots first .. last − 1, of one
/// object), with what holds for each of them: the union of their (padded) rectangles, and a lower
/// bound of their triangles' distance from the camera (TriangleCone::near_distance, as computed;
/// −∞ when none is known). A box that misses the rectangle, or lies nearer than `near` to a
/// non-occupying group, has none of them as a candidate.
struct SlotGroup {
  int first = 0, last = 0;
  std::array<double, 4> rect{};
  double near = 0.0;
  int object = 0;  ///< the object of its triangles
  /// ≥ 0: the group is all of this cluster of the object's triangles (ObjectInfo::clusters), in
  /// order, and its slots' triangles, objects and cone states are written when it is projected
  /// (project_group); −1: written at set-up.
  int cluster = -1;
  int source = 0;  ///< the index of its cluster in ObjectInfo::clusters
};

/// Everything about one camera that one evaluation needs and that does not depend on the
/// voxel: the FOV test, and the triangles that can decide a label (the candidates: in front of
/// the camera or across its plane, not culled, projecting into the FOV; in conservative mode not
/// flat), numbered as slots in triangle order, each with its projection's rectangle and, per
/// mode, its edge lines or its cone; the slots in front of the camera are grouped by cluster of
/// triangles and the groups sorted into bins of the image plane per chunk of 64 states (a slot
/// is a candidate for a voxel only when its group's rectangle and the voxel's projection share a
/// bin).
/// Rebuilt in place for every evaluation (its memory is reused, camera_setup).
struct CameraSetup {
  core::CameraSetting setting;
  std::optional<core::Fov> fov;
  core::Vec3 c = core::Vec3::Zero();
  core::Vec3 axis = core::Vec3::UnitX(), ex = core::Vec3::UnitY(), ey = core::Vec3::UnitZ();
  core::Vec3 abs_ex = core::Vec3::Zero(), abs_ey = core::Vec3::Zero(),
             abs_axis = core::Vec3::Zero();
  double box_x = 0.0, box_y = 0.0, box_z = 0.0;  ///< a voxel box's half extents in this frame
  bool pyramid = false;             ///< side planes (a pyramid or a frustum), not a cone
  std::vector<core::Vec3> normals;  ///< pyramid (frustum) side normals (core::Fov's)
  double near = 0.0;                ///< axial near plane (m), 0 = none
  std::optional<double> range;
  /// The cone's half angle, or the bounding cone's for a pyramid (the cone it is inscribed in)
  /// or a frustum (CameraModel::bounding_half_angle).
  double cos_half = 1.0, sin_half = 0.0;
  double row_cos_sq = 0.0;  ///< cos² of the half angle widened by 1e-6 (row_interval); 0: none
  /// The FOV's section at unit depth lies in [view[0], view[1]] × [view[2], view[3]] of (X/Z,
  /// Y/Z): the projection of every box or ray the labeller tests.
  std::array<double, 4> view{-1.0, 1.0, -1.0, 1.0};
  /// Center mode: the bins one voxel centre looks up. Conservative mode: coarse bins under a
  /// box's projection, and wide bins (twice as fine) holding each rectangle widened by `widen`.
  BinGrid coarse, wide;
  std::array<double, 2> widen{0.0, 0.0};  ///< per image axis
  std::vector<ChunkCandidates> chunks;
  // Per slot: slot_count of them (the arrays are longer, their memory reused); those of a group
  /// of a cluster (SlotGroup::cluster) written when it is projected.
  int slot_count = 0;
  mutable std::vector<int> slot_triangle;
  mutable std::vector<int> slot_object;
  /// Slots are numbered object by object, cluster by cluster. Per object o: its groups are
  /// object_groups[o] .. object_groups[o + 1] − 1 (objects.size() + 1 offsets).
  std::vector<SlotGroup> groups;
  std::vector<int> object_groups;
  /// The slots not wholly in front of the camera, per object o from everywhere_start[o] on.
  std::vector<int> everywhere;
  std::vector<int> everywhere_start;
  /// Per group: kConeReady when its slots' rectangles (and edge lines) are known, else they are
  /// computed on first use (VoxelEvaluator::Impl::ensure_projected; kConeMissing → kConeMaking →
  /// kConeReady).
  mutable std::unique_ptr<std::atomic<std::uint8_t>[]> group_state;
  /// Center mode, per group not projected yet: the rays that tested its triangles directly
  /// (judge_center; it is projected once kDirectRays have).
  mutable std::unique_ptr<std::atomic<std::uint8_t>[]> group_rays;
  int direct_rays = 0;  ///< kDirectRays, or 0 when groups are few (kRaysPerGroup)
  std::size_t group_capacity = 0;
  /// The projection's bounding rectangle (x0, x1, y0, y1), padded; infinite for the slots not
  /// wholly in front of the camera, empty (x0 = ∞) for those of a group projected on first use
  /// that lie outside the FOV's section (no slots of the others). At least one entry per slot.
  mutable std::vector<std::array<double, 4>> rect;
  /// Center mode; when projectable and not degenerate.
  mutable std::vector<EdgeLines> lines;
  /// Conservative mode: per slot its cone, made on first use by whichever thread needs it first
  /// (VoxelEvaluator::Impl::cone_of; cone_state kConeMissing → kConeMaking → kConeReady).
  mutable std::unique_ptr<TriangleCone[]> cones;
  mutable std::unique_ptr<std::atomic<std::uint8_t>[]> cone_state;
  std::size_t cone_capacity = 0;
  // Per object.
  /// Its back faces (detail::back_face) are culled: no slots (docs/design/labelling.md L3).
  std::vector<std::uint8_t> culled;
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
  std::vector<std::uint32_t> stamp;  ///< per slot group (any camera's): last visit that tested it
  std::uint32_t visit = 0;
  struct Hit {
    double t;
    int occupying;  ///< 0 or 1: at equal distance a non-occupying hit comes first (L8)
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

/// The size of a cell at one refinement level l (0 = the base voxel): half extents and radius
/// are the base voxel's times factor = 2^−l, exactly (powers of two scale without rounding), so
/// level 0 computes with the very numbers the unrefined labeller uses.
struct CellSize {
  core::Vec3 half = core::Vec3::Zero();  ///< half extents (m)
  double radius = 0.0;                   ///< |half| (m)
  double factor = 1.0;                   ///< 2^−l
};

/// How many deciding slots (triangles) refinement remembers per node and camera
/// (judge_conservative()'s witnesses): one per copy of a target in each time step, say.
constexpr int kWitnesses = 4;

/// What judge_conservative() tells refinement besides the verdict.
struct Witnesses {
  /// kWitnesses slots to test first (those ≥ 0: the ones that decided the cell's parent),
  /// updated with the triangles that decided states here, most recent first.
  int* triangles = nullptr;
  /// Adds the states whose deciding triangle decides them for every box inside this one as
  /// well: its cone holds the whole box (by a margin) and it is occupying, or it lies nearer to
  /// the camera than every point of the box (blocking).
  StateMask sure = 0;
};

/// What refinement of one base voxel needs besides the Impl (refine.cpp).
struct RefineContext {
  const std::vector<CameraSetup>* cameras = nullptr;
  const StateMask* seeing = nullptr;         ///< per camera: states it is not blind in
  int chunk = 0;                             ///< the chunk of 64 states being refined
  const StateMask* object_states = nullptr;  ///< the chunk's
  /// Obstacle-interior tables of the voxel's steps: the states of the step, the table.
  std::vector<std::pair<StateMask, const std::uint8_t*>> removal;
  /// Interior tables of the occupying objects near the voxel: the object's states, the table.
  std::vector<std::pair<StateMask, const std::uint8_t*>> inside;
  StateMask* out = nullptr;  ///< per finest cell (Morton order): states where it is in M
  Scratch* scratch = nullptr;
  std::size_t hint = 0;  ///< the camera that last freed a cell (tried first)
  /// Per level and camera: kWitnesses slots that decided states of the node being refined
  /// at that level (detail::Witnesses::triangles, most recent first), −1 for none.
  std::vector<int> witness;
  /// Per level and camera: states where every cell below the node at that level is non-free
  /// for the camera (detail::Witnesses::sure; all bits when the node lies outside the camera's
  /// FOV).
  std::vector<StateMask> sure;
};

/// Lazily filled cache of box–critical distances² of the octree nodes below each base voxel for
/// one time step (blocks allocated on first use; racing threads store the same doubles).
class NodeDistanceCache {
 public:
  NodeDistanceCache(int voxels, int block_size);
  ~NodeDistanceCache();
  NodeDistanceCache(const NodeDistanceCache&) = delete;
  NodeDistanceCache& operator=(const NodeDistanceCache&) = delete;
  /// The block of voxel v: block_size slots, NaN until computed.
  std::atomic<double>* block(int v);

 private:
  int voxels_ = 0, block_size_ = 0;
  std::unique_ptr<std::atomic<std::atomic<double>*>[]> blocks_;
};

/// The filtered models of every state for one configuration (VoxelEvaluator::model and
/// leaf_model): the base models and, with refinement, the refined cell sets.
struct FilteredModels {
  std::vector<std::vector<std::uint8_t>> base;
  std::vector<CellSet> cells;  ///< empty without refinement
};

/// The tables set-up builds once from the scene (setup.cpp) and every stage reads: the grid's
/// voxel boxes, the objects with their roles and triangles, the states with their state masks
/// per chunk of 64, obstacle interiors and the voxels occupying objects reach into.
struct SceneTables {
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
  std::vector<detail::Ball> triangle_balls;          ///< a ball holding each triangle
  std::vector<detail::StateInfo> states;
  /// Per chunk of 64 states: the states (bits) each object belongs to, and each time step's.
  std::vector<std::vector<detail::StateMask>> chunk_object_states;
  std::vector<std::vector<detail::StateMask>> chunk_step_states;
  /// Per chunk: the objects (ascending) that belong to one of its states.
  std::vector<std::vector<int>> chunk_objects;
  std::vector<std::vector<std::uint8_t>> removed_by_step;  ///< obstacle interiors per step
  /// Per chunk of 64 states and voxel: the states whose time step removes the voxel as obstacle
  /// interior (removed_by_step), so that raw_models drops them with one load, not one per step.
  std::vector<std::vector<detail::StateMask>> chunk_removed;
  /// Conservative mode: per object, the voxels an occupying one reaches into (voxels_reached;
  /// empty for the others), and per chunk of 64 states and voxel the states where one of them
  /// does. No camera ever sees such a voxel free (docs/design/labelling.md L6): raw_models
  /// keeps it in M for those states without a test.
  std::vector<std::vector<int>> reached_by_object;
  std::vector<std::vector<detail::StateMask>> chunk_reached;
};

/// Distances from the critical objects C_h to the voxels, per time step (setup.cpp; read by
/// distance.cpp and lower_bound.cpp).
struct CriticalTables {
  /// Per step and voxel: a lower bound of d(C_h, voxel)² (the centre's distance less the
  /// voxel's radius; in center mode the value itself), and in conservative mode the value,
  /// computed on first use by critical_sq (NaN until then; evaluate() is const and runs on
  /// several threads: racing threads store the same double).
  std::vector<std::vector<double>> critical_lb_by_step;
  /// Per step: every voxel in shells of its lower bound (counting sort on √lb / width: shell b
  /// holds the voxels with b ≤ √lb / width < b + 1, up to rounding), so that model_distance()
  /// can stop at the first shell whose bound exceeds the best distance so far.
  struct LowerBoundShells {
    double width = 1.0;      ///< m
    std::vector<int> start;  ///< shells + 1 offsets into `voxels`
    std::vector<int> voxels;
  };
  std::vector<LowerBoundShells> shells_by_step;
  std::vector<std::unique_ptr<std::atomic<double>[]>> critical_by_step;
  std::vector<std::vector<detail::IndexedSolid>> critical_solids_by_step;
};

/// Refinement's tables (refine_setup.cpp; conservative mode, options.refine = L > 0 levels;
/// at L = 0 the octree of one cell per voxel, which the lower bound and the cell filter use).
struct RefinementTables {
  int levels = 0;
  std::vector<detail::CellSize> cell_sizes;  ///< per level 0..L
  detail::Octree octree;
  /// Per step: per base voxel the index of its table in removal_tables, or −1 when no node
  /// below it lies wholly inside an obstacle of the step. A table has one byte per octree node
  /// (levels 1..L; 1 = wholly inside, as obstacle_interiors tests a voxel).
  std::vector<std::vector<int>> removal_index;
  std::vector<std::vector<std::uint8_t>> removal_tables;
  /// Per base voxel: (occupying object, index into inside_tables) for the objects with octree
  /// nodes (levels 0..L) wholly inside them below the voxel; a table has one byte per node.
  std::vector<std::vector<std::pair<int, int>>> inside_by_voxel;
  std::vector<std::vector<std::uint8_t>> inside_tables;
  std::vector<std::unique_ptr<detail::NodeDistanceCache>> node_sq_by_step;
};

}  // namespace detail

/// The evaluator's state is the three stages' tables (set-up, critical distances, refinement);
/// the per-camera tables are detail::CameraSetup, built per evaluation; per-evaluation buffers
/// are the callers' (evaluator.cpp). The methods are grouped by the file that defines them.
struct VoxelEvaluator::Impl : detail::SceneTables,
                              detail::CriticalTables,
                              detail::RefinementTables {
  core::Scene scene;
  VoxelOptions options;
  double err_lower_bound = 0.0;  ///< conservative mode only

  /// d(C_h, M) and the model's volume for one state.
  struct ModelDistance {
    double d_model = 0.0;  ///< m; core::empty_model_distance when M is empty
    double volume = 0.0;   ///< m³
  };

  // Set-up (setup.cpp): everything that does not depend on the cameras.
  void build();
  /// The index of the object in `objects`, added with its triangles, or in conservative mode
  /// of an equal one added before (same role and mesh; shared by their states).
  int add_object(const core::SceneObject& object, core::ObjectRole role);
  /// The conservative lower bound of Err (err_lower_bound()) at the evaluator's level
  /// (lower_bound.cpp).
  double lower_bound() const;
  /// How deep (m) an occupying object must reach into a voxel's box for lower_bound() to count
  /// the voxel as always in M: 1e-9 of S's diagonal plus its largest |coordinate|.
  double contact_depth() const;
  /// Voxels whose box, shrunk by contact_depth(), meets the closed solid `mesh`, ascending.
  std::vector<int> voxels_reached(const core::TriangleMesh& mesh) const;
  std::vector<std::uint8_t> obstacle_interiors(const core::TimeStep& step) const;
  /// The step's obstacles (core::is_obstacle): static, then dynamic.
  std::vector<const core::SceneObject*> obstacles_of(const core::TimeStep& step) const;
  /// Per axis, the base voxel indices [lo, hi] within one voxel of `bounds`, clamped to the grid.
  std::array<std::array<int, 2>, 3> voxel_range(const core::Box3& bounds) const;
  /// The shells of shells_by_step for one step's lower bounds.
  LowerBoundShells lower_bound_shells(const std::vector<double>& lb) const;
  /// The lower bounds of critical_lb_by_step for one step.
  std::vector<double> critical_distances(const std::vector<detail::IndexedSolid>& solids) const;
  /// d(C_h, voxel v)² as core::box_solid_sq_distance (conservative) or
  /// core::point_solid_sq_distance (center) gives it, min over C_h.
  double critical_sq(int time_step, int v) const;

  // Refinement (refine.cpp).
  /// Set-up: octree tables, cell sizes, obstacle-interior tables, distance caches
  /// (refine_setup.cpp).
  void build_refinement();
  template <class Inside, class Meets>
  bool node_table(int v, const Inside& wholly_inside, const Meets& meets_surface,
                  std::vector<std::uint8_t>& table) const;
  /// Depth-first over the octree nodes below base voxel v: calls visit(level, morton, box) on
  /// the children of each node visited (from the voxel, level 0, down), and descends into a
  /// child when visit returns true and it is above the finest level.
  template <class Visit>
  void for_each_node_below(int v, const Visit& visit) const {
    std::vector<std::pair<int, int>> stack{{0, 0}};
    while (!stack.empty()) {
      const auto [level, morton] = stack.back();
      stack.pop_back();
      for (int q = 0; q < 8; ++q) {
        const int child = 8 * morton + q;
        if (visit(level + 1, child, node_box(v, level + 1, child)) && level + 1 < levels) {
          stack.push_back({level + 1, child});
        }
      }
    }
  }
  /// The refined model of every state from the filtered base models `rows` (refine.cpp):
  /// kept base voxels near C_h are refined (within a radius that starts at the unrefined
  /// d(C_h, M) plus a voxel diagonal and grows until the nearest kept cell lies within it), the
  /// others stay whole; then components and filter on the finest cells, and d(C_h, M). Into
  /// `leaves` (filtered), `counts` (cell components kept and removed), `distances`; adds the
  /// stages' times to `timing`.
  void refined_states(const std::vector<detail::CameraSetup>& cameras,
                      const std::vector<detail::Rows>& rows, std::vector<detail::CellSet>& leaves,
                      std::vector<ComponentCount>& counts, std::vector<ModelDistance>& distances,
                      core::Timing& timing) const;
  /// ORs into `out` (the voxel's finest cells) the states of `pending` where each cell of base
  /// voxel v is in M before the filter: no camera proves it free, no obstacle holds it wholly.
  void refine_voxel(detail::RefineContext& ctx, const detail::StateMask* step_states, int v,
                    detail::StateMask pending, detail::StateMask* out) const;
  /// Refines the children of node (level, morton) at global cell coordinates (I, J, K) of its
  /// level, for the states `pending` (where the node is in M), into ctx.out.
  /// `fixed`: states where every cell below the node is in M without tests (it lies wholly
  /// inside an occupying object, or outside every camera's FOV); `open`: states where the node
  /// is in M and its children need labels; `in_view`: cameras (bits 0..63) whose FOV holds the
  /// node's box.
  void refine_node(detail::RefineContext& ctx, int level, int morton, long I, long J, long K,
                   detail::StateMask fixed, detail::StateMask open, std::uint64_t in_view) const;
  /// Whether the FOV of `cam` surely misses the ball of radius r about the point at w from the
  /// camera (d = |w|): outside the (bounding) cone, before the near or beyond the far plane, by
  /// a margin.
  /// The states of `interest` holding triangle t's object when t is occupying and its cone
  /// holds the whole cell of size `size` at w from the camera (d = |w|) by
  /// detail::Witnesses' `sure` margin (judge_conservative() would find the cell, and every cell
  /// inside it, occupied there); else 0.
  detail::StateMask contained(const detail::CameraSetup& cam, int slot, const core::Vec3& w,
                              double d, const detail::CellSize& size, detail::StateMask interest,
                              int chunk) const;
  bool ball_outside_fov(const detail::CameraSetup& cam, const core::Vec3& w, double d,
                        double r) const;
  /// The box of octree node (l, m) below base voxel v (m, world frame).
  core::Box3 node_box(int v, int level, int morton) const;
  /// d(C_h, node box)² (core::box_solid_sq_distance, min over C_h), cached.
  double node_sq(int time_step, int v, int level, int morton) const;

  // Labelling (labelling.cpp): SPEC §3 per camera, voxel and state.
  /// `model`: the camera's (one of scene.cameras.models).
  /// Into `cam`, whose memory is reused (camera_setup.cpp).
  void camera_setup(const core::CameraSetting& camera, const core::CameraModel& model,
                    detail::CameraSetup& cam) const;
  /// Unfiltered models of all states (in M: no camera sees the voxel free, minus obstacle
  /// interiors), for voxel slices k ∈ [k_begin, k_end): per chunk of 64 states and voxel of the
  /// slices, the states where it is in M, into `masks[chunk][v]` (grid.count() per chunk).
  void raw_models(const std::vector<detail::CameraSetup>& cameras, int k_begin, int k_end,
                  std::vector<std::vector<detail::StateMask>>& masks) const;
  /// The unfiltered models of all states for a configuration (checked against the scene), into
  /// `models` (one detail::Rows per state; resized, its memory reused from call to call).
  void all_raw_models(const core::CameraConfig& config, std::vector<detail::Rows>& models,
                      std::vector<detail::CameraSetup>* cameras_out = nullptr) const;
  /// Per camera: the states of chunk `chunk` (bits) it is not blind in (SPEC §3.3).
  std::vector<detail::StateMask> seeing_states(const std::vector<detail::CameraSetup>& cameras,
                                               int chunk) const;
  /// The conservative FOV test (in_fov) for a box [lo, hi] of radius r, centre at w from the
  /// camera (d = |w|).
  bool box_in_fov(const detail::CameraSetup& cam, const core::Vec3& lo, const core::Vec3& hi,
                  double r, const core::Vec3& w, double d) const;

  /// κ of every voxel for one camera in one state.
  std::vector<Label> labels(const detail::CameraSetup& camera, int state) const;

  // Distance (distance.cpp): d(C_h, M) and the model's volume for one state.
  ModelDistance model_distance(const detail::Rows& model, int time_step) const;
  /// d(C_h, M) and volume of the finest cells of `set` (node_sq of the nearest cell).
  ModelDistance model_distance(const detail::CellSet& set, int time_step) const;

  /// The plausibility filter on every state's model (`models`, one per state, in chunks of
  /// kChunk), into `counts`: per chunk the components of the voxels its states share, found once
  /// (docs/design/distance.md C1), then each state's (evaluator.cpp).
  void filter_states(std::vector<detail::Rows>& models, std::vector<ComponentCount>& counts) const;
  /// All raw models filtered, and refined with refinement (evaluator.cpp).
  detail::FilteredModels filtered_models(const core::CameraConfig& config) const;

  // Expensive checks (expensive_checks.cpp; only with CAMPLACE_EXPENSIVE_CHECKS): abort with a
  /// message when a stage disagrees with an independent or plain computation.
  /// A sample of voxels of the raw models against tests/support/reference.
  void check_labels(const core::CameraConfig& config,
                    const std::vector<std::vector<std::uint8_t>>& models) const;
  /// Filtered models ⊆ raw models.
  void check_filtered(const std::vector<std::vector<std::uint8_t>>& raw,
                      const std::vector<std::vector<std::uint8_t>>& filtered) const;
  /// model_distance equals the plain minimum over every voxel of the model.
  void check_distance(const std::vector<std::uint8_t>& model, int time_step,
                      const ModelDistance& found) const;
  /// Refined models ⊆ the (filtered) unrefined ones, no nearer, and their distance equals the
  /// plain minimum over every finest cell.
  void check_refined(const std::vector<std::vector<std::uint8_t>>& models,
                     const std::vector<detail::CellSet>& leaves,
                     const std::vector<ModelDistance>& distances) const;

 private:
  /// The scan of model_distance over either view of M with `count` cells (distance.cpp).
  template <class Members>
  ModelDistance nearest(const Members& members, long count, int time_step) const;
  /// min(best, distance² of the nearest cell of M in `slot` of `set`), by branch and bound.
  double nearest_cell(const detail::CellSet& set, int slot, int time_step, double best) const;
  void row_interval(const detail::CameraSetup& cam, int j, int k, int& lo, int& hi, int& in_lo,
                    int& in_hi) const;
  bool in_fov(const detail::CameraSetup& cam, int i, int j, int k, const core::Vec3& w,
              double d) const;
  /// The judges of one camera for the states `interest` of chunk `chunk` (judge.cpp).
  detail::Verdict judge_center(const detail::CameraSetup& cam, const core::Vec3& w, double d,
                               detail::StateMask interest, int chunk, detail::Scratch& scratch,
                               bool free_only) const;
  detail::Verdict judge_conservative(const detail::CameraSetup& cam, const core::Vec3& w, double d,
                                     const detail::CellSize& size, detail::StateMask interest,
                                     int chunk, detail::Scratch& scratch, bool free_only,
                                     detail::Witnesses* witnesses = nullptr) const;
  /// The states of `open` where every voxel of the block [lo, hi] is surely free for the camera
  /// (raw_models), for the states `open` of chunk `chunk`.
  detail::StateMask block_clear(const detail::CameraSetup& cam, const core::Vec3& lo,
                                const core::Vec3& hi, detail::StateMask open, int chunk,
                                detail::Scratch& scratch) const;
  enum class Cone { meet, miss, near_miss };
  /// A box as cone_test sees it: its centre w from the camera (m), its size, and the tolerances
  /// that depend on the box only — kTouch·(|w| + Σh) and kMargin·|w| — computed once per box
  /// (cone_box), the same numbers for every cone it is tested against.
  struct ConeBox {
    core::Vec3 w = core::Vec3::Zero();
    const detail::CellSize* size = nullptr;
    double scale = 0.0, inside = 0.0;
  };
  static ConeBox cone_box(const core::Vec3& w, const detail::CellSize& size);
  Cone cone_test(const detail::TriangleCone& tc, const ConeBox& box) const;
  /// The cone over triangle t from the camera at c (conservative mode; camera_setup.cpp).
  void make_cone(int t, const core::Vec3& c, detail::TriangleCone& tc) const;
  /// The cone of the camera's slot, made on first use (thread-safe; make_cone_of in
  /// camera_setup.cpp).
  const detail::TriangleCone& cone_of(const detail::CameraSetup& cam, int slot) const {
    if (cam.cone_state[slot].load(std::memory_order_acquire) == detail::kConeReady) {
      return cam.cones[slot];
    }
    return make_cone_of(cam, slot);
  }
  const detail::TriangleCone& make_cone_of(const detail::CameraSetup& cam, int slot) const;
  /// Whether the cone of the camera's slot is made.
  static bool cone_ready(const detail::CameraSetup& cam, int slot) {
    return cam.cone_state[slot].load(std::memory_order_acquire) == detail::kConeReady;
  }
  /// Slot group g's slots projected (rectangles and edge lines), on first use (thread-safe;
  /// project_group in camera_setup.cpp).
  void ensure_projected(const detail::CameraSetup& cam, int g) const {
    if (cam.group_state[g].load(std::memory_order_acquire) != detail::kConeReady) {
      project_group(cam, g);
    }
  }
  void project_group(const detail::CameraSetup& cam, int g) const;
  /// Writes the slots of group `group` of a cluster: their triangles, objects and (conservative
  /// mode) cone states (camera_setup.cpp).
  void fill_group(const detail::CameraSetup& cam, const detail::SlotGroup& group) const;
  /// The triangle of slot s of `group`, whether or not its slots are written yet.
  int group_triangle(const detail::CameraSetup& cam, const detail::SlotGroup& group, int s) const {
    if (group.cluster < 0) return cam.slot_triangle[s];
    const detail::ObjectInfo& info = objects[group.object];
    return info.first_triangle +
           info.cluster_order[info.clusters[group.cluster].begin + (s - group.first)];
  }
};

}  // namespace camplace::voxel
