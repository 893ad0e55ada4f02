// The one core translation unit with CGAL mesh processing (compile cost: keep it alone).
#include "mesh_checks.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <optional>
#include <vector>

#include "camplace/core/error.hpp"
#include "mesh_assimp.hpp"
#include "mesh_file_scan.hpp"

namespace camplace::core::detail {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

Mesh to_surface_mesh(const TriangleMesh& mesh) {
  std::vector<Point> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) points.emplace_back(v.x(), v.y(), v.z());
  std::vector<std::vector<std::size_t>> polygons;
  for (const auto& t : mesh.triangles)
    polygons.push_back({std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2])});
  Mesh out;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, out);
  return out;
}

// Volume enclosed by each connected component on its own (a flat component encloses none,
// whatever the other components do). Face f of `sm` is triangle f of the soup.
std::vector<double> component_volumes(Mesh& sm) {
  auto component = sm.add_property_map<Mesh::Face_index, std::size_t>("f:component").first;
  const std::size_t count = PMP::connected_components(sm, component);
  std::vector<double> volumes(count, 0.0);
  std::vector<std::optional<Point>> origins(count);
  for (const Mesh::Face_index f : sm.faces()) {
    const Mesh::Halfedge_index h = sm.halfedge(f);
    const Point& a = sm.point(sm.target(h));
    const Point& b = sm.point(sm.target(sm.next(h)));
    const Point& c = sm.point(sm.source(h));
    // Tetrahedra against a point of the component, not the world origin, to limit cancellation.
    std::optional<Point>& o = origins[component[f]];
    if (!o) o = a;
    volumes[component[f]] +=
        CGAL::scalar_product(a - *o, CGAL::cross_product(b - *o, c - *o)) / 6.0;
  }
  return volumes;
}

/// Removes vertices no triangle uses (they are not part of the solid, and CGAL's volume
/// tests fail on isolated vertices); indices are renumbered. The kept vertices keep their
/// order, so a mesh using all its vertices is left as it is (and the scene writer's output
/// loads back vertex for vertex).
void drop_unused_vertices(TriangleMesh& mesh) {
  std::vector<int> new_index(mesh.vertices.size(), -1);
  for (const auto& t : mesh.triangles) {
    for (const int idx : t) new_index[idx] = 0;
  }
  std::vector<Vec3> used;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (new_index[i] < 0) continue;
    new_index[i] = static_cast<int>(used.size());
    used.push_back(mesh.vertices[i]);
  }
  for (auto& t : mesh.triangles) {
    for (int& idx : t) idx = new_index[idx];
  }
  mesh.vertices = std::move(used);
}

}  // namespace

namespace {

// COLLADA is read y up by assimp (it applies <up_axis> and <unit> itself), glTF is y up by its
// specification; every other format is taken as written (z up).
bool file_is_y_up(const std::string& lower_ext) {
  return lower_ext == ".dae" || lower_ext == ".gltf" || lower_ext == ".glb";
}

TriangleMesh read_cgal_mesh_file(const std::string& path, const std::string& lower,
                                 const std::string& scene_file, const std::string& entry) {
  if (const std::optional<std::string> defect = mesh_file_defect(path, lower)) {
    throw InputError(scene_file, entry, "mesh file " + path + " cannot be read: " + *defect);
  }
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  bool ok = false;
  try {
    ok = CGAL::IO::read_polygon_soup(path, points, polygons, CGAL::parameters::verbose(false));
  } catch (const std::exception& e) {
    throw InputError(scene_file, entry, "mesh file " + path + " cannot be read: " + e.what());
  }
  if (!ok || points.empty() || polygons.empty()) {
    throw InputError(scene_file, entry, "mesh file " + path + " cannot be read as a mesh");
  }
  TriangleMesh mesh;
  for (const Point& p : points) mesh.vertices.emplace_back(p.x(), p.y(), p.z());
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    const auto& poly = polygons[f];
    if (poly.size() < 3) {
      throw InputError(
          scene_file, entry,
          "mesh file " + path + ": face " + std::to_string(f) + " has fewer than 3 vertices");
    }
    for (std::size_t idx : poly) {
      if (idx >= points.size()) {
        throw InputError(
            scene_file, entry,
            "mesh file " + path + ": face " + std::to_string(f) + " uses a vertex out of range");
      }
    }
    // Polygons are fanned from their first vertex; a non-convex polygon then fails the
    // self-intersection or degeneracy checks rather than passing silently.
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
      mesh.triangles.push_back({int(poly[0]), int(poly[k]), int(poly[k + 1])});
    }
  }
  return mesh;
}

}  // namespace

TriangleMesh read_mesh_file(const std::string& path, const std::string& scene_file,
                            const std::string& entry, const MeshFileOptions& options) {
  const std::string ext = std::filesystem::path(path).extension().string();
  std::string lower = ext;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  // The CGAL readers keep their historical case rule (.off or .OFF, not .Off).
  const bool cgal = ext == ".off" || ext == ".obj" || ext == ".stl" || ext == ".ply" ||
                    ext == ".OFF" || ext == ".OBJ" || ext == ".STL" || ext == ".PLY";
  const bool assimp = lower == ".dae" || lower == ".gltf" || lower == ".glb" || lower == ".3mf";
  if (!cgal && !assimp) {
    throw InputError(scene_file, entry,
                     "mesh file " + path + ": unsupported format \"" + ext +
                         "\" (expected .off, .obj, .stl, .ply, .dae, .gltf, .glb or .3mf)");
  }
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    throw InputError(scene_file, entry, "mesh file " + path + " does not exist");
  }
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(scene_file, entry, "mesh file " + path + " is not a regular file");
  }
  const bool ignore_file_up = options.up != MeshFileOptions::UpAxis::file;
  TriangleMesh mesh = cgal ? read_cgal_mesh_file(path, lower, scene_file, entry)
                           : read_assimp_mesh_file(path, scene_file, entry, ignore_file_up);
  const bool y_up = options.up == MeshFileOptions::UpAxis::y ||
                    (options.up == MeshFileOptions::UpAxis::file && file_is_y_up(lower));
  for (Vec3& v : mesh.vertices) {
    v *= options.unit_scale;
    // +90° about x takes the file's y (up) to z: (x, y, z) -> (x, -z, y).
    if (y_up) v = Vec3(v.x(), -v.z(), v.y());
  }
  return mesh;
}

std::string repair_hint(const MeshDefect& defect) {
  if (!defect.repairable) return "";
  if (defect.reason.find("flat") != std::string::npos) {
    return "; to accept it, add \"repair\": \"wrap\" (an enclosing alpha wrap) to the object "
           "or the scene (docs/scene-format.md#repair)";
  }
  return "; to accept it, add \"repair\": \"wrap\" (an enclosing alpha wrap) or \"repair\": "
         "\"hull\" to the object or the scene (docs/scene-format.md#repair)";
}

std::optional<MeshDefect> check_and_orient(TriangleMesh& mesh) {
  auto fatal = [](const std::string& reason) { return MeshDefect{reason, false}; };
  auto repairable = [](const std::string& reason) { return MeshDefect{reason, true}; };
  if (mesh.triangles.empty()) return fatal("mesh has no triangles");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].allFinite())
      return fatal("vertex " + std::to_string(i) + " has a non-finite coordinate");
  }
  const int nv = static_cast<int>(mesh.vertices.size());
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    for (int idx : mesh.triangles[f]) {
      if (idx < 0 || idx >= nv)
        return fatal("triangle " + std::to_string(f) + " uses a vertex index out of range");
    }
  }
  drop_unused_vertices(mesh);
  std::vector<std::vector<std::size_t>> polygons;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    const Point a(mesh.vertices[t[0]].x(), mesh.vertices[t[0]].y(), mesh.vertices[t[0]].z());
    const Point b(mesh.vertices[t[1]].x(), mesh.vertices[t[1]].y(), mesh.vertices[t[1]].z());
    const Point c(mesh.vertices[t[2]].x(), mesh.vertices[t[2]].y(), mesh.vertices[t[2]].z());
    if (CGAL::collinear(a, b, c))
      return repairable("mesh is degenerate: triangle " + std::to_string(f) + " has zero area");
    polygons.push_back({std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2])});
  }
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) {
    return repairable(
        "mesh is not a consistently oriented manifold (an edge is used twice in the same "
        "direction or by more than two triangles)");
  }
  Mesh sm = to_surface_mesh(mesh);
  if (!CGAL::is_closed(sm)) return repairable("mesh is open (it has border edges)");
  // Before the self-intersection test: a flat shell's faces overlap, but "flat" is the cause.
  for (const double v : component_volumes(sm)) {
    if (std::abs(v) < 1e-12)
      return repairable("mesh is degenerate: a shell encloses no volume (it is flat)");
  }
  if (PMP::does_self_intersect(sm)) return repairable("mesh intersects itself");
  // Closed and free of self-intersections, yet the shells can still disagree: an inner shell
  // must face the opposite way from the one around it, disjoint shells the same way.
  if (!PMP::does_bound_a_volume(sm)) {
    return repairable(
        "mesh does not bound a volume: its shells are inconsistently oriented (nested shells "
        "with the same orientation, or disjoint shells with opposite orientations)");
  }
  const double volume = signed_volume(mesh);
  if (std::abs(volume) < 1e-12) return repairable("mesh is degenerate: it encloses no volume");
  if (volume < 0) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  }
  return std::nullopt;
}

void validate_and_orient(TriangleMesh& mesh, const std::string& file, const std::string& entry) {
  if (const std::optional<MeshDefect> defect = check_and_orient(mesh)) {
    throw InputError(file, entry, defect->reason + repair_hint(*defect));
  }
}

bool solids_intersect(const TriangleMesh& a, const TriangleMesh& b) {
  const Mesh ma = to_surface_mesh(a), mb = to_surface_mesh(b);
  return PMP::do_intersect(ma, mb, CGAL::parameters::do_overlap_test_of_bounded_sides(true),
                           CGAL::parameters::do_overlap_test_of_bounded_sides(true));
}

}  // namespace camplace::core::detail
