#pragma once
// Scene objects in exact coordinates, point containment, convex hulls as Nef polyhedra and their
// unions. Private to exact_pipeline.cpp.
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <array>
#include <optional>
#include <vector>

#include "camplace/core/geometry.hpp"
#include "internal/faces.hpp"
#include "internal/kernel.hpp"

namespace camplace::exact::internal {

/// One scene object with its closed solid as a Nef polyhedron, built on first use.
struct Solid : Faces {
  mutable std::optional<Nef> nef;

  explicit Solid(const core::TriangleMesh& mesh) : Faces(mesh) {}

  /// The closed solid as a Nef polyhedron (built on first use).
  const Nef& as_nef() const {
    if (!nef) {
      std::vector<std::vector<std::size_t>> polygons;
      for (const auto& t : triangles)
        polygons.push_back({std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2])});
      SurfaceMesh sm;
      CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, polygons, sm);
      nef.emplace(sm);
    }
    return *nef;
  }
};

/// True when the Nef polyhedron contains p (closed sets: boundary items count by their mark).
inline bool nef_contains(const Nef& nef, const Point& p) {
  const auto o = nef.locate(p);
  Nef::Vertex_const_handle v;
  Nef::Halfedge_const_handle e;
  Nef::Halffacet_const_handle f;
  Nef::Volume_const_handle c;
  if (CGAL::assign(v, o)) return v->mark();
  if (CGAL::assign(e, o)) return e->mark();
  if (CGAL::assign(f, o)) return f->mark();
  if (CGAL::assign(c, o)) return c->mark();
  return false;
}

/// True when p lies in the closed solid.
inline bool solid_contains(const Solid& solid, const Point& p) {
  if (solid.convex) {
    for (const auto& plane : solid.planes)
      if (plane.oriented_side(p) == CGAL::ON_POSITIVE_SIDE) return false;
    return true;
  }
  return nef_contains(solid.as_nef(), p);
}

/// Nef polyhedron of the convex hull of the points; empty when they do not span 3D.
inline Nef hull_nef(const std::vector<Point>& pts) {
  if (pts.size() < 4) return Nef();
  std::size_t i1 = 0, i2 = 0;
  for (std::size_t i = 1; i < pts.size() && i1 == 0; ++i)
    if (pts[i] != pts[0]) i1 = i;
  if (i1 == 0) return Nef();
  for (std::size_t i = 1; i < pts.size() && i2 == 0; ++i)
    if (!CGAL::collinear(pts[0], pts[i1], pts[i])) i2 = i;
  if (i2 == 0) return Nef();
  bool solid = false;
  for (std::size_t i = 1; i < pts.size() && !solid; ++i)
    solid = !CGAL::coplanar(pts[0], pts[i1], pts[i2], pts[i]);
  if (!solid) return Nef();
  SurfaceMesh sm;
  CGAL::convex_hull_3(pts.begin(), pts.end(), sm);
  return Nef(sm);
}

/// Union of many polyhedra, merged pairwise (balanced) — much cheaper than a running union when
/// there are many pieces (e.g. per-face frustums of a non-convex mesh).
inline Nef union_all(std::vector<Nef> parts) {
  parts.erase(std::remove_if(parts.begin(), parts.end(), [](const Nef& n) { return n.is_empty(); }),
              parts.end());
  if (parts.empty()) return Nef();
  while (parts.size() > 1) {
    std::vector<Nef> next;
    for (std::size_t i = 0; i + 1 < parts.size(); i += 2) next.push_back(parts[i] + parts[i + 1]);
    if (parts.size() % 2 == 1) next.push_back(std::move(parts.back()));
    parts = std::move(next);
  }
  return std::move(parts.front());
}

/// The closed box as a Nef polyhedron.
inline Nef box_nef(const core::Box3& box) {
  std::vector<Point> pts;
  for (int i = 0; i < 8; ++i)
    pts.emplace_back((i & 1) ? box.max.x() : box.min.x(), (i & 2) ? box.max.y() : box.min.y(),
                     (i & 4) ? box.max.z() : box.min.z());
  return hull_nef(pts);
}

}  // namespace camplace::exact::internal
