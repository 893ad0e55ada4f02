// Per camera, once per evaluation (SPEC §3): everything the labeller needs that does not depend
// on the voxel — the camera's frame and FOV numbers, the objects that hold the camera (blind in
// their states), back-face culling, the slots (the triangles that can decide a label, with their
// projections and, in conservative mode, their cones) in groups per cluster of triangles, and
// the groups sorted into bins of the image plane per chunk of 64 states (docs/design/labelling.md
// L1, L3, L10). Clusters wholly behind the camera, or facing it, cost no work per triangle; a
// group's projections are computed when a box or ray first needs them. Its memory is reused from
// evaluation to evaluation.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <thread>

#include "camplace/core/geometry.hpp"
#include "image_plane.hpp"
#include "impl.hpp"

namespace camplace::voxel {

using core::Vec3;
using detail::BinGrid;
using detail::BinLists;
using detail::BinRange;
using detail::CameraSetup;
using detail::ChunkCandidates;
using detail::kMargin;
using detail::ObjectInfo;
using detail::TriangleCone;

namespace {

using Triangles = std::vector<std::array<Vec3, 3>>;

/// The camera's frame (axis, ex right, ey up), a voxel box's half extents in it, and the FOV's
/// numbers: near and far planes, the (bounding) cone's half angle, the row test's widened cone,
/// the FOV's section at unit depth. Returns the bins' width per image axis at the grid's
/// resolution: `bins` bins across the section of the FOV's (bounding) cone, or of a frustum's
/// image rectangle.
std::array<double, 2> camera_frame(const core::CameraSetting& camera,
                                   const core::CameraModel& model, const Vec3& half_step, int bins,
                                   CameraSetup& cam) {
  cam.setting = camera;
  cam.fov.emplace(camera, model);
  const core::Fov& fov = *cam.fov;
  cam.c = camera.position;
  cam.axis = fov.axis();
  cam.ey = core::up_vector(camera);
  cam.ex = cam.axis.cross(cam.ey).normalized();
  cam.abs_ex = cam.ex.cwiseAbs();
  cam.abs_ey = cam.ey.cwiseAbs();
  cam.abs_axis = cam.axis.cwiseAbs();
  cam.box_x = cam.abs_ex.dot(half_step);
  cam.box_y = cam.abs_ey.dot(half_step);
  cam.box_z = cam.abs_axis.dot(half_step);
  cam.pyramid = !fov.is_cone();
  cam.normals = fov.pyramid_normals();
  cam.near = model.near;
  cam.range = model.range;
  // The cone's, or the bounding cone's half angle: every test that uses it proves a point
  // outside the FOV (or, for a cone, inside), and the pyramid and the frustum lie in it.
  const double half_angle = model.bounding_half_angle();
  cam.cos_half = std::cos(half_angle);  // as core::Fov computes it
  cam.sin_half = std::sin(half_angle);
  const double widened = half_angle + 1e-6;
  cam.row_cos_sq = widened < 0.5 * core::kPi ? std::cos(widened) * std::cos(widened) : 0.0;
  // The FOV's section at unit depth: inside the bounding cone's circle of radius tan α, or a
  // frustum's image rectangle tan(H/2) × tan(V/2) along ex (right) and ey (up), both turned by
  // the roll (core::Fov's corners). Every box the labeller tests lies in the FOV (its corners
  // pass core::Fov::contains, or its centre does in center mode), so it projects into this
  // section, widened here against rounding.
  std::array<double, 2> half{std::tan(half_angle), std::tan(half_angle)};
  if (model.fov == core::FovShape::frustum) {
    half = {std::tan(0.5 * model.horizontal), std::tan(0.5 * model.vertical)};
  }
  const double inf = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 2; ++a) {
    const double h =
        half_angle < 0.5 * core::kPi && std::isfinite(half[a]) ? half[a] * (1 + 1e-6) + 1e-9 : inf;
    cam.view[2 * a] = -h;
    cam.view[2 * a + 1] = h;
  }
  return {2.0 * half[0] / bins, 2.0 * half[1] / bins};
}

/// Per object: whether it holds the camera at c. SPEC §3.3 with one convention in both
/// pipelines: a camera in the closed object, on its surface too, is blind (its rays start on the
/// object). The exact pipeline decides this exactly; here a camera within a rounding distance of
/// the surface counts as on it, which only makes the model larger, never smaller (conservative
/// mode stays ⊇ exact).
void objects_holding(const std::vector<ObjectInfo>& objects, const Vec3& c,
                     std::vector<std::uint8_t>& inside) {
  inside.assign(objects.size(), 0);
  for (std::size_t o = 0; o < objects.size(); ++o) {
    const ObjectInfo& info = objects[o];
    const double d = (info.center - c).norm();
    const double on_surface = 1e-9 * (info.radius + info.center.norm() + c.norm());
    const bool near = d <= info.radius + on_surface;
    inside[o] = near && core::point_solid_sq_distance(*info.mesh, c) <= on_surface * on_surface;
  }
}

/// One vertex seen from the camera: its offset q = vertex − c, |q|, and its image coordinates
/// (X/Z, Y/Z) when it lies in front of the camera (Z > 1e-9 |q|).
struct VertexView {
  Vec3 q;
  double norm;
  double x, y;
  bool in_front;
};

/// The bins a slot group (center mode) or a bundle of groups (conservative mode) covers.
struct GroupBins {
  BinRange coarse, wide;
};

/// The working memory of camera_setup, reused from evaluation to evaluation on each thread.
struct SetupWork {
  std::vector<VertexView> vertices;  ///< per vertex of the current object, once viewed
  std::vector<std::uint32_t> vertex_stamp;
  std::uint32_t vertex_visit = 0;
  /// Per triangle of the current object, once its cluster's tilts are computed: det / scale, 0
  /// when flat.
  std::vector<double> tilt;
  std::vector<std::uint8_t> flat;
  /// Per node of the object's tree: facing_cluster of its bounds where the walk of
  /// cull_back_faces stopped at it (proven; the nodes below are not visited), else kMixed.
  std::vector<std::uint8_t> node_facing;
  std::vector<std::uint8_t> group_projected;  ///< per slot group: its slots projected
  std::vector<GroupBins> bins;                ///< per slot group
  std::vector<int> deferred;  ///< the current cluster's triangles not wholly in front
  std::vector<int> fill;
  std::vector<int> members;  ///< one chunk's slot groups (chunk_candidates)
  /// make_bundles: per group (family, rank in its object, group), and a buffer and the run
  /// starts to sort them (sort_runs); per bundle its bins and index.
  std::vector<std::array<int, 3>> keyed, keyed_buffer;
  std::vector<std::size_t> runs;
  std::vector<GroupBins> bundle_bins;
  std::vector<int> bundle_ids;
};

/// Counting sort of the slot groups of one chunk (`members`, ascending) into the bins of `grid`:
/// `range(group)` gives the bins a group covers.
template <class Range>
void sort_into_bins(const BinGrid& grid, const std::vector<int>& members, const Range& range,
                    std::vector<int>& fill, BinLists& lists) {
  const int cells = grid.count();
  lists.start.assign(cells + 1, 0);
  for (int s : members) {
    const BinRange& r = range(s);
    for (int by = r.y0; by <= r.y1; ++by) {
      for (int bx = r.x0; bx <= r.x1; ++bx) ++lists.start[by * grid.n[0] + bx + 1];
    }
  }
  for (int b = 0; b < cells; ++b) lists.start[b + 1] += lists.start[b];
  lists.items.resize(lists.start[cells]);
  fill.assign(lists.start.begin(), lists.start.end() - 1);
  for (int s : members) {
    const BinRange& r = range(s);
    for (int by = r.y0; by <= r.y1; ++by) {
      for (int bx = r.x0; bx <= r.x1; ++bx) lists.items[fill[by * grid.n[0] + bx]++] = s;
    }
  }
}

/// Slot groups per bin of the chunk with most groups, on average, above which the bins get finer
/// than the grid's resolution gives (place_bins), and at most how many bins there are then.
/// Center mode looks up one bin per voxel centre; conservative mode every bin under a box's
/// projection, or for a small box one wide bin (4 times as many bins per chunk): fewer, larger
/// bins. Measured on fine meshes when the bins held single slots (bench/scale_bench,
/// instructions per evaluation): 8 against 2 and 4; not measured again for groups.
constexpr double kCenterPerBin = 4.0, kConservativePerBin = 8.0;
constexpr double kCenterMaxBins = 1 << 18, kConservativeMaxBins = 1 << 14;

/// A grid of bins of width `width` per axis over [lo, hi], at most `max_bins` per axis.
BinGrid grid_over(const std::array<double, 2>& lo, const std::array<double, 2>& hi,
                  const std::array<double, 2>& width, int max_bins) {
  BinGrid grid;
  for (int a = 0; a < 2; ++a) {
    const double extent = hi[a] - lo[a];
    const double n = extent > 0.0 && width[a] > 0.0 ? std::ceil(extent / width[a]) : 1.0;
    grid.n[a] = static_cast<int>(std::clamp(n, 1.0, static_cast<double>(max_bins)));
    grid.origin[a] = lo[a];
    grid.scale[a] = extent > 0.0 ? grid.n[a] / extent : 1.0;
  }
  return grid;
}

/// Vertex p seen from the camera.
VertexView view_point(const Vec3& p, const CameraSetup& cam) {
  VertexView vv;
  vv.q = p - cam.c;
  vv.norm = vv.q.norm();
  const double z = vv.q.dot(cam.axis);
  vv.in_front = z > kMargin * vv.norm;
  if (vv.in_front) {
    vv.x = vv.q.dot(cam.ex) / z;
    vv.y = vv.q.dot(cam.ey) / z;
  }
  return vv;
}

/// The vertices of cluster k's triangles not yet seen from the camera for this object
/// (work.vertex_stamp ≠ work.vertex_visit), each once: its offset, length and projection (the same
/// numbers per triangle corner as computed from the triangle).
void view_vertices(const ObjectInfo& info, const detail::TriangleCluster& k, const CameraSetup& cam,
                   SetupWork& work) {
  const core::TriangleMesh& mesh = *info.mesh;
  for (int n = k.begin; n < k.end; ++n) {
    for (int v : mesh.triangles[info.cluster_order[n]]) {
      if (work.vertex_stamp[v] == work.vertex_visit) continue;
      work.vertex_stamp[v] = work.vertex_visit;
      work.vertices[v] = view_point(mesh.vertices[v], cam);
    }
  }
}

/// A tilt of magnitude at most this is near edge-on: its sign may be a rounding's (L3). A culled
/// object's triangles tilted above it are its back faces without slots.
constexpr double kEdgeOn = 1e-9;

/// The camera's tilt against the plane of each triangle of cluster k (det / scale; 0 when the
/// camera lies in it, flat: the cone has no volume), into work.tilt and work.flat (with its
/// vertices' views); the least |tilt| of them (above kEdgeOn: every one clear of edge-on; above
/// 0: none flat).
double tilts(const ObjectInfo& info, const detail::TriangleCluster& k, const CameraSetup& cam,
             SetupWork& work) {
  view_vertices(info, k, cam, work);
  const core::TriangleMesh& mesh = *info.mesh;
  double least = std::numeric_limits<double>::infinity();
  for (int n = k.begin; n < k.end; ++n) {
    const int i = info.cluster_order[n];
    const auto& tv = mesh.triangles[i];
    const VertexView &a = work.vertices[tv[0]], &b = work.vertices[tv[1]],
                     &e = work.vertices[tv[2]];
    const double det = a.q.dot(b.q.cross(e.q));
    const double scale = a.norm * b.norm * e.norm;
    work.flat[i] = !(std::abs(det) > 1e-12 * scale);
    work.tilt[i] = work.flat[i] ? 0.0 : det / scale;
    least = std::min(least, std::abs(work.tilt[i]));
  }
  return least;
}

/// How every triangle of a cluster faces the camera (facing_cluster).
constexpr std::uint8_t kMixed = 0, kBehind = 1, kInFront = 2;

/// kBehind when the camera at c lies behind the plane of every triangle of cluster k, kInFront
/// when in front of every one, each tilt (as tilts() computes it) of magnitude above 1e-9, proven
/// from the cluster's bounds; else kMixed. For a triangle with unit normal n (within the
/// cluster's normal cone), |cross| ≥ min_cross, corner a in the ball (m, R):
/// det = (a − c)·cross, ±n·(a − c) ≥ |m − c| cos(φ + θ) − R (φ: the angle of m − c to the cone's
/// axis, turned by ±, θ the cone's half angle), and scale ≤ (|m − c| + R)³. The bound asks 4
/// times the threshold: far above the rounding of either.
std::uint8_t facing_cluster(const detail::TriangleCluster& k, const Vec3& c) {
  if (!(k.normal_cos > 0.0) || !(k.min_cross > 0.0)) return kMixed;
  const Vec3 v = k.ball.center - c;
  const double dist = v.norm();
  if (!(dist > k.ball.radius)) return kMixed;
  const double cos_phi = std::clamp(k.normal_axis.dot(v) / dist, -1.0, 1.0);
  const double sin_phi = std::sqrt(1.0 - cos_phi * cos_phi);
  const double sin_theta = std::sqrt(1.0 - k.normal_cos * k.normal_cos);
  const double far = dist + k.ball.radius;
  const double needed = 4e-9 * far * far * far / k.min_cross;
  for (const double sign : {1.0, -1.0}) {
    const double plane =
        dist * (sign * cos_phi * k.normal_cos - sin_phi * sin_theta) - k.ball.radius;
    if (plane > 0.0 && plane > needed) return sign > 0 ? kBehind : kInFront;
  }
  return kMixed;
}

/// Whether the object's back faces are culled (both modes; docs/design/labelling.md L3), with
/// how its triangles face the camera: down the object's tree, a node whose bounds prove how all
/// its triangles face the camera (facing_cluster: each tilt of magnitude above 1e-9, so none
/// flat or near edge-on) stops the descent (work.node_facing), and the clusters reached unproven
/// get the tilts of their triangles (tilts(), into work). det > 0 means the camera is behind the
/// triangle's plane. An object is culled only when it is oriented outward, the camera is outside
/// it and clear of its surface, and no triangle is near edge-on, or, with `edge_on_kept`
/// (conservative mode, an occupying object), none is flat: its near edge-on triangles then stay
/// slots, whichever side they face (a fine mesh nearly always has some along its outline). A near
/// miss of a culled object's front face makes judge_conservative() test its back faces too. The
/// surface's clearance is measured per triangle only when the bounding sphere does not prove it
/// (a sphere gap of twice the bound leaves room for any rounding of either).
bool cull_back_faces(const ObjectInfo& info, bool camera_inside, bool edge_on_kept,
                     const Triangles& triangles, const CameraSetup& cam, SetupWork& work) {
  const Vec3& c = cam.c;
  const int n = info.triangle_count;
  // Grown, never shrunk: the objects, of all sizes, share this memory, and shrinking it for a
  // small object cleared it all again for the next large one, per camera (bench/scale_bench,
  // robot family of 100k triangles: 6 % of an evaluation in memset, perf).
  if (work.tilt.size() < static_cast<std::size_t>(n)) {
    work.tilt.resize(n);
    work.flat.resize(n);
  }
  const std::size_t vertex_count = info.mesh->vertices.size();
  if (work.vertices.size() < vertex_count) {
    work.vertices.resize(vertex_count);
    work.vertex_stamp.resize(vertex_count, 0);
  }
  if (++work.vertex_visit == 0) {
    std::fill(work.vertex_stamp.begin(), work.vertex_stamp.end(), 0);
    work.vertex_visit = 1;
  }
  work.node_facing.assign(info.nodes.size(), kMixed);
  double least_tilt = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < info.nodes.size();) {
    const detail::ClusterNode& node = info.nodes[i];
    const std::uint8_t f = facing_cluster(node.bounds, c);
    if (f != kMixed) {
      work.node_facing[i] = f;
      i = node.next;
      continue;
    }
    if (node.cluster_end - node.cluster_begin == 1) {
      least_tilt = std::min(least_tilt, tilts(info, info.clusters[node.cluster_begin], cam, work));
    }
    ++i;
  }
  const bool clear_tilts = least_tilt > (edge_on_kept ? 0.0 : kEdgeOn);
  if (!(info.outward && !camera_inside && clear_tilts)) return false;
  const double scale = (info.center - c).norm() + info.radius;
  if ((info.center - c).norm() - info.radius > 2e-9 * scale) return true;
  double clearance = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) {
    const auto& tri = triangles[info.first_triangle + i];
    clearance =
        std::min(clearance, std::sqrt(core::point_triangle_sq_distance(c, tri[0], tri[1], tri[2])));
  }
  return clearance > 1e-9 * scale;
}

/// Slot s's projection from its triangle's corners seen from the camera: its rectangle
/// (padded) and, in center mode, its edge lines (padded like the rectangle; invalid for a nearly
/// degenerate projection). False when the rectangle lies outside the FOV's section: no box or ray
/// the labeller tests projects onto it (the triangle is no slot).
bool project_slot(const VertexView* const v[3], const CameraSetup& cam, bool conservative, int s) {
  const double xlo = std::min({v[0]->x, v[1]->x, v[2]->x});
  const double xhi = std::max({v[0]->x, v[1]->x, v[2]->x});
  const double ylo = std::min({v[0]->y, v[1]->y, v[2]->y});
  const double yhi = std::max({v[0]->y, v[1]->y, v[2]->y});
  const double pad_x = 2 * kMargin * (1.0 + std::max(std::abs(xlo), std::abs(xhi)));
  const double pad_y = 2 * kMargin * (1.0 + std::max(std::abs(ylo), std::abs(yhi)));
  const std::array<double, 4> r{xlo - pad_x, xhi + pad_x, ylo - pad_y, yhi + pad_y};
  if (r[1] < cam.view[0] || r[0] > cam.view[1] || r[3] < cam.view[2] || r[2] > cam.view[3]) {
    return false;
  }
  cam.rect[s] = r;
  if (conservative) return true;
  detail::EdgeLines& lines = cam.lines[s];
  const double px[3] = {v[0]->x, v[1]->x, v[2]->x}, py[3] = {v[0]->y, v[1]->y, v[2]->y};
  const double area = (px[1] - px[0]) * (py[2] - py[0]) - (py[1] - py[0]) * (px[2] - px[0]);
  const double size = std::max(xhi - xlo, yhi - ylo);
  lines.valid = std::abs(area) > 1e-9 * size * size;
  if (!lines.valid) return true;
  const double pad = std::max(pad_x, pad_y);
  for (int ed = 0; ed < 3; ++ed) {
    const int f = (ed + 1) % 3;
    double la = -(py[f] - py[ed]), lb = px[f] - px[ed];
    if (area < 0) {
      la = -la;
      lb = -lb;
    }
    const double norm = std::sqrt(la * la + lb * lb);
    la /= norm;
    lb /= norm;
    lines.line[ed] = {la, lb, -(la * px[ed] + lb * py[ed]) + pad};
  }
  return true;
}

/// A rectangle (padded) of image coordinates holding the projection of every point of the ball,
/// padded twice as much as a slot's: it holds the rectangle of each triangle inside; or nothing
/// when the ball is not wholly in front of the camera, every vertex inside clearly passing
/// VertexView's in_front test.
std::optional<std::array<double, 4>> ball_rectangle(const detail::Ball& ball,
                                                    const CameraSetup& cam) {
  const Vec3 v = ball.center - cam.c;
  const double z = v.dot(cam.axis), r = ball.radius;
  if (!(z - r > 4 * kMargin * (v.norm() + r))) return std::nullopt;
  auto p = detail::box_projection(v.dot(cam.ex), v.dot(cam.ey), z, r, r, r);
  const double pad_x = 4 * kMargin * (1.0 + std::max(std::abs(p[0]), std::abs(p[1])));
  const double pad_y = 4 * kMargin * (1.0 + std::max(std::abs(p[2]), std::abs(p[3])));
  return std::array<double, 4>{p[0] - pad_x, p[1] + pad_x, p[2] - pad_y, p[3] + pad_y};
}

/// Whether the rectangle r (x0, x1, y0, y1) misses the FOV's section.
bool outside_view(const std::array<double, 4>& r, const CameraSetup& cam) {
  return r[1] < cam.view[0] || r[0] > cam.view[1] || r[3] < cam.view[2] || r[2] > cam.view[3];
}

/// The slots of object o: its triangles that can decide a label (not culled back faces; in
/// conservative mode not flat; projecting into the FOV's section or not wholly in front of the
/// camera), cluster by cluster (ObjectInfo::clusters), with their padded rectangles and, in center
/// mode, edge lines. Per cluster, its slots wholly in front of the camera form a group (binned),
/// then come the others (candidates everywhere). A cluster proven to face the camera one way
/// (work.node_facing, at it or a node above; none of its triangles flat), unless its triangles
/// are culled back faces, whose ball lies in front of the camera is a group of all its triangles,
/// projected on first use (project_group); one whose rectangle misses the FOV's section has no
/// slot. The walk of the object's tree skips a subtree of culled back faces (no slots), or a
/// proven subtree whose ball lies in front of the camera and whose rectangle misses the FOV's
/// section: that rectangle holds every cluster's rectangle and every triangle's inside the ball
/// (L10), so none of them has a slot.
void add_slots(int o, const ObjectInfo& info, bool cull, bool conservative, CameraSetup& cam,
               SetupWork& work) {
  const double inf = std::numeric_limits<double>::infinity();
  const core::TriangleMesh& mesh = *info.mesh;
  auto add_slot = [&](int t) {
    cam.slot_triangle[cam.slot_count] = t;
    cam.slot_object[cam.slot_count] = o;
    return cam.slot_count++;
  };
  // Cluster k's slots, the cluster facing the camera as `facing` says (kMixed: unproven; not
  // culled back faces).
  auto cluster_slots = [&](int k, std::uint8_t facing) {
    const detail::TriangleCluster& cluster = info.clusters[k];
    const double near = detail::nearest_in_ball(cluster.ball, cam.c);
    if (facing != kMixed) {
      const auto rect = ball_rectangle(cluster.ball, cam);
      if (rect) {
        const auto& r = *rect;
        if (outside_view(r, cam)) return;  // neither is any of its triangles'
        // Its slots are written when it is projected (fill_group).
        const int first = cam.slot_count;
        cam.slot_count += cluster.end - cluster.begin;
        work.group_projected.push_back(0);
        cam.groups.push_back({first, cam.slot_count, r, near, o, k, k});
        return;
      }
      // Its triangles one by one: their tilts and views (none flat; back faces only when the
      // object is not culled).
      tilts(info, cluster, cam, work);
    }
    work.deferred.clear();
    const int first = cam.slot_count;
    std::array<double, 4> group_rect{inf, -inf, inf, -inf};
    for (int n = cluster.begin; n < cluster.end; ++n) {
      const int i = info.cluster_order[n];
      const int t = info.first_triangle + i;
      if (cull && work.tilt[i] > kEdgeOn) continue;  // a back face (detail::back_face)
      if (conservative && work.flat[i]) continue;
      const auto& tv = mesh.triangles[i];
      const VertexView* v[3] = {&work.vertices[tv[0]], &work.vertices[tv[1]],
                                &work.vertices[tv[2]]};
      if (!(v[0]->in_front && v[1]->in_front && v[2]->in_front)) {
        work.deferred.push_back(t);
        continue;
      }
      const int s = cam.slot_count;
      if (!project_slot(v, cam, conservative, s)) continue;
      add_slot(t);
      const auto& r = cam.rect[s];
      group_rect = {std::min(group_rect[0], r[0]), std::max(group_rect[1], r[1]),
                    std::min(group_rect[2], r[2]), std::max(group_rect[3], r[3])};
    }
    const int last = cam.slot_count;
    if (last > first) {
      work.group_projected.push_back(1);
      cam.groups.push_back({first, last, group_rect, near, o, -1, k});
    }
    // Not wholly in front of the camera: a candidate everywhere.
    for (int t : work.deferred) {
      const int s = add_slot(t);
      cam.everywhere.push_back(s);
      cam.rect[s] = {-inf, inf, -inf, inf};
      if (!conservative) cam.lines[s].valid = false;
    }
  };
  // Pre-order: the nodes before proven_end lie below the proven node `proven` (facing it says).
  int proven_end = 0;
  std::uint8_t proven = kMixed;
  for (int i = 0; i < static_cast<int>(info.nodes.size());) {
    const detail::ClusterNode& node = info.nodes[i];
    const bool leaf = node.cluster_end - node.cluster_begin == 1;
    if (i >= proven_end && work.node_facing[i] != kMixed) {
      proven = work.node_facing[i];
      proven_end = node.next;
    }
    const std::uint8_t facing = i < proven_end ? proven : kMixed;
    if (cull && facing == kBehind) {
      i = node.next;  // back faces all (facing_cluster): no slots
      continue;
    }
    if (facing != kMixed && !leaf) {
      const auto rect = ball_rectangle(node.bounds.ball, cam);
      i = rect && outside_view(*rect, cam) ? node.next : i + 1;
      continue;
    }
    if (leaf) cluster_slots(node.cluster_begin, facing);
    ++i;
  }
}

/// The bins: they cover the slot groups' (padded) rectangles within the FOV's section, at bin
/// width `width`, finer where a chunk has more groups than a few per bin (`per_chunk`: the groups
/// of the chunk that has most), so that the candidates per voxel stay bounded as meshes get finer.
/// A box or ray whose projection misses that rectangle has no binned candidate
/// (detail::outside_bins). Conservative mode: wide bins twice as fine with every rectangle
/// widened by half a coarse bin, so that a box whose projection is at most one coarse bin wide
/// finds every group it can meet in the bin of its rectangle's centre, each once (no repeats to
/// skip); the bins then hold bundles of groups (make_bundles), with the bundles' rectangles.
/// Then, in center mode, each group's bin range, into work.bins.
void place_bins(const std::array<double, 2>& width, int per_chunk, bool conservative,
                CameraSetup& cam, SetupWork& work) {
  const double inf = std::numeric_limits<double>::infinity();
  std::array<double, 2> lo{inf, inf}, hi{-inf, -inf};
  for (const detail::SlotGroup& g : cam.groups) {
    const auto& r = g.rect;
    lo = {std::min(lo[0], r[0]), std::min(lo[1], r[2])};
    hi = {std::max(hi[0], r[1]), std::max(hi[1], r[3])};
  }
  for (int a = 0; a < 2; ++a) {
    lo[a] = std::max(lo[a], cam.view[2 * a]);
    hi[a] = std::min(hi[a], cam.view[2 * a + 1]);
    if (!(lo[a] < hi[a])) lo[a] = hi[a] = 0.0;
  }
  constexpr int kMaxBins = 1024;
  std::array<double, 2> w = width;
  cam.coarse = grid_over(lo, hi, w, kMaxBins);
  const double wanted = conservative
                            ? std::min(per_chunk / kConservativePerBin, kConservativeMaxBins)
                            : std::min(per_chunk / kCenterPerBin, kCenterMaxBins);
  if (cam.coarse.count() < wanted) {
    const double f = std::sqrt(wanted / cam.coarse.count());
    w = {width[0] / f, width[1] / f};
    cam.coarse = grid_over(lo, hi, w, kMaxBins);
  }
  for (int a = 0; a < 2; ++a) cam.widen[a] = 0.5 * w[a];
  cam.wide = conservative ? grid_over({lo[0] - cam.widen[0], lo[1] - cam.widen[1]},
                                      {hi[0] + cam.widen[0], hi[1] + cam.widen[1]},
                                      {0.5 * w[0], 0.5 * w[1]}, 2 * kMaxBins)
                          : BinGrid{};
  if (conservative) return;
  work.bins.resize(cam.groups.size());
  for (std::size_t g = 0; g < cam.groups.size(); ++g) {
    const auto& r = cam.groups[g].rect;
    work.bins[g].coarse = detail::bins_under(cam.coarse, r[0], r[1], r[2], r[3]);
  }
}

/// Slot groups per bundle at most (make_bundles): copies in this many consecutive time steps,
/// whose states then lie close together in the chunk's bits; and how much wider and higher than
/// its first group's rectangle a bundle's may grow. Choices: 16 measured side by side against 4,
/// 8 and 64 (bench/scale_bench, 384 distinct states, conservative: the fastest, 64 within noise
/// of it); the growth not measured against others.
constexpr int kBundle = 16;
/// Center mode bundles a chunk's groups only when its states span at least this many time steps
/// (chosen, not tuned: the paper's 2 steps, as in the robot family, do not pay; 8 steps do).
constexpr int kCenterBundleSteps = 4;
constexpr double kBundleGrowth = 1.5;

/// Sorts `keys` (distinct) ascending, into the order std::sort gives, by merging its ascending
/// runs pairwise (`buffer`, `runs`: working memory): make_bundles' keys come object by object,
/// each object's groups in cluster order, so the runs are few (about one per time step) and the
/// sort takes time proportional to the groups, where std::sort took a third of an evaluation's
/// set-up on fine meshes (bench/scale_bench, robot family of 100k triangles, callgrind).
void sort_runs(std::vector<std::array<int, 3>>& keys, std::vector<std::array<int, 3>>& buffer,
               std::vector<std::size_t>& runs) {
  runs.clear();
  runs.push_back(0);
  for (std::size_t n = 1; n < keys.size(); ++n) {
    if (keys[n] < keys[n - 1]) runs.push_back(n);
  }
  runs.push_back(keys.size());
  buffer.resize(keys.size());
  while (runs.size() > 2) {
    // Runs 2i and 2i + 1 into one; the last run alone is copied.
    std::size_t kept = 0;
    for (std::size_t r = 0; r + 1 < runs.size(); r += 2) {
      const auto begin = keys.begin() + static_cast<std::ptrdiff_t>(runs[r]);
      const auto middle = keys.begin() + static_cast<std::ptrdiff_t>(runs[r + 1]);
      const auto end =
          r + 2 < runs.size() ? keys.begin() + static_cast<std::ptrdiff_t>(runs[r + 2]) : middle;
      std::merge(begin, middle, middle, end, buffer.begin() + static_cast<std::ptrdiff_t>(runs[r]));
      runs[kept++] = runs[r];
    }
    runs[kept++] = keys.size();
    runs.resize(kept);
    keys.swap(buffer);
  }
}

/// Conservative mode: the chunk's slot groups (`members`, ascending) in bundles
/// (detail::SlotBundle) into out.bundles and out.bundle_groups, and each bundle's bins into
/// work.bundle_bins: the groups sorted by their object's family, their cluster and their index
/// (the same cluster of copies of a mesh, time step by time step), and each run of one family
/// and cluster cut into bundles of at most kBundle groups whose rectangles stay within
/// kBundleGrowth times the first one's width and height. Any bundling gives the same labels: a
/// bundle's bounds hold each of its groups'.
void make_bundles(const CameraSetup& cam, const std::vector<ObjectInfo>& objects,
                  const detail::StateMask* object_states, SetupWork& work, ChunkCandidates& out) {
  const double inf = std::numeric_limits<double>::infinity();
  work.keyed.clear();
  for (int g : work.members) {
    work.keyed.push_back({objects[cam.groups[g].object].family, cam.groups[g].source, g});
  }
  sort_runs(work.keyed, work.keyed_buffer, work.runs);
  out.bundles.clear();
  out.bundle_groups.clear();
  work.bundle_bins.clear();
  for (std::size_t n = 0; n < work.keyed.size();) {
    detail::SlotBundle bundle;
    bundle.rect = cam.groups[work.keyed[n][2]].rect;
    bundle.near = inf;
    bundle.first = static_cast<int>(out.bundle_groups.size());
    const double max_x = kBundleGrowth * (bundle.rect[1] - bundle.rect[0]);
    const double max_y = kBundleGrowth * (bundle.rect[3] - bundle.rect[2]);
    const std::size_t begin = n;
    for (; n < work.keyed.size() && n - begin < static_cast<std::size_t>(kBundle) &&
           work.keyed[n][0] == work.keyed[begin][0] && work.keyed[n][1] == work.keyed[begin][1];
         ++n) {
      const detail::SlotGroup& group = cam.groups[work.keyed[n][2]];
      const auto& r = group.rect;
      const std::array<double, 4> grown{
          std::min(bundle.rect[0], r[0]), std::max(bundle.rect[1], r[1]),
          std::min(bundle.rect[2], r[2]), std::max(bundle.rect[3], r[3])};
      if (n > begin && !(grown[1] - grown[0] <= max_x && grown[3] - grown[2] <= max_y)) break;
      bundle.rect = grown;
      bundle.near = std::min(bundle.near, group.near);
      bundle.states |= object_states[group.object];
      bundle.occupying = objects[group.object].occupying;
      out.bundle_groups.push_back(work.keyed[n][2]);
    }
    bundle.last = static_cast<int>(out.bundle_groups.size());
    out.bundles.push_back(bundle);
    const auto& r = bundle.rect;
    work.bundle_bins.push_back(
        {detail::bins_under(cam.coarse, r[0], r[1], r[2], r[3]),
         detail::bins_under(cam.wide, r[0] - cam.widen[0], r[1] + cam.widen[0], r[2] - cam.widen[1],
                            r[3] + cam.widen[1])});
  }
}

/// One chunk's candidates: the slot groups of its objects (`objects`, ascending), sorted into the
/// bins (center mode) or in bundles sorted into the bins (conservative mode, make_bundles), and
/// their slots not wholly in front of the camera in `everywhere`. Only the chunk's own groups are
/// visited: with many states, each chunk holds few of the objects.
void chunk_candidates(const CameraSetup& cam, const std::vector<int>& objects,
                      const std::vector<ObjectInfo>& infos, const detail::StateMask* object_states,
                      bool conservative, bool bundled, SetupWork& work, ChunkCandidates& out) {
  work.members.clear();
  out.everywhere.clear();
  for (int o : objects) {
    for (int g = cam.object_groups[o]; g < cam.object_groups[o + 1]; ++g) work.members.push_back(g);
    out.everywhere.insert(out.everywhere.end(), cam.everywhere.begin() + cam.everywhere_start[o],
                          cam.everywhere.begin() + cam.everywhere_start[o + 1]);
  }
  if (conservative) {
    make_bundles(cam, infos, object_states, work, out);
    work.bundle_ids.resize(out.bundles.size());
    for (std::size_t b = 0; b < out.bundles.size(); ++b) work.bundle_ids[b] = static_cast<int>(b);
    sort_into_bins(
        cam.coarse, work.bundle_ids,
        [&](int b) -> const BinRange& { return work.bundle_bins[b].coarse; }, work.fill,
        out.coarse);
    sort_into_bins(
        cam.wide, work.bundle_ids,
        [&](int b) -> const BinRange& { return work.bundle_bins[b].wide; }, work.fill, out.wide);
    return;
  }
  out.wide.start.assign(cam.wide.count() + 1, 0);
  out.wide.items.clear();
  if (!bundled) {
    out.bundles.clear();
    out.bundle_groups.clear();
    sort_into_bins(
        cam.coarse, work.members, [&](int g) -> const BinRange& { return work.bins[g].coarse; },
        work.fill, out.coarse);
    return;
  }
  // Center mode with many time steps: bundles in the coarse bins too (judge_center tests a
  // bundle's rectangle and states first).
  make_bundles(cam, infos, object_states, work, out);
  work.bundle_ids.resize(out.bundles.size());
  for (std::size_t b = 0; b < out.bundles.size(); ++b) work.bundle_ids[b] = static_cast<int>(b);
  sort_into_bins(
      cam.coarse, work.bundle_ids,
      [&](int b) -> const BinRange& { return work.bundle_bins[b].coarse; }, work.fill, out.coarse);
}

}  // namespace

void VoxelEvaluator::Impl::project_group(const CameraSetup& cam, int g) const {
  std::atomic<std::uint8_t>& state = cam.group_state[g];
  std::uint8_t expected = detail::kConeMissing;
  if (!state.compare_exchange_strong(expected, detail::kConeMaking, std::memory_order_acq_rel)) {
    while (state.load(std::memory_order_acquire) != detail::kConeReady) std::this_thread::yield();
    return;
  }
  // The numbers add_slots computes from the vertices' views (cluster_corners holds the same
  // vertices), of triangles that lie wholly in front of the camera (ball_rectangle) and face it.
  // Only a group of all of a cluster's triangles is projected here (the others at set-up).
  const double inf = std::numeric_limits<double>::infinity();
  const detail::SlotGroup& group = cam.groups[g];
  if (group.cluster >= 0) fill_group(cam, group);
  const detail::ObjectInfo& info = objects[group.object];
  const auto* corners = &info.cluster_corners[info.clusters[group.source].begin];
  for (int s = group.first; s < group.last; ++s) {
    const auto& tri = corners[s - group.first];
    const VertexView views[3] = {view_point(tri[0], cam), view_point(tri[1], cam),
                                 view_point(tri[2], cam)};
    CAMPLACE_ASSERT(views[0].in_front && views[1].in_front && views[2].in_front);
    const VertexView* const v[3] = {&views[0], &views[1], &views[2]};
    // Outside the FOV's section: an empty rectangle, which no box's meets.
    if (!project_slot(v, cam, conservative, s)) cam.rect[s] = {inf, -inf, inf, -inf};
  }
  state.store(detail::kConeReady, std::memory_order_release);
}

void VoxelEvaluator::Impl::fill_group(const CameraSetup& cam,
                                      const detail::SlotGroup& group) const {
  for (int s = group.first; s < group.last; ++s) {
    cam.slot_triangle[s] = group_triangle(cam, group, s);
    cam.slot_object[s] = group.object;
    if (conservative) cam.cone_state[s].store(detail::kConeMissing, std::memory_order_relaxed);
  }
}

const TriangleCone& VoxelEvaluator::Impl::make_cone_of(const CameraSetup& cam, int slot) const {
  std::atomic<std::uint8_t>& state = cam.cone_state[slot];
  std::uint8_t expected = detail::kConeMissing;
  if (state.compare_exchange_strong(expected, detail::kConeMaking, std::memory_order_acq_rel)) {
    make_cone(cam.slot_triangle[slot], cam.c, cam.cones[slot]);
    state.store(detail::kConeReady, std::memory_order_release);
  } else {
    while (state.load(std::memory_order_acquire) != detail::kConeReady) std::this_thread::yield();
  }
  return cam.cones[slot];
}

void VoxelEvaluator::Impl::make_cone(int t, const Vec3& c, TriangleCone& tc) const {
  const auto& tri = triangles[t];
  const Vec3 a = tri[0] - c, b = tri[1] - c, e = tri[2] - c;
  const double det = a.dot(b.cross(e));
  // Read only for an occluding object's triangle (one wholly beyond a box does not block it); an
  // occupying object's cone is tested on every ray through the box, so it gets no distance.
  tc.near_distance = objects[triangle_object[t]].occupying
                         ? 0.0
                         : std::sqrt(core::point_triangle_sq_distance(c, tri[0], tri[1], tri[2]));
  const double sign = det > 0 ? 1.0 : -1.0;
  const Vec3 edge[3] = {a, b, e};
  tc.normal[0] = (sign * a.cross(b)).normalized();
  tc.normal[1] = (sign * b.cross(e)).normalized();
  tc.normal[2] = (sign * e.cross(a)).normalized();
  // The voxel-independent part of the separating-axis test (the edges' projections), once per
  // camera: the axes on one side of which the cone lies, turned toward it.
  tc.axis_count = 0;
  auto add_axis = [&](const Vec3& axis) {
    const double pa = axis.dot(edge[0]), pb = axis.dot(edge[1]), pc = axis.dot(edge[2]);
    if (pa >= 0.0 && pb >= 0.0 && pc >= 0.0) {
      tc.axes[tc.axis_count++] = axis;
    } else if (pa <= 0.0 && pb <= 0.0 && pc <= 0.0) {
      tc.axes[tc.axis_count++] = -axis;
    }
  };
  for (int i = 0; i < 3; ++i) add_axis(Vec3::Unit(i));
  for (const Vec3& ed : edge) {
    for (int i = 0; i < 3; ++i) add_axis(ed.cross(Vec3::Unit(i)));
  }
}

void VoxelEvaluator::Impl::camera_setup(const core::CameraSetting& camera,
                                        const core::CameraModel& model, CameraSetup& cam) const {
  thread_local SetupWork work;
  // Center mode looks up one bin per voxel: fine bins. Conservative mode looks up the bins under
  // the box's projection and then each slot's rectangle: coarse bins (fewer repeats).
  const int n_max = *std::max_element(grid.n.begin(), grid.n.end());
  const int bins = conservative ? std::clamp(n_max / 3, 8, 32) : std::clamp(n_max, 16, 64);
  const std::array<double, 2> width = camera_frame(camera, model, half_step, bins, cam);
  objects_holding(objects, cam.c, cam.inside_object);
  cam.culled.assign(objects.size(), 0);
  // At most one slot per triangle.
  cam.slot_count = 0;
  if (cam.slot_triangle.size() < triangles.size()) {
    cam.slot_triangle.resize(triangles.size());
    cam.slot_object.resize(triangles.size());
  }
  // Written per slot (at most one per triangle), projected groups on first use.
  if (cam.rect.size() < triangles.size()) cam.rect.resize(triangles.size());
  if (!conservative && cam.lines.size() < triangles.size()) cam.lines.resize(triangles.size());
  cam.groups.clear();
  work.group_projected.clear();
  cam.everywhere.clear();
  cam.object_groups.assign(objects.size() + 1, 0);
  cam.everywhere_start.assign(objects.size() + 1, 0);
  for (std::size_t o = 0; o < objects.size(); ++o) {
    cam.object_groups[o] = static_cast<int>(cam.groups.size());
    cam.everywhere_start[o] = static_cast<int>(cam.everywhere.size());
    const bool cull = cull_back_faces(objects[o], cam.inside_object[o],
                                      conservative && objects[o].occupying, triangles, cam, work);
    cam.culled[o] = cull;
    add_slots(static_cast<int>(o), objects[o], cull, conservative, cam, work);
  }
  cam.object_groups[objects.size()] = static_cast<int>(cam.groups.size());
  cam.everywhere_start[objects.size()] = static_cast<int>(cam.everywhere.size());
  const std::size_t groups = cam.groups.size();
  if (cam.group_capacity < groups) {
    cam.group_capacity = std::max(groups, 2 * cam.group_capacity);
    cam.group_state.reset(new std::atomic<std::uint8_t>[cam.group_capacity]);
    // (In both modes: a thread's CameraSetup serves evaluators of either mode.)
    cam.group_rays.reset(new std::atomic<std::uint8_t>[cam.group_capacity]);
  }
  for (std::size_t g = 0; g < groups; ++g) {
    cam.group_state[g].store(work.group_projected[g] ? detail::kConeReady : detail::kConeMissing,
                             std::memory_order_relaxed);
    if (!conservative) cam.group_rays[g].store(0, std::memory_order_relaxed);
  }
  cam.direct_rays =
      static_cast<long>(groups) * detail::kRaysPerGroup > grid.count() ? detail::kDirectRays : 0;
  if (conservative) {
    // The cones are made on first use (cone_of): a fine mesh has many slots that no box tests.
    const std::size_t slots = cam.slot_count;
    if (cam.cone_capacity < slots) {
      cam.cone_capacity = std::max(slots, 2 * cam.cone_capacity);
      cam.cones.reset(new TriangleCone[cam.cone_capacity]);  // uninitialised: no page touched
      cam.cone_state.reset(new std::atomic<std::uint8_t>[cam.cone_capacity]);
    }
    // Few slots for many boxes (a coarse mesh): each cone serves many tests, made up front.
    if (slots * 8 <= static_cast<std::size_t>(grid.count())) {
      for (detail::SlotGroup& group : cam.groups) {
        if (group.cluster >= 0) fill_group(cam, group);
        group.cluster = -1;
      }
      for (std::size_t s = 0; s < slots; ++s) {
        make_cone(cam.slot_triangle[s], cam.c, cam.cones[s]);
        cam.cone_state[s].store(detail::kConeReady, std::memory_order_relaxed);
      }
    } else {
      // The slots written now; a group of a cluster's when it is projected (fill_group).
      for (const detail::SlotGroup& group : cam.groups) {
        if (group.cluster >= 0) continue;
        for (int s = group.first; s < group.last; ++s) {
          cam.cone_state[s].store(detail::kConeMissing, std::memory_order_relaxed);
        }
      }
      for (int s : cam.everywhere) {
        cam.cone_state[s].store(detail::kConeMissing, std::memory_order_relaxed);
      }
    }
  }
  // The slot groups of the chunk that has most (an object may belong to several chunks).
  int per_chunk = 0;
  for (const std::vector<int>& chunk : chunk_objects) {
    int count = 0;
    for (int o : chunk) count += cam.object_groups[o + 1] - cam.object_groups[o];
    per_chunk = std::max(per_chunk, count);
  }
  place_bins(width, per_chunk, conservative, cam, work);
  cam.chunks.resize(chunk_object_states.size());
  for (std::size_t ch = 0; ch < chunk_object_states.size(); ++ch) {
    // Center mode bundles the copies of a mesh only when the chunk has states in enough time
    // steps for bundles of several groups (with the paper's 2, sorting them cost more than they
    // saved: bench/scale_bench, robot family of 10k triangles, +5 % instructions).
    int steps = 0;
    for (const detail::StateMask m : chunk_step_states[ch]) steps += m != 0;
    const bool bundled = conservative || steps >= kCenterBundleSteps;
    chunk_candidates(cam, chunk_objects[ch], objects, chunk_object_states[ch].data(), conservative,
                     bundled, work, cam.chunks[ch]);
  }
}

}  // namespace camplace::voxel
