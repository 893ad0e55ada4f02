// Box/point to solid distances with bounding-box culling (see solid_distance.hpp).
#include "solid_distance.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

namespace camplace::voxel::detail {

using core::Box3;
using core::Vec3;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Box3 bounds_of(std::initializer_list<Vec3> points) {
  Box3 box{Vec3::Constant(kInf), Vec3::Constant(-kInf)};
  for (const Vec3& p : points) {
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  return box;
}

// core/src/geometry.cpp's box corners (Box3::corners) and edge table (same order, same numbers).
std::array<Vec3, 8> box_corners(const Box3& box) { return box.corners(); }
constexpr int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                               {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

double point_segment_sq(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len = ab.squaredNorm();
  const double t = len > 0.0 ? std::clamp((p - a).dot(ab) / len, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).squaredNorm();
}

/// Squared distance from segment [a, b] to the box, approximately (the minimum of the convex,
/// piecewise quadratic g(t) = Σ_i gap_i(a + t(b − a))², found where its derivative, linear
/// between the breakpoints, changes sign). Used as a lower bound with a margin: g at the
/// computed t is at least the minimum, and the minimum lies within rounding of it.
double segment_box_sq(const Vec3& a, const Vec3& b, const Box3& box) {
  const Vec3 d = b - a;
  auto slope = [&](double t) {  // g'(t) / 2
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double x = a[i] + t * d[i];
      if (x < box.min[i]) sum += d[i] * (x - box.min[i]);
      if (x > box.max[i]) sum += d[i] * (x - box.max[i]);
    }
    return sum;
  };
  auto value = [&](double t) {
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double x = a[i] + t * d[i];
      const double gap = std::max({0.0, box.min[i] - x, x - box.max[i]});
      sum += gap * gap;
    }
    return sum;
  };
  double points[8];
  int count = 0;
  points[count++] = 0.0;
  points[count++] = 1.0;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) continue;
    for (double bound : {box.min[i], box.max[i]}) {
      const double t = (bound - a[i]) / d[i];
      if (t > 0.0 && t < 1.0) points[count++] = t;
    }
  }
  std::sort(points, points + count);
  double prev_t = points[0], prev_s = slope(prev_t);
  if (prev_s >= 0.0) return value(prev_t);
  for (int n = 1; n < count; ++n) {
    const double t = points[n], s = slope(t);
    if (s >= 0.0) {
      // g' is linear on [prev_t, t]: its zero.
      const double root = s > prev_s ? prev_t + (t - prev_t) * (-prev_s / (s - prev_s)) : t;
      return value(std::clamp(root, prev_t, t));
    }
    prev_t = t;
    prev_s = s;
  }
  return value(1.0);
}

/// Lowers `best` to core::triangle_box_sq_distance(a, b, c, box) when that is below `best`
/// (or below `cutoff`, whichever is smaller; otherwise `best` may stay): the same terms
/// (overlap → 0; vertex–box, corner–triangle, edge–edge), each skipped when a lower bound of it
/// is beyond min(best, cutoff). The likely smallest terms go first so that the bound tightens.
void triangle_box(const IndexedSolid& s, std::size_t t, const Box3& box,
                  const std::array<Vec3, 8>& corners, double cutoff, double& best) {
  const auto& tri = s.triangles[t];
  // Overlap needs the bounding boxes to meet; separated by more than the margin, core's test
  // (whose first axes are the box normals) says no as well.
  if (!beyond(core::box_box_sq_distance(s.triangle_bounds[t], box), 0.0) &&
      core::triangle_box_overlap(tri[0], tri[1], tri[2], box)) {
    best = 0.0;
    return;
  }
  best = std::min({best, core::point_box_sq_distance(tri[0], box),
                   core::point_box_sq_distance(tri[1], box),
                   core::point_box_sq_distance(tri[2], box)});
  // Corners: the distance to the triangle's plane bounds the distance to the triangle; the
  // corner nearest the plane first.
  const Vec3& normal = s.unit_normals[t];
  double plane[8];
  int nearest = 0;
  for (int q = 0; q < 8; ++q) {
    plane[q] = std::abs(normal.dot(corners[q] - tri[0]));
    if (plane[q] < plane[nearest]) nearest = q;
  }
  for (int n = -1; n < 8; ++n) {
    const int q = n < 0 ? nearest : n;
    if (n == nearest) continue;
    if (beyond(plane[q] * plane[q] * (1.0 - 1e-9), std::min(best, cutoff))) continue;
    best = std::min(best, core::point_triangle_sq_distance(corners[q], tri[0], tri[1], tri[2]));
  }
  for (int i = 0; i < 3; ++i) {
    const Vec3 &f0 = tri[i], &f1 = tri[(i + 1) % 3];
    // Every edge–edge term of f is at least f's distance to the box.
    const double gap = segment_box_sq(f0, f1, box);
    if (beyond(gap * (1.0 - 1e-9), std::min(best, cutoff))) continue;
    for (const auto& e : kEdges) {
      const Box3 edge{corners[e[0]], corners[e[1]]};  // axis-aligned: its own bounding box
      const double cut = std::min(best, cutoff);
      // Every point of the box edge is within half its length of its midpoint.
      const double edge_gap =
          std::sqrt(point_segment_sq(edge.center(), f0, f1)) - 0.5 * edge.diagonal();
      if (edge_gap > 0.0 && beyond(edge_gap * edge_gap * (1.0 - 1e-9), cut)) continue;
      best =
          std::min(best, core::segment_segment_sq_distance(corners[e[0]], corners[e[1]], f0, f1));
    }
  }
}

/// Whether every edge of `mesh` is used as often from u to v as from v to u.
bool edges_balanced(const core::TriangleMesh& mesh) {
  std::unordered_map<std::uint64_t, int> balance;
  balance.reserve(mesh.triangles.size() * 3);
  for (const auto& t : mesh.triangles) {
    for (int i = 0; i < 3; ++i) {
      const auto u = static_cast<std::uint32_t>(t[i]),
                 v = static_cast<std::uint32_t>(t[(i + 1) % 3]);
      balance[(std::uint64_t(std::min(u, v)) << 32) | std::max(u, v)] += u < v ? 1 : -1;
    }
  }
  return std::all_of(balance.begin(), balance.end(), [](const auto& e) { return e.second == 0; });
}

/// How the ray {p + t·(0, 0, 1), t > 0} crosses triangle `tri`: +1 or −1 (the sign of the
/// normal's z component) when it certainly passes through the triangle's interior, 0 when it
/// certainly misses it, kUnsure when rounding could decide either (the ray near an edge or a
/// vertex, or p near the triangle).
constexpr int kUnsure = 2;
int ray_crossing(const std::array<Vec3, 3>& tri, const Vec3& p) {
  const Vec3 a = tri[0] - p, b = tri[1] - p, c = tri[2] - p;
  // Twice the signed areas of the projections of (p, a, b), (p, b, c), (p, c, a) on the xy
  // plane, each with the sum of its products' magnitudes: computed from the rounded
  // differences, each within 4·2⁻⁵³ of that sum of the exact value, so its sign is certain
  // when it exceeds 1e-12 of it.
  const double e[3] = {a.x() * b.y() - a.y() * b.x(), b.x() * c.y() - b.y() * c.x(),
                       c.x() * a.y() - c.y() * a.x()};
  const double m[3] = {std::abs(a.x() * b.y()) + std::abs(a.y() * b.x()),
                       std::abs(b.x() * c.y()) + std::abs(b.y() * c.x()),
                       std::abs(c.x() * a.y()) + std::abs(c.y() * a.x())};
  int positive = 0, negative = 0;
  bool unsure = false;
  double relative = 0.0;  // the largest m / |e| of the certain ones
  for (int i = 0; i < 3; ++i) {
    if (!(std::abs(e[i]) > 1e-12 * m[i])) {
      unsure = true;
      continue;
    }
    (e[i] > 0.0 ? positive : negative)++;
    relative = std::max(relative, m[i] / std::abs(e[i]));
  }
  if (positive > 0 && negative > 0) return 0;  // p's projection is outside the triangle's
  if (unsure) return kUnsure;
  // p's projection is inside: the height of the crossing above p, a convex combination of the
  // vertices' heights with weights e / Σe, each weight within (2·relative + 1)·1e-15 of its
  // exact value (relatively).
  const double sum = e[0] + e[1] + e[2];
  const double t = (e[1] * a.z() + e[2] * b.z() + e[0] * c.z()) / sum;
  const double error =
      (8.0 * relative + 8.0) * 1e-15 * (std::abs(a.z()) + std::abs(b.z()) + std::abs(c.z()));
  if (!(std::abs(t) > error)) return kUnsure;
  if (t < 0.0) return 0;
  return sum > 0.0 ? 1 : -1;
}

/// Calls `visit(t)` for each triangle t of the leaves of the hierarchy whose nodes' boxes all
/// pass `keep`, until it returns true; true then.
template <class Keep, class Visit>
bool walk_triangles(const IndexedSolid& s, const Keep& keep, const Visit& visit) {
  thread_local std::vector<std::size_t> stack;
  stack.clear();
  if (!s.nodes.empty()) stack.push_back(0);
  while (!stack.empty()) {
    const core::BoxTreeNode& node = s.nodes[stack.back()];
    stack.pop_back();
    if (!keep(node.box)) continue;
    if (node.count == 0) {
      stack.push_back(node.first);
      stack.push_back(node.first + 1);
      continue;
    }
    for (std::size_t k = node.first; k < node.first + node.count; ++k)
      if (visit(s.order[k])) return true;
  }
  return false;
}

/// Calls `visit(t)` for each triangle t whose bounds are within the margin of `box` (the others
/// certainly miss it: core::triangle_box_overlap's first axes are the box's normals) until it
/// returns true; true then.
template <class Visit>
bool any_triangle_near(const IndexedSolid& s, const Box3& box, const Visit& visit) {
  const auto near = [&](const Box3& b) { return !beyond(core::box_box_sq_distance(b, box), 0.0); };
  return walk_triangles(s, near, [&](int t) { return near(s.triangle_bounds[t]) && visit(t); });
}

/// The squared distance from p to the nearest triangle of s when it is at most `bound`
/// (otherwise some value above `bound`), and that triangle (-1: none found). The triangles
/// through the hierarchy, nearer child first; a subtree or triangle is skipped when its box's
/// distance is beyond min(best, bound) (then so is every triangle in it): the nearest triangle
/// is never skipped, so the minimum is the scan's, the same double.
double surface_sq_distance(const IndexedSolid& s, const Vec3& p, double bound, int& triangle) {
  double best = kInf;
  triangle = -1;
  // Nodes with the lower bound of their distance computed when they were pushed.
  thread_local std::vector<std::pair<std::size_t, double>> stack;
  stack.clear();
  if (!s.nodes.empty()) stack.emplace_back(0, core::point_box_sq_distance(p, s.nodes[0].box));
  while (!stack.empty()) {
    const auto [index, lower] = stack.back();
    stack.pop_back();
    if (beyond(lower, std::min(best, bound))) continue;
    const core::BoxTreeNode& node = s.nodes[index];
    if (node.count == 0) {
      const double near = core::point_box_sq_distance(p, s.nodes[node.first].box);
      const double far = core::point_box_sq_distance(p, s.nodes[node.first + 1].box);
      if (near <= far) {
        stack.emplace_back(node.first + 1, far);
        stack.emplace_back(node.first, near);
      } else {
        stack.emplace_back(node.first, near);
        stack.emplace_back(node.first + 1, far);
      }
      continue;
    }
    for (std::size_t k = node.first; k < node.first + node.count; ++k) {
      const int t = s.order[k];
      if (beyond(core::point_box_sq_distance(p, s.triangle_bounds[t]), std::min(best, bound)))
        continue;
      const auto& tri = s.triangles[t];
      const double d = core::point_triangle_sq_distance(p, tri[0], tri[1], tri[2]);
      if (d < best) {
        best = d;
        triangle = t;
      }
    }
  }
  return best;
}

/// The hierarchy of s's triangle boxes: top down, each node split at the median of its box
/// centres along the widest axis of their range, leaves of at most 4 triangles.
void build_hierarchy(IndexedSolid& s) {
  constexpr std::size_t kLeaf = 4;
  s.order.resize(s.triangles.size());
  for (std::size_t t = 0; t < s.order.size(); ++t) s.order[t] = static_cast<int>(t);
  s.nodes = core::build_box_tree(
      s.order, [&](int t) -> const Box3& { return s.triangle_bounds[t]; }, kLeaf);
}

}  // namespace

IndexedSolid index_solid(const core::TriangleMesh& mesh) {
  IndexedSolid s;
  s.mesh = &mesh;
  s.bounds = Box3{Vec3::Constant(kInf), Vec3::Constant(-kInf)};
  for (const Vec3& v : mesh.vertices) {
    s.bounds.min = s.bounds.min.cwiseMin(v);
    s.bounds.max = s.bounds.max.cwiseMax(v);
  }
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    s.triangles.push_back({a, b, c});
    s.triangle_bounds.push_back(bounds_of({a, b, c}));
    s.edge_bounds.push_back({bounds_of({a, b}), bounds_of({b, c}), bounds_of({c, a})});
    const Vec3 n = (b - a).cross(c - a);
    s.unit_normals.push_back(n.norm() > 0.0 ? Vec3(n.normalized()) : Vec3::Zero());
  }
  build_hierarchy(s);
  s.closed = edges_balanced(mesh);
  return s;
}

bool inside_solid(const IndexedSolid& s, const Vec3& p) {
  // On a closed, consistently oriented surface the winding number of a point off the surface is
  // an integer, the signed count of the crossings of any ray from it that passes through no
  // edge or vertex; core::inside_mesh's sum of solid angles lies within rounding of that
  // integer and says inside when it is at least 1. A ray crossing that rounding could decide
  // either way (the ray near an edge or a vertex, p near the surface) leaves it to that sum.
  if (!s.closed) return core::inside_mesh(*s.mesh, p);
  // Within a nanometre (and rounding) of the surface the sum's rounding may decide, so it does.
  const double clearance = 1e-9 * (1.0 + p.cwiseAbs().maxCoeff());
  int ignored = 0;
  if (!beyond(surface_sq_distance(s, p, clearance * clearance, ignored), clearance * clearance))
    return core::inside_mesh(*s.mesh, p);
  int winding = 0;
  bool unsure = false;
  // The ray meets only triangles whose boxes it meets (exact comparisons of doubles: a box left
  // out lies wholly beside or below the ray).
  const auto on_ray = [&](const Box3& b) {
    return !(p.x() < b.min.x() || p.x() > b.max.x() || p.y() < b.min.y() || p.y() > b.max.y() ||
             p.z() > b.max.z());
  };
  walk_triangles(s, on_ray, [&](int t) {
    const int crossing = ray_crossing(s.triangles[t], p);
    unsure = crossing == kUnsure;
    if (!unsure) winding += crossing;
    return unsure;
  });
  if (unsure) return core::inside_mesh(*s.mesh, p);
  return winding >= 1;
}

double vertex_upper_bound(const std::vector<IndexedSolid>& solids, const Box3& box) {
  double best = kInf;
  for (const IndexedSolid& s : solids) {
    for (const Vec3& v : s.mesh->vertices)
      best = std::min(best, core::point_box_sq_distance(v, box));
  }
  return best;
}

double vertex_upper_bound(const std::vector<IndexedSolid>& solids, const Vec3& p) {
  double best = kInf;
  for (const IndexedSolid& s : solids) {
    for (const Vec3& v : s.mesh->vertices) best = std::min(best, (v - p).squaredNorm());
  }
  return best;
}

double box_solids_sq_distance(const std::vector<IndexedSolid>& solids, const Box3& box,
                              double cutoff) {
  // core::box_solid_sq_distance per solid is 0 when a triangle meets the box or the box's
  // centre is inside, else the smallest triangle–box distance; the minimum over the solids is
  // 0 when any solid gives 0, else the smallest of all triangle terms.
  // The triangles are searched first and the (costly) centre test made only when no triangle
  // meets the box: 0 either way when one does.
  const Vec3 center = box.center();
  const double radius = 0.5 * box.diagonal();
  // Each solid's triangles through its hierarchy, the nearer child (to the box's centre) first.
  // The distance from the centre to a triangle is an upper bound of the box's distance (the
  // centre is in the box): it tightens the cutoff; less the box's radius it bounds the
  // triangle's distance from below. Every triangle or subtree is skipped only when a lower
  // bound of its distance is beyond min(best, cutoff), where best and the cutoff are at least
  // the minimum: the triangle term holding the minimum is always computed, so the result is
  // the minimum over the same doubles as core's scan of every triangle.
  double best = kInf;
  const std::array<Vec3, 8> corners = box_corners(box);
  thread_local std::vector<std::size_t> stack;
  for (const IndexedSolid& s : solids) {
    if (s.nodes.empty() || beyond(core::box_box_sq_distance(s.bounds, box), std::min(best, cutoff)))
      continue;
    stack.assign(1, 0);
    while (!stack.empty()) {
      const core::BoxTreeNode& node = s.nodes[stack.back()];
      stack.pop_back();
      if (beyond(core::box_box_sq_distance(node.box, box), std::min(best, cutoff))) continue;
      if (node.count == 0) {
        const double near = core::point_box_sq_distance(center, s.nodes[node.first].box);
        const double far = core::point_box_sq_distance(center, s.nodes[node.first + 1].box);
        stack.push_back(near <= far ? node.first + 1 : node.first);
        stack.push_back(near <= far ? node.first : node.first + 1);
        continue;
      }
      for (std::size_t k = node.first; k < node.first + node.count; ++k) {
        const int t = s.order[k];
        const auto& tri = s.triangles[t];
        const double d = core::point_triangle_sq_distance(center, tri[0], tri[1], tri[2]);
        cutoff = std::min(cutoff, d * (1.0 + 1e-9) + 1e-18);
        const double cut = std::min(best, cutoff);
        const double gap = std::sqrt(d) - radius;
        if (gap > 0.0 && beyond(gap * gap * (1.0 - 1e-9), cut)) continue;
        if (beyond(core::box_box_sq_distance(s.triangle_bounds[t], box), cut)) continue;
        triangle_box(s, static_cast<std::size_t>(t), box, corners, cut, best);
        if (best == 0.0) return 0.0;
      }
    }
  }
  for (const IndexedSolid& s : solids) {
    if (s.bounds.contains(center) && inside_solid(s, center)) return 0.0;
  }
  return best;
}

double point_solids_sq_distance(const std::vector<IndexedSolid>& solids, const Vec3& p,
                                double cutoff, bool inside_test, NearestTriangle* nearest) {
  // A hinted triangle's distance is one of the candidates, so at least the minimum: a cutoff.
  if (nearest != nullptr && nearest->solid >= 0) {
    const auto& tri = solids[std::size_t(nearest->solid)].triangles[std::size_t(nearest->triangle)];
    cutoff = std::min(cutoff, core::point_triangle_sq_distance(p, tri[0], tri[1], tri[2]));
  }
  double result = kInf;
  NearestTriangle found;
  for (std::size_t si = 0; si < solids.size(); ++si) {
    const IndexedSolid& s = solids[si];
    const double bound = std::min(result, cutoff);
    if (beyond(core::point_box_sq_distance(p, s.bounds), bound)) continue;
    // core::point_solid_sq_distance: 0 inside (a point outside the bounds is not), else the
    // nearest triangle.
    if (inside_test && s.bounds.contains(p) && inside_solid(s, p)) {
      result = 0.0;
      continue;
    }
    int triangle = -1;
    const double best = surface_sq_distance(s, p, bound, triangle);
    if (best < result) {
      result = best;
      found = {static_cast<int>(si), triangle};
    }
  }
  if (nearest != nullptr && found.solid >= 0) *nearest = found;
  return result;
}

bool box_meets_surface(const IndexedSolid& s, const Box3& box) {
  return any_triangle_near(s, box, [&](int t) {
    const auto& tri = s.triangles[t];
    return core::triangle_box_overlap(tri[0], tri[1], tri[2], box);
  });
}

bool box_inside_solid(const IndexedSolid& s, const Box3& box, double depth, bool faces) {
  if (!s.bounds.contains(box.center()) || !inside_solid(s, box.center())) return false;
  if (!faces) return true;
  const Box3 interior{box.min + Vec3::Constant(depth), box.max - Vec3::Constant(depth)};
  return !box_meets_surface(s, interior);
}

}  // namespace camplace::voxel::detail
