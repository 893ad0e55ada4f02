// Exact true distance d(C, O_u) (SPEC §4) with CGAL's exact kernel.
#include "camplace/core/distance.hpp"

#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/intersections.h>
#include <CGAL/squared_distance_3.h>

#include <algorithm>
#include <limits>
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
  // Branch and bound: the exact squared distance of two triangles is at least the squared gap
  // of their bounding boxes, so only pairs whose gap does not exceed the best exact value found
  // so far can hold the minimum; every other pair is skipped unmeasured. The gaps are computed
  // in doubles from the input coordinates (exact doubles): each coordinate difference, square
  // and sum is rounded at most 2^-53 relatively, so the computed gap g satisfies
  // g ≤ (1 + 1e-15) · gap; a pair is skipped only when g · (1 − 1e-12) > best · (1 + 1e-12)
  // (best's certified upper bound), i.e. when its exact distance certainly exceeds the minimum.
  // Same exact minimum as measuring every pair (tests/core/distance_test.cpp).
  const auto triangle_boxes = [](const TriangleMesh& m) {
    std::vector<Box3> out;
    out.reserve(m.triangles.size());
    for (const auto& t : m.triangles) {
      Box3 box{m.vertices[t[0]], m.vertices[t[0]]};
      for (int k = 1; k < 3; ++k) {
        box.min = box.min.cwiseMin(m.vertices[t[k]]);
        box.max = box.max.cwiseMax(m.vertices[t[k]]);
      }
      out.push_back(box);
    }
    return out;
  };
  const auto exact_triangle = [](const TriangleMesh& m, std::size_t t) {
    const auto& tri = m.triangles[t];
    auto pt = [&](int k) {
      const Vec3& v = m.vertices[tri[k]];
      return Point(v.x(), v.y(), v.z());
    };
    return Triangle(pt(0), pt(1), pt(2));
  };
  // Each mesh's triangle boxes, once (a mesh meets every mesh of the other set).
  std::vector<std::vector<Box3>> boxes_a, boxes_b;
  for (const TriangleMesh* m : a) boxes_a.push_back(triangle_boxes(*m));
  for (const TriangleMesh* m : b) boxes_b.push_back(triangle_boxes(*m));
  struct MeshPair {
    double gap;
    std::size_t i, j;
  };
  std::vector<MeshPair> pairs;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Box3 box_a = bounding_box(*a[i]);
    for (std::size_t j = 0; j < b.size(); ++j) {
      const Box3 box_b = bounding_box(*b[j]);
      const double gap = box_box_sq_distance(box_a, box_b);
      // One solid inside the other: distance 0 although the surfaces never meet (only possible
      // when the bounding boxes overlap).
      if (gap == 0.0 && (point_inside(*b[j], a[i]->vertices.front()) ||
                         point_inside(*a[i], b[j]->vertices.front()))) {
        return {0.0, "0/1"};
      }
      pairs.push_back({gap, i, j});
    }
  }
  std::sort(pairs.begin(), pairs.end(),
            [](const MeshPair& p, const MeshPair& q) { return p.gap < q.gap; });
  FT best;
  bool have = false;
  double best_upper = std::numeric_limits<double>::infinity();
  // The absolute 1e-300 covers gaps whose squares are subnormal (rounded absolutely).
  const auto skipped = [&](double gap) {
    return have && gap * (1.0 - 1e-12) - 1e-300 > best_upper;
  };
  // Measures one triangle pair exactly; true when the distance is 0 (nothing can beat it).
  const auto measure = [&](const TriangleMesh& ma, std::size_t x, const TriangleMesh& mb,
                           std::size_t y) {
    const FT d = CGAL::squared_distance(exact_triangle(ma, x), exact_triangle(mb, y));
    if (!have || d < best) {
      best = d;
      have = true;
      // The interval's upper end bounds the exact value (to_double may lie below it by up to
      // the lazy number's relative precision, 1e-5 by default).
      best_upper = CGAL::to_interval(best).second * (1.0 + 1e-12);
    }
    return best == 0;
  };
  // Pairs of one mesh pair sorted by gap, up to this many (beyond: in file order, same result).
  constexpr std::size_t kMaxSorted = std::size_t{1} << 22;
  std::vector<std::pair<double, std::pair<std::size_t, std::size_t>>> candidates;
  for (const MeshPair& p : pairs) {
    if (skipped(p.gap)) break;  // sorted: no later mesh pair can hold the minimum
    const TriangleMesh& ma = *a[p.i];
    const TriangleMesh& mb = *b[p.j];
    const std::vector<Box3>& ba = boxes_a[p.i];
    const std::vector<Box3>& bb = boxes_b[p.j];
    if (ba.size() * bb.size() <= kMaxSorted) {
      candidates.clear();
      for (std::size_t x = 0; x < ba.size(); ++x) {
        for (std::size_t y = 0; y < bb.size(); ++y)
          candidates.push_back({box_box_sq_distance(ba[x], bb[y]), {x, y}});
      }
      std::sort(candidates.begin(), candidates.end(),
                [](const auto& u, const auto& v) { return u.first < v.first; });
      for (const auto& [gap, xy] : candidates) {
        if (skipped(gap)) break;
        if (measure(ma, xy.first, mb, xy.second)) return {0.0, "0/1"};
      }
    } else {
      for (std::size_t x = 0; x < ba.size(); ++x) {
        for (std::size_t y = 0; y < bb.size(); ++y) {
          if (skipped(box_box_sq_distance(ba[x], bb[y]))) continue;
          if (measure(ma, x, mb, y)) return {0.0, "0/1"};
        }
      }
    }
  }
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
