// Mesh repair: CGAL alpha wrap and convex hull (compile cost: the wrap's Delaunay code is here
// alone).
#include "mesh_repair.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/alpha_wrap_3.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "camplace/core/error.hpp"
#include "camplace/core/json_reader.hpp"
#include "mesh_checks.hpp"

namespace camplace::core::detail {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;

Point point(const Vec3& v) { return Point(v.x(), v.y(), v.z()); }

TriangleMesh from_surface_mesh(const Mesh& sm) {
  TriangleMesh out;
  std::vector<int> index(sm.number_of_vertices() + sm.number_of_removed_vertices(), -1);
  for (const Mesh::Vertex_index v : sm.vertices()) {
    index[v] = static_cast<int>(out.vertices.size());
    const Point& p = sm.point(v);
    out.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  for (const Mesh::Face_index f : sm.faces()) {
    std::vector<int> corners;
    for (const Mesh::Vertex_index v : sm.vertices_around_face(sm.halfedge(f)))
      corners.push_back(index[v]);
    for (std::size_t k = 1; k + 1 < corners.size(); ++k)
      out.triangles.push_back({corners[0], corners[k], corners[k + 1]});
  }
  return out;
}

// Thrown by StopAfterSteinerPoints out of CGAL's flood fill (which has no other way to stop).
struct WrapTooLarge {};

// Bounds the wrap's work: every vertex of the wrap is a Steiner point, so a wrap that needs more
// Steiner points than the budget is abandoned as soon as it does.
struct StopAfterSteinerPoints : CGAL::Alpha_wraps_3::internal::Wrapping_default_visitor {
  std::size_t budget = 0;
  std::size_t inserted = 0;
  explicit StopAfterSteinerPoints(std::size_t b) : budget(b) {}
  template <typename Wrapper, typename VertexHandle>
  void after_Steiner_point_insertion(const Wrapper&, VertexHandle) {
    if (++inserted > budget) throw WrapTooLarge{};
  }
};

std::string method_name(RepairOptions::Method m) {
  switch (m) {
    case RepairOptions::Method::wrap:
      return "wrap";
    case RepairOptions::Method::hull:
      return "hull";
    case RepairOptions::Method::none:
      break;
  }
  return "none";
}

}  // namespace

std::optional<TriangleMesh> alpha_wrap(const TriangleMesh& mesh, double alpha, double offset,
                                       std::size_t max_steiner_points) {
  std::vector<Point> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) points.push_back(point(v));
  std::vector<std::array<std::size_t, 3>> faces;
  faces.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    faces.push_back({std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2])});
  Mesh wrap;
  StopAfterSteinerPoints stop{max_steiner_points};
  try {
    CGAL::alpha_wrap_3(points, faces, alpha, offset, wrap, CGAL::parameters::default_values(),
                       CGAL::parameters::visitor(stop));
  } catch (const WrapTooLarge&) {
    return std::nullopt;
  }
  return from_surface_mesh(wrap);
}

namespace {

std::size_t find_root(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Triangulates the convex polygon `ring` (points in the order of the face's outward
// orientation, possibly with collinear runs) by clipping ears, always the lexicographically
// smallest corner that is not collinear with its neighbours: the result depends on the
// polygon alone, not on where its vertices were listed from.
void clip_ears(std::vector<Mesh::Vertex_index> ring, const Mesh& hull,
               std::vector<std::array<Mesh::Vertex_index, 3>>& out) {
  while (ring.size() > 3) {
    std::size_t best = ring.size();
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const Point& prev = hull.point(ring[(i + ring.size() - 1) % ring.size()]);
      const Point& next = hull.point(ring[(i + 1) % ring.size()]);
      if (CGAL::collinear(prev, hull.point(ring[i]), next)) continue;
      if (best == ring.size() || hull.point(ring[i]) < hull.point(ring[best])) best = i;
    }
    CAMPLACE_ASSERT(best < ring.size());  // a polygon of positive area has convex corners
    out.push_back(
        {ring[(best + ring.size() - 1) % ring.size()], ring[best], ring[(best + 1) % ring.size()]});
    ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(best));
  }
  out.push_back({ring[0], ring[1], ring[2]});
}

// The hull as a TriangleMesh that depends on the hull's geometry alone. CGAL lists the hull's
// vertices, and splits its flat faces (4 or more coplanar vertices, as in every box) into
// triangles, in an order that follows memory addresses, which change with everything the
// process allocated before; the split of a flat face decides conservative labels. So the
// coplanar triangles of each face are merged into their polygon (exact coplanarity test), the
// polygon is triangulated by clip_ears, the vertices are sorted lexicographically and the
// triangles sorted.
TriangleMesh canonical_hull(const Mesh& hull) {
  std::vector<std::size_t> parent(hull.number_of_faces());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = i;
  for (const Mesh::Edge_index e : hull.edges()) {
    const Mesh::Halfedge_index h = hull.halfedge(e, 0), o = hull.opposite(h);
    if (CGAL::coplanar(hull.point(hull.source(h)), hull.point(hull.target(h)),
                       hull.point(hull.target(hull.next(h))),
                       hull.point(hull.target(hull.next(o))))) {
      parent[find_root(parent, hull.face(h).idx())] = find_root(parent, hull.face(o).idx());
    }
  }
  // Each merged face's boundary: its halfedges whose opposite lies in another face, chained
  // from source to target.
  std::vector<std::vector<Mesh::Halfedge_index>> boundary(parent.size());
  for (const Mesh::Halfedge_index h : hull.halfedges()) {
    const std::size_t f = find_root(parent, hull.face(h).idx());
    if (f != find_root(parent, hull.face(hull.opposite(h)).idx())) boundary[f].push_back(h);
  }
  std::vector<std::array<Mesh::Vertex_index, 3>> triangles;
  for (const std::vector<Mesh::Halfedge_index>& edges : boundary) {
    if (edges.empty()) continue;
    std::map<Mesh::Vertex_index, Mesh::Vertex_index> next;
    for (const Mesh::Halfedge_index h : edges) next[hull.source(h)] = hull.target(h);
    std::vector<Mesh::Vertex_index> ring{hull.source(edges.front())};
    while (ring.size() < edges.size()) ring.push_back(next.at(ring.back()));
    CAMPLACE_ASSERT(next.at(ring.back()) == ring.front());  // one convex polygon per face
    clip_ears(std::move(ring), hull, triangles);
  }
  std::vector<Mesh::Vertex_index> used;
  for (const auto& t : triangles) used.insert(used.end(), t.begin(), t.end());
  std::sort(used.begin(), used.end(), [&](Mesh::Vertex_index a, Mesh::Vertex_index b) {
    return hull.point(a) < hull.point(b);
  });
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::map<Mesh::Vertex_index, int> index;
  TriangleMesh out;
  for (const Mesh::Vertex_index v : used) {
    index[v] = static_cast<int>(out.vertices.size());
    const Point& p = hull.point(v);
    out.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  for (const auto& t : triangles) {
    std::array<int, 3> k{index.at(t[0]), index.at(t[1]), index.at(t[2])};
    // Smallest index first, the orientation kept.
    std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
    out.triangles.push_back(k);
  }
  std::sort(out.triangles.begin(), out.triangles.end());
  return out;
}

}  // namespace

std::optional<TriangleMesh> convex_hull(const TriangleMesh& mesh) {
  std::vector<Point> points;
  for (const Vec3& v : mesh.vertices) points.push_back(point(v));
  // convex_hull_3 gives a polygon or a segment for points of lower dimension: find four points
  // that span a volume first.
  std::size_t b = 1, c = 0, d = 0;
  while (b < points.size() && points[b] == points[0]) ++b;
  if (b >= points.size()) return std::nullopt;
  for (c = b + 1; c < points.size() && CGAL::collinear(points[0], points[b], points[c]); ++c) {
  }
  if (c >= points.size()) return std::nullopt;
  for (d = c + 1; d < points.size() && CGAL::coplanar(points[0], points[b], points[c], points[d]);
       ++d) {
  }
  if (d >= points.size()) return std::nullopt;
  Mesh hull;
  CGAL::convex_hull_3(points.begin(), points.end(), hull);
  return canonical_hull(hull);
}

RepairOptions parse_repair(const JsonNode& node) {
  RepairOptions options;
  auto method_of = [](const JsonNode& m) {
    const std::string name = m.string();
    if (name == "none") return RepairOptions::Method::none;
    if (name == "wrap") return RepairOptions::Method::wrap;
    if (name == "hull") return RepairOptions::Method::hull;
    m.fail("unknown repair method \"" + name + "\" (expected wrap, hull or none)");
  };
  if (node.is_string()) {
    options.method = method_of(node);
    return options;
  }
  if (!node.is_object()) {
    node.fail("repair must be \"wrap\", \"hull\", \"none\" or an object with a \"method\"");
  }
  node.only_keys({"method", "offset_m", "alpha_m", "max_triangles", "always"});
  options.method = method_of(node.at("method"));
  for (const char* key : {"offset_m", "alpha_m"}) {
    if (node.has(key) && options.method != RepairOptions::Method::wrap)
      node.at(key).fail(std::string("\"") + key + "\" applies only to \"method\": \"wrap\"");
  }
  // Upper bounds far beyond any cell (1 km); the lower bounds, relative to the mesh, are
  // checked when the mesh is known (finish_mesh).
  if (node.has("offset_m")) {
    const JsonNode o = node.at("offset_m");
    options.offset = o.number_in(0, 1000);
    if (!(options.offset > 0)) o.fail("offset_m must be positive");
  }
  if (node.has("alpha_m")) {
    const JsonNode a = node.at("alpha_m");
    options.alpha = a.number_in(0, 1000);
    if (!(options.alpha > 0)) a.fail("alpha_m must be positive");
  }
  if (node.has("max_triangles"))
    options.max_triangles = node.at("max_triangles").integer_in(4, kMaxRepairTriangles);
  if (node.has("always")) {
    const JsonNode a = node.at("always");
    if (!a.value().is_boolean()) a.fail("always must be true or false");
    options.always = a.value().get<bool>();
  }
  return options;
}

std::optional<MeshRepair> finish_mesh(TriangleMesh& mesh, const RepairOptions& repair,
                                      const std::string& file, const std::string& entry,
                                      const std::string& object_name) {
  auto fail = [&](const std::string& reason) { throw InputError(file, entry, reason); };
  const std::optional<MeshDefect> defect = check_and_orient(mesh);
  if (repair.method == RepairOptions::Method::none || (!defect && !repair.always)) {
    if (defect) fail(defect->reason + repair_hint(*defect));
    return std::nullopt;
  }
  if (defect && !defect->repairable) fail(defect->reason);
  const std::string method = method_name(repair.method);
  MeshRepair record;
  record.object = object_name;
  record.entry = entry;
  record.method = method;
  record.defect = defect ? defect->reason : "";
  record.triangles_before = static_cast<int>(mesh.triangles.size());
  TriangleMesh repaired;
  if (repair.method == RepairOptions::Method::wrap) {
    const Box3 box = bounding_box(mesh);
    const double diagonal = box.diagonal();
    if (!std::isfinite(diagonal) || !(diagonal > 0)) {
      fail("mesh cannot be wrapped: its bounding box has no finite, positive diagonal");
    }
    const double alpha = repair.alpha > 0 ? repair.alpha : diagonal / kDefaultRelativeAlpha;
    const double offset = repair.offset > 0 ? repair.offset : alpha / kDefaultAlphaPerOffset;
    if (alpha < diagonal / kMaxRelativeAlpha) {
      fail("repair alpha_m " + format_number(alpha) + " m is too small for this mesh: it must be " +
           "at least its bounding-box diagonal / " + format_number(kMaxRelativeAlpha) + " = " +
           format_number(diagonal / kMaxRelativeAlpha) +
           " m (the wrap's size grows as (diagonal / alpha)²)");
    }
    if (offset < alpha / kMaxAlphaPerOffset) {
      fail("repair offset_m " + format_number(offset) + " m is too small for alpha " +
           format_number(alpha) + " m: it must be at least alpha / " +
           format_number(kMaxAlphaPerOffset) + " = " + format_number(alpha / kMaxAlphaPerOffset) +
           " m (a tight offset multiplies the wrap's work)");
    }
    // A closed wrap with V vertices has about 2V triangles; its vertices are Steiner points,
    // so more than max_triangles Steiner points cannot end within the budget unless most of
    // them are carved away again: the wrap stops there (a bound on its work).
    std::optional<TriangleMesh> wrap =
        alpha_wrap(mesh, alpha, offset, static_cast<std::size_t>(repair.max_triangles));
    if (!wrap) {
      fail("mesh repaired by wrap" + std::string(defect ? " (" + defect->reason + ")" : "") +
           " needs more than max_triangles = " + std::to_string(repair.max_triangles) +
           " vertices, so more triangles than that; raise \"max_triangles\" or give a larger "
           "\"alpha_m\" in the repair object");
    }
    repaired = std::move(*wrap);
    record.offset = offset;
  } else {
    std::optional<TriangleMesh> hull = convex_hull(mesh);
    if (!hull) {
      fail("mesh cannot be repaired by hull: its vertices are coplanar, so the hull is flat; " +
           std::string("use \"repair\": \"wrap\" (docs/scene-format.md#repair)"));
    }
    repaired = std::move(*hull);
  }
  const std::string why = defect ? " (" + defect->reason + ")" : "";
  if (repaired.triangles.empty()) {
    fail("mesh cannot be repaired by " + method + why + ": the repair produced no triangles");
  }
  if (static_cast<int>(repaired.triangles.size()) > repair.max_triangles) {
    fail("mesh repaired by " + method + why + " has " + std::to_string(repaired.triangles.size()) +
         " triangles, more than max_triangles = " + std::to_string(repair.max_triangles) +
         (repair.method == RepairOptions::Method::wrap
              ? "; raise \"max_triangles\" or give a larger \"alpha_m\" in the repair object"
              : "; raise \"max_triangles\" in the repair object"));
  }
  if (const std::optional<MeshDefect> left = check_and_orient(repaired)) {
    fail("mesh repaired by " + method + why + " still fails the checks: " + left->reason);
  }
  record.triangles_after = static_cast<int>(repaired.triangles.size());
  mesh = std::move(repaired);
  return record;
}

}  // namespace camplace::core::detail
