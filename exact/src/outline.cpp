// The occupied part of a camera's view as outlines in its image plane (internal/outline.hpp): the
// faces nothing hides as one boundary chain (an arrangement of their silhouette edges with
// winding numbers), the others projected and cut to the window with the blockers' parts in front
// of them removed, all joined with CGAL's exact 2D booleans (Boolean_set_operations_2 on the
// exact kernel), and the result split into simple cycles and triangulated for the cones of
// cones.hpp; and the split of an occluding solid's front faces into patches whose shadows are
// simple polyhedra (checked on the arrangement of their boundary edges' images). No Nef code here.
#include "internal/outline.hpp"

#include <CGAL/Arr_curve_data_traits_2.h>
#include <CGAL/Arr_extended_dcel.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arrangement_2.h>
#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Constrained_triangulation_2.h>
#include <CGAL/Polygon_set_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <functional>
#include <iterator>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <stdexcept>

#include "camplace/core/error.hpp"

namespace camplace::exact::internal {
namespace {

using Point2 = Kernel::Point_2;
using Polygon2 = CGAL::Polygon_2<Kernel>;
using PolygonWithHoles = CGAL::Polygon_with_holes_2<Kernel>;
using PolygonSet = CGAL::Polygon_set_2<Kernel>;
using Tetrahedron = Kernel::Tetrahedron_3;
// Segments carrying their multiplicity in a boundary chain, counted in the direction of
// increasing (x, y); overlapping pieces add up. Faces carry their winding number.
using SegmentTraits = CGAL::Arr_segment_traits_2<Kernel>;
using ChainTraits = CGAL::Arr_curve_data_traits_2<SegmentTraits, int, std::plus<int>>;
using ChainArrangement =
    CGAL::Arrangement_2<ChainTraits, CGAL::Arr_face_extended_dcel<ChainTraits, int>>;

/// The part of a convex polygon where the affine function phi is ≥ 0 (Sutherland–Hodgman).
template <class Phi>
std::vector<Point> clip(const std::vector<Point>& poly, const Phi& phi) {
  const std::size_t n = poly.size();
  std::vector<FT> v;
  v.reserve(n);
  for (const auto& p : poly) v.push_back(phi(p));
  std::vector<Point> out;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    const CGAL::Sign si = CGAL::sign(v[i]), sj = CGAL::sign(v[j]);
    if (si != CGAL::NEGATIVE) out.push_back(poly[i]);
    if ((si == CGAL::POSITIVE && sj == CGAL::NEGATIVE) ||
        (si == CGAL::NEGATIVE && sj == CGAL::POSITIVE))
      out.push_back(poly[i] + (poly[j] - poly[i]) * (v[i] / (v[i] - v[j])));
  }
  return out;
}

/// Central projection from c onto the image plane, and back.
class Projector {
 public:
  explicit Projector(const ImagePlane& plane)
      : p_(plane),
        d_(plane.d / (plane.d * plane.d)),
        a_(plane.a / (plane.a * plane.a)),
        b_(plane.b / (plane.b * plane.b)) {}

  /// The image of a convex polygon (3D points, its plane not through c) cut to the window:
  /// counter-clockwise, or nothing when no part of positive area remains. Cutting to the window
  /// (the cone |(x − c)·a|, |(x − c)·b| ≤ half_width·(x − c)·d) leaves only points with
  /// (x − c)·d > 0, whose images exist.
  std::optional<Polygon2> image(std::vector<Point> poly) {
    const FT& w = p_.half_width;
    for (int axis = 0; axis < 2; ++axis) {
      const Vector& e = axis == 0 ? p_.a : p_.b;
      for (int sign : {1, -1}) {
        poly = clip(poly, [&](const Point& x) {
          const Vector u = x - p_.c;
          return w * (u * p_.d) - FT(sign) * (u * e);
        });
        if (poly.size() < 3) return std::nullopt;
      }
    }
    Polygon2 out;
    for (const auto& x : poly) {
      const Point2 q = project(x);
      if (out.is_empty() || q != out[out.size() - 1]) out.push_back(q);
    }
    while (out.size() > 1 && out[0] == out[out.size() - 1]) out.erase(out.vertices_end() - 1);
    if (out.size() < 3) return std::nullopt;
    const CGAL::Sign area = CGAL::sign(out.area());
    if (area == CGAL::ZERO) return std::nullopt;
    if (area == CGAL::NEGATIVE) out.reverse_orientation();
    return out;
  }

  /// The image of x, remembered as a point of its ray.
  Point2 project(const Point& x) {
    const Vector u = x - p_.c;
    const FT depth = u * p_.d;
    const Point2 q((u * p_.a) / depth, (u * p_.b) / depth);
    origin_.emplace(q, x);
    return q;
  }

  /// A point with image q: a projected point when there is one (its coordinates are shorter
  /// than those of the image plane's point), else the image plane's point.
  Point lift(const Point2& q) const {
    const auto it = origin_.find(q);
    return it != origin_.end() ? it->second : p_.c + d_ + a_ * q.x() + b_ * q.y();
  }

 private:
  const ImagePlane& p_;
  Vector d_, a_, b_;
  std::map<Point2, Point> origin_;
};

/// The union of triangles of the image plane given as a boundary chain: each triangle's
/// counter-clockwise boundary added up, an edge shared by two triangles cancelling out (their
/// images run along it in opposite directions). The union is where the chain's winding number
/// (the number of triangles covering a point) is at least 1, so only the chain's edges — the
/// silhouette edges of a mesh, few against its faces — enter the arrangement.
class Chain {
 public:
  /// Adds the directed edge p → q (vertex keys, images) of a counter-clockwise triangle.
  void add(const std::pair<int, int>& p, const std::pair<int, int>& q, const Point2& pp,
           const Point2& qp) {
    const bool forward = p < q;
    Edge& e = edges_[forward ? std::make_pair(p, q) : std::make_pair(q, p)];
    e.count += forward ? 1 : -1;
    e.from = forward ? pp : qp;
    e.to = forward ? qp : pp;
  }

  /// The union as polygons with holes (counter-clockwise outer boundaries, clockwise holes).
  std::vector<PolygonWithHoles> regions() const {
    std::vector<ChainTraits::Curve_2> curves;
    for (const auto& [key, e] : edges_) {
      if (e.count == 0) continue;
      const bool rightward = CGAL::compare_xy(e.from, e.to) == CGAL::SMALLER;
      curves.emplace_back(SegmentTraits::Curve_2(e.from, e.to), rightward ? e.count : -e.count);
    }
    std::vector<PolygonWithHoles> out;
    if (curves.empty()) return out;
    ChainArrangement arr;
    CGAL::insert(arr, curves.begin(), curves.end());
    // Winding numbers: 0 in the unbounded face; crossing h from its right (its twin's face) to
    // its left (its face) adds shift(h).
    for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) f->set_data(INT_MIN);
    std::vector<ChainArrangement::Face_handle> stack{arr.unbounded_face()};
    arr.unbounded_face()->set_data(0);
    auto visit = [&](ChainArrangement::Face_handle f,
                     ChainArrangement::Ccb_halfedge_circulator first) {
      auto h = first;
      do {
        const auto nb = h->twin()->face();
        const int w = f->data() - shift(h);
        CAMPLACE_ASSERT(nb->data() == INT_MIN || nb->data() == w);
        if (nb->data() == INT_MIN) {
          nb->set_data(w);
          stack.push_back(nb);
        }
      } while (++h != first);
    };
    while (!stack.empty()) {
      const auto f = stack.back();
      stack.pop_back();
      if (f->has_outer_ccb()) visit(f, f->outer_ccb());
      for (auto i = f->inner_ccbs_begin(); i != f->inner_ccbs_end(); ++i) visit(f, *i);
    }
    // Keep only the edges between the union and the rest: every face is then wholly inside or
    // outside, and a face is inside when its boundary's shifts are positive.
    std::vector<ChainArrangement::Halfedge_handle> inner_edges;
    for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e)
      if ((e->face()->data() >= 1) == (e->twin()->face()->data() >= 1)) inner_edges.push_back(e);
    for (auto e : inner_edges) arr.remove_edge(e);
    auto cycle = [](ChainArrangement::Ccb_halfedge_const_circulator first) {
      Polygon2 p;
      auto h = first;
      do p.push_back(h->source()->point());
      while (++h != first);
      return p;
    };
    for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) {
      if (f->is_unbounded() || shift(f->outer_ccb()) <= 0) continue;
      std::vector<Polygon2> holes;
      for (auto i = f->inner_ccbs_begin(); i != f->inner_ccbs_end(); ++i)
        holes.push_back(cycle(*i));
      out.emplace_back(cycle(f->outer_ccb()), holes.begin(), holes.end());
    }
    return out;
  }

 private:
  struct Edge {
    int count = 0;  ///< multiplicity in the direction from → to
    Point2 from, to;
  };
  template <class H>
  static int shift(const H& h) {
    return h->direction() == CGAL::ARR_LEFT_TO_RIGHT ? h->curve().data() : -h->curve().data();
  }
  /// Keyed by the (solid, vertex) pairs of the ends, the smaller first.
  std::map<std::pair<std::pair<int, int>, std::pair<int, int>>, Edge> edges_;
};

/// A weakly simple cycle (as Boolean_set_operations_2 returns boundaries: a vertex may repeat
/// where a hole touches the outer boundary) split at its repeated vertices into simple cycles,
/// each with its own orientation; cycles without area are dropped.
std::vector<std::vector<Point2>> simple_cycles(const Polygon2& cycle) {
  std::vector<std::vector<Point2>> out;
  std::vector<Point2> stack;
  std::map<Point2, std::size_t> at;  // position of each point on the stack
  auto emit = [&](std::vector<Point2> c) {
    if (c.size() >= 3 && !CGAL::is_zero(CGAL::polygon_area_2(c.begin(), c.end(), Kernel())))
      out.push_back(std::move(c));
  };
  for (auto v = cycle.vertices_begin(); v != cycle.vertices_end(); ++v) {
    const auto it = at.find(*v);
    if (it != at.end()) {
      const std::size_t start = it->second;
      emit(std::vector<Point2>(stack.begin() + std::ptrdiff_t(start), stack.end()));
      for (std::size_t k = start; k < stack.size(); ++k) at.erase(stack[k]);
      stack.resize(start);
    }
    at.emplace(*v, stack.size());
    stack.push_back(*v);
  }
  emit(std::move(stack));
  return out;
}

/// A simple counter-clockwise cycle lifted to points on its rays with a triangulation of its
/// interior (constrained triangulation; the faces not reachable from the infinite face without
/// crossing the cycle are inside).
OutlineCycle lifted_cycle(const std::vector<Point2>& cycle, const Projector& proj) {
  using Vb = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
  using Fbi = CGAL::Triangulation_face_base_with_info_2<bool, Kernel>;  // outside
  using Fb = CGAL::Constrained_triangulation_face_base_2<Kernel, Fbi>;
  using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
  // The cycle is simple: constraints meet only at shared vertices, anything else throws.
  using Ct = CGAL::Constrained_triangulation_2<Kernel, Tds, CGAL::No_constraint_intersection_tag>;
  OutlineCycle out;
  Ct ct;
  std::vector<Ct::Vertex_handle> handles;
  for (const auto& q : cycle) {
    handles.push_back(ct.insert(q));
    handles.back()->info() = int(out.points.size());
    out.points.push_back(proj.lift(q));
  }
  for (std::size_t i = 0; i < handles.size(); ++i)
    ct.insert_constraint(handles[i], handles[(i + 1) % handles.size()]);
  for (auto fh : ct.all_face_handles()) fh->info() = false;
  std::vector<Ct::Face_handle> stack{ct.infinite_face()};
  ct.infinite_face()->info() = true;
  while (!stack.empty()) {
    const Ct::Face_handle fh = stack.back();
    stack.pop_back();
    for (int i = 0; i < 3; ++i) {
      const Ct::Face_handle nb = fh->neighbor(i);
      if (nb->info() || ct.is_constrained(Ct::Edge(fh, i))) continue;
      nb->info() = true;
      stack.push_back(nb);
    }
  }
  for (auto fh : ct.finite_face_handles())
    if (!fh->info())
      out.triangles.push_back(
          {fh->vertex(0)->info(), fh->vertex(1)->info(), fh->vertex(2)->info()});
  return out;
}

/// Adds the simple cycles of a boundary to the region: those turning the way the boundary does
/// (counter-clockwise for an outer boundary) to `same`, the others to `opposite`.
void add_cycles(const Polygon2& boundary, const Projector& proj, std::vector<OutlineCycle>& same,
                std::vector<OutlineCycle>& opposite) {
  const CGAL::Sign turn = CGAL::sign(boundary.area());
  for (auto& c : simple_cycles(boundary)) {
    const CGAL::Sign s = CGAL::sign(CGAL::polygon_area_2(c.begin(), c.end(), Kernel()));
    if (s == CGAL::NEGATIVE) std::reverse(c.begin(), c.end());
    (s == turn ? same : opposite).push_back(lifted_cycle(c, proj));
  }
}

/// True when the faces `group` of `solid` (all wholly in front of c; `image` holds their
/// vertices' images) have images with pairwise disjoint interiors and a boundary that projects
/// onto pairwise disjoint simple closed polygons, each boundary edge once (ShadowPatches).
bool valid_patch(const Faces& solid, const std::vector<int>& group,
                 const std::vector<std::optional<Point2>>& image) {
  // The faces' edges, each face counter-clockwise in the image; an edge of two faces of the group
  // is inner (a closed manifold mesh has no edge of three faces), the others bound the group.
  std::map<std::pair<int, int>, std::pair<int, int>> boundary;  // key (min, max) → directed
  std::map<std::pair<int, int>, int> uses;
  for (int f : group) {
    std::array<int, 3> t = solid.triangles[f];
    if (CGAL::orientation(*image[t[0]], *image[t[1]], *image[t[2]]) == CGAL::CLOCKWISE)
      std::swap(t[1], t[2]);
    for (int i = 0; i < 3; ++i) {
      const int p = t[i], q = t[(i + 1) % 3];
      const auto key = std::minmax(p, q);
      if (++uses[key] == 1)
        boundary[key] = {p, q};
      else
        boundary.erase(key);
    }
  }
  if (boundary.empty()) return false;  // a closed group: never in front of c only
  // Each boundary vertex on two boundary edges, and distinct vertices with distinct images.
  std::map<int, int> degree;
  for (const auto& [key, e] : boundary) {
    ++degree[e.first];
    ++degree[e.second];
  }
  std::set<Point2> images;
  for (const auto& [v, n] : degree) {
    if (n != 2) return false;
    images.insert(*image[v]);
  }
  if (images.size() != degree.size()) return false;
  // The boundary's images as a chain with winding numbers (as in Chain::regions): no crossing,
  // touching or overlapping edges (as many vertices and edges as the boundary has, each edge
  // once) and winding numbers 0 or 1 (the sum of the faces' indicators: no overlap).
  std::vector<ChainTraits::Curve_2> curves;
  for (const auto& [key, e] : boundary) {
    const Point2 &from = *image[e.first], &to = *image[e.second];
    const bool rightward = CGAL::compare_xy(from, to) == CGAL::SMALLER;
    curves.emplace_back(SegmentTraits::Curve_2(from, to), rightward ? 1 : -1);
  }
  ChainArrangement arr;
  CGAL::insert(arr, curves.begin(), curves.end());
  if (arr.number_of_vertices() != degree.size() || arr.number_of_edges() != boundary.size())
    return false;
  for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e)
    if (std::abs(e->curve().data()) != 1) return false;
  for (auto v = arr.vertices_begin(); v != arr.vertices_end(); ++v)
    if (v->degree() != 2) return false;
  for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) f->set_data(INT_MIN);
  std::vector<ChainArrangement::Face_handle> stack{arr.unbounded_face()};
  arr.unbounded_face()->set_data(0);
  auto shift = [](const auto& h) {
    return h->direction() == CGAL::ARR_LEFT_TO_RIGHT ? h->curve().data() : -h->curve().data();
  };
  auto visit = [&](ChainArrangement::Face_handle f,
                   ChainArrangement::Ccb_halfedge_circulator first) {
    auto h = first;
    do {
      const auto nb = h->twin()->face();
      if (nb->data() == INT_MIN) {
        nb->set_data(f->data() - shift(h));
        stack.push_back(nb);
      }
    } while (++h != first);
  };
  while (!stack.empty()) {
    const auto f = stack.back();
    stack.pop_back();
    if (f->data() < 0 || f->data() > 1) return false;
    if (f->has_outer_ccb()) visit(f, f->outer_ccb());
    for (auto i = f->inner_ccbs_begin(); i != f->inner_ccbs_end(); ++i) visit(f, *i);
  }
  return true;
}

}  // namespace

ImagePlane image_plane(const core::CameraSetting& setting, const core::CameraModel& model) {
  const core::Fov fov(setting, core::exact_model(model));
  const core::Vec3& d = fov.axis();
  const core::Vec3 a =
      (d.x() != 0.0 || d.y() != 0.0) ? core::Vec3(-d.y(), d.x(), 0.0) : core::Vec3(1.0, 0.0, 0.0);
  const core::Vec3 b = d.cross(a);
  ImagePlane plane;
  plane.c = to_point(setting.position);
  plane.d = to_vector(d);
  plane.a = to_vector(a);  // exactly orthogonal to d
  plane.b = CGAL::cross_product(plane.d, plane.a);
  // The FOV's directions are the cone over its edges; their images, computed in double, lie well
  // inside twice their extent (every edge has e·d > 0, fov_nef).
  double extent = 0.0;
  for (const auto& e : fov.pyramid_edges()) {
    const double depth = e.dot(d);
    CAMPLACE_ASSERT(depth > 0.0);
    extent = std::max({extent, std::abs(e.dot(a)) / depth, std::abs(e.dot(b)) / depth});
  }
  plane.half_width = FT(std::exp2(std::ceil(std::log2(2.0 * extent + 1.0))));
  return plane;
}

std::vector<OutlineRegion> occupied_outline(const ImagePlane& plane,
                                            const std::vector<const Faces*>& occupying,
                                            const std::vector<const Faces*>& blockers) {
  Projector proj(plane);
  std::vector<std::vector<int>> blocker_front;
  for (const Faces* b : blockers) blocker_front.push_back(b->front_faces(plane.c));
  std::vector<Polygon2> plain;        // images of faces nothing hides that leave the window
  std::vector<PolygonWithHoles> cut;  // images of faces partly hidden, the hidden part removed
  Chain chain;                        // faces nothing hides, wholly inside the window
  const FT& w = plane.half_width;
  for (int k = 0; k < int(occupying.size()); ++k) {
    const Faces* solid = occupying[k];
    // Each vertex's image when it lies strictly inside the window's cone (then (x − c)·d > 0).
    std::vector<std::optional<Point2>> images(solid->points.size());
    std::vector<bool> projected(solid->points.size(), false);
    auto vertex_image = [&](int v) -> const std::optional<Point2>& {
      if (!projected[v]) {
        projected[v] = true;
        const Vector u = solid->points[v] - plane.c;
        const FT depth = w * (u * plane.d), s = u * plane.a, r = u * plane.b;
        if (CGAL::abs(s) < depth && CGAL::abs(r) < depth)
          images[v] = proj.project(solid->points[v]);
      }
      return images[v];
    };
    for (int f : solid->front_faces(plane.c)) {
      const auto& tri = solid->triangles[f];
      const std::vector<Point> face{solid->points[tri[0]], solid->points[tri[1]],
                                    solid->points[tri[2]]};
      const Tetrahedron tet(plane.c, face[0], face[1], face[2]);
      const CGAL::Bbox_3 tet_box = tet.bbox();
      const Plane& fplane = solid->planes[f];
      std::vector<Polygon2> hidden;
      bool blocked = false;
      for (std::size_t b = 0; b < blockers.size(); ++b) {
        const Faces& blocker = *blockers[b];
        if (!CGAL::do_overlap(tet_box, blocker.bbox)) continue;
        for (int g : blocker_front[b]) {
          const Triangle gt = blocker.triangle(g);
          if (!CGAL::do_overlap(tet_box, gt.bbox()) || !CGAL::do_intersect(tet, gt)) continue;
          blocked = true;
          // g ∩ H̄_f: the part of g on the camera's side of f's plane (c is on the positive side).
          auto piece = clip({gt[0], gt[1], gt[2]}, [&](const Point& x) {
            return fplane.a() * x.x() + fplane.b() * x.y() + fplane.c() * x.z() + fplane.d();
          });
          if (piece.size() < 3) continue;
          if (auto image = proj.image(std::move(piece))) hidden.push_back(std::move(*image));
        }
      }
      if (!blocked && vertex_image(tri[0]) && vertex_image(tri[1]) && vertex_image(tri[2])) {
        // f's plane misses c, so its image is a proper triangle; its turn gives the order.
        std::array<int, 3> t = tri;
        if (CGAL::orientation(*images[t[0]], *images[t[1]], *images[t[2]]) == CGAL::CLOCKWISE)
          std::swap(t[1], t[2]);
        for (int i = 0; i < 3; ++i) {
          const int p = t[i], q = t[(i + 1) % 3];
          chain.add({k, p}, {k, q}, *images[p], *images[q]);
        }
        continue;
      }
      auto image = proj.image(face);
      if (!image) continue;
      if (hidden.empty()) {
        plain.push_back(std::move(*image));
        continue;
      }
      PolygonSet visible(*image);
      PolygonSet behind;
      behind.join(hidden.begin(), hidden.end());
      visible.difference(behind);
      visible.polygons_with_holes(std::back_inserter(cut));
    }
  }
  for (auto& region : chain.regions()) cut.push_back(std::move(region));
  std::vector<OutlineRegion> regions;
  if (plain.empty() && cut.empty()) return regions;
  PolygonSet all;
  all.join(plain.begin(), plain.end(), cut.begin(), cut.end());
  std::vector<PolygonWithHoles> pieces;
  all.polygons_with_holes(std::back_inserter(pieces));
  for (const auto& pwh : pieces) {
    OutlineRegion region;
    CAMPLACE_ASSERT(!pwh.is_unbounded());
    add_cycles(pwh.outer_boundary(), proj, region.outer, region.holes);
    for (auto h = pwh.holes_begin(); h != pwh.holes_end(); ++h) {
      std::vector<OutlineCycle> inside;  // an island touching a hole's boundary: never expected
      add_cycles(*h, proj, region.holes, inside);
      if (!inside.empty())
        throw std::logic_error("exact pipeline: a hole of an occupied outline holds an island");
    }
    regions.push_back(std::move(region));
  }
  return regions;
}

ShadowPatches shadow_patches(const ImagePlane& plane, const Faces& solid) {
  ShadowPatches out;
  std::vector<CGAL::Sign> side(solid.points.size());
  for (std::size_t v = 0; v < solid.points.size(); ++v)
    side[v] = CGAL::sign((solid.points[v] - plane.c) * plane.d);
  std::vector<std::optional<Point2>> image(solid.points.size());
  std::vector<int> ahead;
  for (int f : solid.front_faces(plane.c)) {
    const auto& t = solid.triangles[f];
    const int in_front = (side[t[0]] == CGAL::POSITIVE) + (side[t[1]] == CGAL::POSITIVE) +
                         (side[t[2]] == CGAL::POSITIVE);
    if (in_front == 0) continue;
    if (in_front < 3) {
      out.single.push_back(f);
      continue;
    }
    ahead.push_back(f);
    for (int v : t) {
      if (image[v]) continue;
      const Vector u = solid.points[v] - plane.c;
      const FT depth = u * plane.d;
      image[v] = Point2((u * plane.a) / depth, (u * plane.b) / depth);
    }
  }
  // Neighbours among the faces ahead, through shared edges.
  std::map<std::pair<int, int>, std::vector<int>> by_edge;
  for (int f : ahead) {
    const auto& t = solid.triangles[f];
    for (int i = 0; i < 3; ++i) by_edge[std::minmax(t[i], t[(i + 1) % 3])].push_back(f);
  }
  std::map<int, std::vector<int>> neighbours;
  for (const auto& [key, faces] : by_edge)
    for (int f : faces)
      for (int g : faces)
        if (f != g) neighbours[f].push_back(g);
  // The faces of `group` in breadth-first order through shared edges, component by component.
  auto breadth_first = [&](const std::vector<int>& group) {
    const std::set<int> members(group.begin(), group.end());
    std::set<int> seen;
    std::vector<int> order;
    for (int start : group) {
      if (!seen.insert(start).second) continue;
      std::size_t head = order.size();
      order.push_back(start);
      for (; head < order.size(); ++head)
        for (int g : neighbours[order[head]])
          if (members.count(g) && seen.insert(g).second) order.push_back(g);
    }
    return order;
  };
  // Layers first: grown through shared edges from a seed, taking each face whose image's interior
  // meets no taken face's (exact orientation tests; a grid of double boxes finds the candidates),
  // so that a fold's near and far sheets fall into different layers; then halves of the layers
  // that still fail (their boundaries touch).
  std::vector<CGAL::Bbox_2> box(solid.triangles.size());
  CGAL::Bbox_2 all;
  for (int f : ahead) {
    const auto& t = solid.triangles[f];
    box[f] = image[t[0]]->bbox() + image[t[1]]->bbox() + image[t[2]]->bbox();
    all += box[f];
  }
  constexpr int kCells = 64;
  std::function<std::vector<int>&(int, int)> grid_cell;
  const double cell_w = std::max(all.xmax() - all.xmin(), 1e-300) / kCells,
               cell_h = std::max(all.ymax() - all.ymin(), 1e-300) / kCells;
  auto cells = [&](int f, const std::function<bool(std::vector<int>&)>& visit) {
    auto index = [](double v, double lo, double w) {
      return std::clamp(int(std::floor((v - lo) / w)), 0, kCells - 1);
    };
    for (int i = index(box[f].xmin(), all.xmin(), cell_w);
         i <= index(box[f].xmax(), all.xmin(), cell_w); ++i)
      for (int j = index(box[f].ymin(), all.ymin(), cell_h);
           j <= index(box[f].ymax(), all.ymin(), cell_h); ++j)
        if (!visit(grid_cell(i, j))) return false;
    return true;
  };
  // A face's vertices, counter-clockwise in the image.
  auto ccw = [&](int f) {
    std::array<int, 3> t = solid.triangles[f];
    if (CGAL::orientation(*image[t[0]], *image[t[1]], *image[t[2]]) == CGAL::CLOCKWISE)
      std::swap(t[1], t[2]);
    return t;
  };
  // True when a line through an edge of a has b in its closed outer side. A shared vertex lies on
  // the line (no exact evaluation of a degenerate orientation).
  auto separated = [&](const std::array<int, 3>& a, const std::array<int, 3>& b) {
    for (int i = 0; i < 3; ++i) {
      const int p = a[i], q = a[(i + 1) % 3];
      if (std::none_of(b.begin(), b.end(), [&](int v) {
            return v != p && v != q &&
                   CGAL::orientation(*image[p], *image[q], *image[v]) == CGAL::LEFT_TURN;
          }))
        return true;
    }
    return false;
  };
  std::vector<std::vector<int>> todo;
  std::set<int> remaining(ahead.begin(), ahead.end());
  while (!remaining.empty()) {
    std::vector<std::vector<int>> grid(kCells * kCells);
    grid_cell = [&grid](int i, int j) -> std::vector<int>& { return grid[i * kCells + j]; };
    std::vector<int> layer;
    std::set<int> queued{*remaining.begin()};
    std::vector<int> queue{*remaining.begin()};
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const int f = queue[head];
      const auto tf = ccw(f);
      const bool free = cells(f, [&](std::vector<int>& taken) {
        for (int g : taken)
          if (CGAL::do_overlap(box[f], box[g]) && !separated(tf, ccw(g)) && !separated(ccw(g), tf))
            return false;
        return true;
      });
      if (!free) continue;
      layer.push_back(f);
      remaining.erase(f);
      cells(f, [&](std::vector<int>& taken) {
        taken.push_back(f);
        return true;
      });
      for (int g : neighbours[f])
        if (remaining.count(g) && queued.insert(g).second) queue.push_back(g);
    }
    todo.push_back(std::move(layer));
  }
  while (!todo.empty()) {
    std::vector<int> group = std::move(todo.back());
    todo.pop_back();
    if (valid_patch(solid, group, image)) {
      out.patches.push_back(std::move(group));
      continue;
    }
    // A single face in front of c always passes (a proper triangle); kept safe all the same.
    if (group.size() == 1) {
      out.single.push_back(group[0]);
      continue;
    }
    const std::vector<int> order = breadth_first(group);
    const auto half = order.begin() + std::ptrdiff_t(order.size() / 2);
    todo.emplace_back(order.begin(), half);
    todo.emplace_back(half, order.end());
  }
  return out;
}

}  // namespace camplace::exact::internal
