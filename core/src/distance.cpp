// Exact true distance d(C, O_u) (SPEC §4) with CGAL's exact kernel.
#include "camplace/core/distance.hpp"

#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/intersections.h>
#include <CGAL/squared_distance_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <type_traits>

#include "camplace/core/box_tree.hpp"
#include "camplace/core/closest_points.hpp"
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

/// One triangle of a set of solids, with its bounding box and where it comes from.
struct FlatTriangle {
  std::array<Vec3, 3> v;
  Box3 box;
  const TriangleMesh* mesh;
  std::size_t index;  ///< in mesh->triangles
};

/// Bounding-volume hierarchy over triangle boxes (core::build_box_tree): the leaves hold
/// triangles of `triangles` (reordered by the build).
struct Bvh {
  using Node = BoxTreeNode;
  std::vector<FlatTriangle> triangles;
  std::vector<Node> nodes;
};

constexpr std::size_t kLeafSize = 4;

Bvh build_bvh(const std::vector<const TriangleMesh*>& meshes) {
  Bvh bvh;
  for (const TriangleMesh* m : meshes) {
    for (std::size_t t = 0; t < m->triangles.size(); ++t) {
      const auto& tri = m->triangles[t];
      const Vec3 &p = m->vertices[tri[0]], &q = m->vertices[tri[1]], &r = m->vertices[tri[2]];
      bvh.triangles.push_back(
          {{p, q, r}, {p.cwiseMin(q).cwiseMin(r), p.cwiseMax(q).cwiseMax(r)}, m, t});
    }
  }
  CAMPLACE_ASSERT(!bvh.triangles.empty());
  bvh.nodes = build_box_tree(
      bvh.triangles, [](const FlatTriangle& t) -> const Box3& { return t.box; }, kLeafSize);
  return bvh;
}

/// A certified lower bound of the exact squared distance between triangles a and b, from the
/// slab they leave between them along the direction `n` (any vector). For a unit m and every
/// p in a, q in b: |q − p| ≥ m·(q − p) ≥ min_j m·b_j − max_i m·a_i (a linear function takes its
/// extremes over a triangle at vertices), so that gap, when positive, bounds the distance from
/// below; along the direction of the closest points it equals the distance. In doubles, with
/// m = fl(n / |n|) (whatever its rounding, m is some exact vector of doubles; its length is
/// within a few ulps of 1 and is bounded above below):
/// - each dot product m·v of three terms is off by at most γ₃·Σ|m_k||v_k| (γ₃ = 3u/(1 − 3u),
///   u = 2⁻⁵³, with or without fused multiply–adds): E = 1e-14·max_v Σ|m_k||v_k| bounds it with
///   a margin of 25 that also covers the rounding of that sum;
/// - the gap s = fl(min_b − max_a) is off by at most u·|s|, its corrections by a few ulps of
///   |s| + E, covered by 1e-15·|s| and the margin in E;
/// - dividing by |m| ≤ fl(|m|)·(1 + 1e-14) and squaring (relative u each) lose at most a few
///   ulps, covered by the factors (1 − 1e-15) and (1 − 1e-14); results below 1e-280 are taken
///   as 0 (no subnormal rounding, whose error is absolute).
double slab_lower_bound(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b, const Vec3& n) {
  const double nn = n.squaredNorm();
  if (!(nn > 1e-250) || !std::isfinite(nn)) return 0.0;
  const Vec3 m = n / std::sqrt(nn);
  double max_a = -std::numeric_limits<double>::infinity();
  double min_b = std::numeric_limits<double>::infinity();
  double magnitude = 0.0;
  for (const Vec3& v : a) {
    max_a = std::max(max_a, m.dot(v));
    magnitude = std::max(magnitude, m.cwiseAbs().dot(v.cwiseAbs()));
  }
  for (const Vec3& v : b) {
    min_b = std::min(min_b, m.dot(v));
    magnitude = std::max(magnitude, m.cwiseAbs().dot(v.cwiseAbs()));
  }
  const double s = min_b - max_a;
  const double gap = s - 2.0 * 1e-14 * magnitude - 1e-15 * std::abs(s);
  if (!(gap > 0.0)) return 0.0;
  const double length = std::sqrt(m.squaredNorm()) * (1.0 + 1e-14);
  const double distance = gap / length * (1.0 - 1e-15);
  const double sq = distance * distance * (1.0 - 1e-14);
  return sq < 1e-280 ? 0.0 : sq;
}

/// A certified lower bound of the squared distance of anything in two boxes: the computed gap
/// g satisfies g ≤ (1 + 1e-15)·gap (each coordinate difference, square and sum rounded at most
/// 2⁻⁵³ relatively; the absolute 1e-300 covers subnormal squares).
double box_lower_bound(const Box3& a, const Box3& b) {
  const double g = box_box_sq_distance(a, b) * (1.0 - 1e-12) - 1e-300;
  return g > 0.0 ? g : 0.0;
}

/// A triangle pair that may hold the minimum: its approximate squared distance (doubles, for
/// the order of measuring) and a certified lower bound of its exact one.
struct Candidate {
  double approx;
  double lower;
  std::size_t x, y;  ///< in the two hierarchies' triangle arrays
};

/// Every triangle pair of `ta` × `tb` whose certified lower bound is at most the threshold.
/// With `adaptive`, the threshold starts at infinity and follows the smallest approximate
/// distance seen, t = (1 + 1e-6)·min approx + 1e-30 (never increasing); otherwise it stays at
/// `threshold`. Node pairs are visited nearer first and skipped, whole, when the certified
/// lower bound of their boxes' gap exceeds the threshold of the moment. Returns the final
/// threshold: every pair not returned has a certified lower bound above it.
double collect(const Bvh& ta, const Bvh& tb, bool adaptive, double threshold,
               std::vector<Candidate>& out) {
  out.clear();
  if (adaptive) threshold = std::numeric_limits<double>::infinity();
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, 0}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    const Bvh::Node& na = ta.nodes[i];
    const Bvh::Node& nb = tb.nodes[j];
    if (box_lower_bound(na.box, nb.box) > threshold) continue;
    if (na.count > 0 && nb.count > 0) {
      for (std::size_t x = na.first; x < na.first + na.count; ++x) {
        const FlatTriangle& s = ta.triangles[x];
        for (std::size_t y = nb.first; y < nb.first + nb.count; ++y) {
          const FlatTriangle& t = tb.triangles[y];
          const double box_lower = box_lower_bound(s.box, t.box);
          if (box_lower > threshold) continue;
          const ClosestPoints c =
              closest_points_of_triangles(s.v[0], s.v[1], s.v[2], t.v[0], t.v[1], t.v[2]);
          const double lower = std::max(box_lower, slab_lower_bound(s.v, t.v, c.b - c.a));
          if (lower > threshold) continue;
          out.push_back({c.sq_distance, lower, x, y});
          if (adaptive) threshold = std::min(threshold, c.sq_distance * (1.0 + 1e-6) + 1e-30);
        }
      }
      continue;
    }
    // Split the larger node (a leaf is never split); the nearer child pair is visited first.
    const bool split_a =
        nb.count > 0 || (na.count == 0 && (na.box.max - na.box.min).squaredNorm() >=
                                              (nb.box.max - nb.box.min).squaredNorm());
    std::pair<std::size_t, std::size_t> p, q;
    double gp, gq;
    if (split_a) {
      p = {na.first, j};
      q = {na.first + 1, j};
      gp = box_box_sq_distance(ta.nodes[p.first].box, nb.box);
      gq = box_box_sq_distance(ta.nodes[q.first].box, nb.box);
    } else {
      p = {i, nb.first};
      q = {i, nb.first + 1};
      gp = box_box_sq_distance(na.box, tb.nodes[p.second].box);
      gq = box_box_sq_distance(na.box, tb.nodes[q.second].box);
    }
    if (gp < gq) std::swap(p, q);
    stack.push_back(p);
    stack.push_back(q);
  }
  return threshold;
}

}  // namespace

ExactSquaredDistance solids_squared_distance(const std::vector<const TriangleMesh*>& a,
                                             const std::vector<const TriangleMesh*>& b) {
  CAMPLACE_ASSERT(!a.empty() && !b.empty());
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Box3 box_a = bounding_box(*a[i]);
    for (std::size_t j = 0; j < b.size(); ++j) {
      // One solid inside the other: distance 0 although the surfaces never meet (only possible
      // when the bounding boxes overlap).
      if (box_box_sq_distance(box_a, bounding_box(*b[j])) == 0.0 &&
          (point_inside(*b[j], a[i]->vertices.front()) ||
           point_inside(*a[i], b[j]->vertices.front()))) {
        return {0.0, "0/1"};
      }
    }
  }
  // Otherwise the distance of the two unions is the smallest exact distance of a triangle of a
  // and a triangle of b. Why no pair that holds it is skipped:
  // 1. `collect` returns every pair whose certified lower bound (the larger of the boxes' gap
  //    and the slab gap along the pair's approximate closest direction, slab_lower_bound) is at
  //    most its final threshold t; every other pair, alone or with a whole node pair, was
  //    dropped because a certified lower bound of its exact distance exceeded the threshold of
  //    that moment, which is at least t.
  // 2. The pair of least approximate distance is measured exactly first: best, and
  //    best_upper ≥ best (the interval's upper end). If best_upper ≤ t, every dropped pair's
  //    exact distance exceeds t ≥ best_upper ≥ best; if not (the doubles misjudged that pair),
  //    the pairs are collected again with the fixed threshold best_upper, which then holds for
  //    the same reason.
  // 3. The returned pairs are measured exactly in the order of their approximate distances,
  //    each skipped when its certified lower bound exceeds the current best_upper (its exact
  //    distance then exceeds the current best, which only decreases).
  // The minimum is over the same exact values as measuring every pair, so it is the same
  // number (and fraction); pairs tied at it may be skipped, which changes nothing.
  const Bvh ta = build_bvh(a);
  const Bvh tb = build_bvh(b);
  const auto exact_triangle = [](const FlatTriangle& f) {
    const auto& tri = f.mesh->triangles[f.index];
    auto pt = [&](int k) {
      const Vec3& v = f.mesh->vertices[tri[k]];
      return Point(v.x(), v.y(), v.z());
    };
    return Triangle(pt(0), pt(1), pt(2));
  };
  FT best;
  bool have = false;
  double best_upper = std::numeric_limits<double>::infinity();
  // Measures one triangle pair exactly; true when the distance is 0 (nothing can beat it).
  const auto measure = [&](const Candidate& c) {
    const FT d = CGAL::squared_distance(exact_triangle(ta.triangles[c.x]),
                                        exact_triangle(tb.triangles[c.y]));
    if (!have || d < best) {
      best = d;
      have = true;
      // The interval's upper end bounds the exact value (to_double may lie below it by up to
      // the lazy number's relative precision, 1e-5 by default).
      best_upper = CGAL::to_interval(best).second * (1.0 + 1e-12);
    }
    return best == 0;
  };
  std::vector<Candidate> candidates;
  const double threshold = collect(ta, tb, true, 0.0, candidates);
  CAMPLACE_ASSERT(!candidates.empty());
  const auto by_approx = [](const Candidate& p, const Candidate& q) {
    return p.approx < q.approx ||
           (p.approx == q.approx && (p.x < q.x || (p.x == q.x && p.y < q.y)));
  };
  std::sort(candidates.begin(), candidates.end(), by_approx);
  if (measure(candidates.front())) return {0.0, "0/1"};
  std::size_t from = 1;
  if (best_upper > threshold) {
    collect(ta, tb, false, best_upper, candidates);
    std::sort(candidates.begin(), candidates.end(), by_approx);
    from = 0;
  }
  for (std::size_t k = from; k < candidates.size(); ++k) {
    if (candidates[k].lower > best_upper) continue;
    if (measure(candidates[k])) return {0.0, "0/1"};
  }
  // The value from the exact number (its tight interval), not from whatever approximation the
  // comparisons left: the same double whichever pairs were measured, and in which order.
  CGAL::exact(best);
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
