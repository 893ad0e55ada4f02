// Exact true distance d(C, O_u) (SPEC §4) with CGAL's exact kernel.
#include "camplace/core/distance.hpp"

#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/intersections.h>
#include <CGAL/squared_distance_3.h>

#include <sstream>
#include <type_traits>

#include "camplace/core/error.hpp"
#include "camplace/core/internal/exact_kernel.hpp"

namespace camplace::core {

namespace {
using K = internal::Kernel;
using internal::fraction_string;
using internal::FT;
using internal::Point;
using Triangle = K::Triangle_3;

std::vector<Triangle> triangles_of(const TriangleMesh& mesh) {
  std::vector<Triangle> out;
  auto pt = [&](int i) {
    const Vec3& v = mesh.vertices[i];
    return Point(v.x(), v.y(), v.z());
  };
  for (const auto& t : mesh.triangles) out.emplace_back(pt(t[0]), pt(t[1]), pt(t[2]));
  return out;
}

bool point_inside(const TriangleMesh& mesh, const Vec3& p) {
  using Mesh = CGAL::Surface_mesh<Point>;
  std::vector<Point> points;
  for (const Vec3& v : mesh.vertices) points.emplace_back(v.x(), v.y(), v.z());
  std::vector<std::vector<std::size_t>> polygons;
  for (const auto& t : mesh.triangles)
    polygons.push_back({std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2])});
  Mesh sm;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, polygons, sm);
  CGAL::Side_of_triangle_mesh<Mesh, K> side(sm);
  return side(Point(p.x(), p.y(), p.z())) != CGAL::ON_UNBOUNDED_SIDE;
}

}  // namespace

ExactSquaredDistance solids_squared_distance(const std::vector<const TriangleMesh*>& a,
                                             const std::vector<const TriangleMesh*>& b) {
  CAMPLACE_ASSERT(!a.empty() && !b.empty());
  FT best;
  bool have = false;
  for (const TriangleMesh* ma : a) {
    const auto ta = triangles_of(*ma);
    for (const TriangleMesh* mb : b) {
      // One solid inside the other: distance 0 although the surfaces never meet.
      if (point_inside(*mb, ma->vertices.front()) || point_inside(*ma, mb->vertices.front())) {
        return {0.0, "0/1"};
      }
      const auto tb = triangles_of(*mb);
      for (const Triangle& x : ta) {
        for (const Triangle& y : tb) {
          const FT d = CGAL::squared_distance(x, y);
          if (!have || d < best) {
            best = d;
            have = true;
          }
        }
      }
    }
  }
  if (have && best == 0) return {0.0, "0/1"};
  return {CGAL::to_double(best), fraction_string(best)};
}

ExactSquaredDistance true_squared_distance(const Scene& scene, const StateIndex& state) {
  const TimeStep& step = scene.time_steps.at(state.time_step);
  const Event& event = step.events.at(state.event);
  std::vector<const TriangleMesh*> critical, targets;
  for (const SceneObject& o : step.critical) critical.push_back(&o.mesh);
  for (const SceneObject& o : event.targets) targets.push_back(&o.mesh);
  return solids_squared_distance(critical, targets);
}

}  // namespace camplace::core
