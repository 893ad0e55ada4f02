#pragma once
// What one camera cannot see past (SPEC §3), as Nef polyhedra: its FOV, the shadow volumes of
// occluding objects and the silhouette cones of occupying ones (cones over their image-plane
// outlines, or per face as a reference).
// Cones and shadows are convex hulls of exact points: K(P) = conv(c, c + T(P − c)) and
// shadow(P) = conv(P, c + T(P − c)) for a convex P, with T a power of two large enough that the
// far cap lies outside the pipeline's clip box (a box around S: only M ⊂ S matters). Private to
// exact_pipeline.cpp.
#include <CGAL/Interval_nt.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/scene.hpp"
#include "internal/kernel.hpp"
#include "internal/outline.hpp"
#include "internal/solids.hpp"

namespace camplace::exact::internal {

/// A camera's centre c and how far the clip box reaches from it.
struct ViewPoint {
  Point position;
  double reach = 0.0;  ///< upper bound (m) of the distance from c to any point of the clip box
};

/// The view point of a camera for the clip box `area` (m, world frame).
inline ViewPoint view_point(const core::CameraSetting& setting, const core::Box3& area) {
  ViewPoint cam;
  cam.position = to_point(setting.position);
  for (int i = 0; i < 8; ++i) {
    const core::Vec3 corner((i & 1) ? area.max.x() : area.min.x(),
                            (i & 2) ? area.max.y() : area.min.y(),
                            (i & 4) ? area.max.z() : area.min.z());
    cam.reach = std::max(cam.reach, (corner - setting.position).norm());
  }
  cam.reach = cam.reach * 1.01 + 1e-6;
  return cam;
}

/// The camera's FOV (SPEC §1): a cone's inscribed regular k-sided pyramid, a pyramid, or a
/// frustum (the 4-sided pyramid over the image rectangle, turned by the roll), its edges shared
/// with core (and thus the voxel pipeline), cut by the near plane (p − c)·d ≥ near and the far
/// plane (p − c)·d ≤ range; unlimited ones are cut beyond the clip box. Not yet intersected with
/// it.
inline Nef fov_nef(const ViewPoint& cam, const core::CameraSetting& setting,
                   const core::CameraModel& model) {
  const core::Fov fov(setting, core::exact_model(model));
  const Vector d = to_vector(core::view_direction(setting));
  // Every point of the hull lies on an edge ray c + s·e (e exact from its double), so its side
  // faces are the planes through c and two consecutive edges, whatever the caps.
  std::vector<Point> pts;
  auto cap = [&](const FT& depth) {  // the points of the edges at axial depth `depth`
    for (const auto& e : fov.pyramid_edges()) {
      const Vector ev = to_vector(e);
      pts.push_back(cam.position + ev * (depth / (ev * d)));
    }
  };
  if (model.near > 0.0) {
    cap(FT(model.near));
  } else {
    pts.push_back(cam.position);
  }
  if (model.range) {
    cap(FT(*model.range));
  } else {
    // The far cap at axial depth at least twice the reach, so that no point of the clip box
    // (axial depth ≤ reach) lies beyond it, at every opening angle: each edge e is scaled to
    // depth T ≥ 2·reach, T a power of two (the points' coordinates stay short). For a wide
    // frustum (up to 179°) e·d is small and the cap lies far out, as it must.
    double min_cos = 1.0;
    for (const auto& e : fov.pyramid_edges()) min_cos = std::min(min_cos, e.dot(fov.axis()));
    CAMPLACE_ASSERT(min_cos > 0.0);
    const FT t(std::exp2(std::ceil(std::log2(2.0 * cam.reach / min_cos))));
    // Scaled along the edges: depth t·(e·d) ≥ 2·reach for every edge.
    for (const auto& e : fov.pyramid_edges()) pts.push_back(cam.position + to_vector(e) * t);
  }
  return hull_nef(pts);
}

/// A power of two T with c + T(x − c) outside S for every x at distance ≥ h from c.
inline FT scale_for(const ViewPoint& cam, double h) {
  CAMPLACE_ASSERT(h > 0.0);
  h = std::max(h, 1e-200);  // never reached for a camera outside the solid
  return FT(std::exp2(std::ceil(std::log2(2.0 * cam.reach / h))));
}

/// The faces of the solid whose outer side holds c.
inline std::vector<int> front_faces(const ViewPoint& cam, const Solid& solid) {
  return solid.front_faces(cam.position);
}

inline double plane_distance_lower(const ViewPoint& cam, const Plane& plane) {
  return sqrt_lower(CGAL::squared_distance(cam.position, plane));
}

/// Lower bound of the distance from the camera to a convex solid it lies outside of.
inline double convex_distance_lower(const ViewPoint& cam, const Solid& solid,
                                    const std::vector<int>& front) {
  double h = 0.0;
  for (int i : front) h = std::max(h, plane_distance_lower(cam, solid.planes[i]));
  return h;
}

/// The points c + t(p − c).
inline std::vector<Point> scaled(const ViewPoint& cam, const std::vector<Point>& pts, const FT& t) {
  std::vector<Point> out;
  out.reserve(pts.size());
  for (const auto& p : pts) out.push_back(cam.position + (p - cam.position) * t);
  return out;
}

/// The shadow of one front face f, cut beyond the clip box: conv(f, c + T(f − c)).
inline Nef face_shadow(const ViewPoint& cam, const Solid& solid, int f) {
  const FT t = scale_for(cam, plane_distance_lower(cam, solid.planes[f]));
  const auto& tri = solid.triangles[f];
  std::vector<Point> pts{solid.points[tri[0]], solid.points[tri[1]], solid.points[tri[2]]};
  const auto far = scaled(cam, pts, t);
  pts.insert(pts.end(), far.begin(), far.end());
  return hull_nef(pts);
}

/// The shadow of a patch of front faces (ShadowPatches, outline.hpp), cut beyond the clip box:
/// {c + s(x − c) : x on the patch, 1 ≤ s ≤ T}, the union of its faces' shadows. Its boundary is
/// the patch itself (outward as the solid's faces: c lies on their outer side), the patch scaled
/// from c by T (reversed) and, over each boundary edge p → q of the patch (as its face runs), the
/// wall q, p, c + T(p − c), c + T(q − c) in the plane of c, p and q. The patch's images overlap
/// nowhere and its boundary projects onto disjoint simple polygons, so every ray from c meets the
/// patch at most once and the walls meet only along the rays over common vertices: the soup is a
/// closed oriented 2-manifold bounding the sweep. T: the patch lies at least the smallest distance
/// from c to its faces' planes away, so the scaled patch lies beyond the clip box (scale_for).
inline Nef patch_shadow(const ViewPoint& cam, const Solid& solid, const std::vector<int>& patch) {
  double h = HUGE_VAL;
  for (int f : patch) h = std::min(h, plane_distance_lower(cam, solid.planes[f]));
  const FT t = scale_for(cam, h);
  std::vector<Point> pts;
  std::unordered_map<int, std::size_t> near;  // mesh vertex → index of the near point; far: + 1
  auto index = [&](int v) {
    const auto [it, inserted] = near.emplace(v, pts.size());
    if (inserted) {
      pts.push_back(solid.points[v]);
      pts.push_back(cam.position + (solid.points[v] - cam.position) * t);
    }
    return it->second;
  };
  std::vector<std::vector<std::size_t>> faces;
  std::map<std::pair<int, int>, std::pair<int, int>> boundary;  // key (min, max) → p → q
  for (int f : patch) {
    const auto& tri = solid.triangles[f];
    const std::size_t a = index(tri[0]), b = index(tri[1]), c = index(tri[2]);
    faces.push_back({a, b, c});
    faces.push_back({c + 1, b + 1, a + 1});
    for (int i = 0; i < 3; ++i) {
      const int p = tri[i], q = tri[(i + 1) % 3];
      const auto key = std::minmax(p, q);
      if (!boundary.erase(key)) boundary.emplace(key, std::make_pair(p, q));
    }
  }
  for (const auto& [key, e] : boundary) {
    const std::size_t p = near.at(e.first), q = near.at(e.second);
    faces.push_back({q, p, p + 1});
    faces.push_back({q, p + 1, q + 1});
  }
  SurfaceMesh sm;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(pts, faces, sm);
  CAMPLACE_ASSERT(CGAL::is_closed(sm));
  return Nef(sm);
}

/// Points p whose segment [c, p] meets the solid, where they can meet camera c's FOV (c outside
/// the solid; the FOV lies in {c} ∪ {(x − c)·d > 0}), cut beyond the clip box. A convex solid: one
/// hull. Otherwise the union of the shadows of its front faces' patches (shadow_patches in the
/// image plane `image`: a few closed polyhedra, each from one polygon soup) and of the faces that
/// cross the plane (x − c)·d = 0 one by one; with `per_face` (the reference,
/// ExactOptions::face_shadows) the union of every front face's shadow. Within the FOV the two are
/// the same point set (docs/design/exact-model.md E2).
inline Nef shadow(const ViewPoint& cam, const ImagePlane& image, const Solid& solid,
                  bool per_face) {
  const auto front = front_faces(cam, solid);
  if (front.empty()) return Nef();
  if (solid.convex) {
    const FT t = scale_for(cam, convex_distance_lower(cam, solid, front));
    auto pts = solid.points;
    const auto far = scaled(cam, solid.points, t);
    pts.insert(pts.end(), far.begin(), far.end());
    return hull_nef(pts);
  }
  std::vector<Nef> parts;
  if (per_face) {
    for (int f : front) parts.push_back(face_shadow(cam, solid, f));
    return union_all(std::move(parts));
  }
  const ShadowPatches split = shadow_patches(image, solid);
  for (const auto& patch : split.patches) parts.push_back(patch_shadow(cam, solid, patch));
  for (int f : split.single) parts.push_back(face_shadow(cam, solid, f));
  return union_all(std::move(parts));
}

/// True when a front face of a blocker meets conv(c, f) for a front face f of the solid: the
/// blocker may hide part of it (occupied_cone's test).
inline bool may_be_hidden(const ViewPoint& cam, const Solid& solid,
                          const std::vector<const Solid*>& blockers) {
  CGAL::Bbox_3 reach = solid.bbox + cam.position.bbox();
  std::vector<std::pair<const Solid*, std::vector<int>>> near;
  for (const Solid* b : blockers)
    if (CGAL::do_overlap(reach, b->bbox)) near.push_back({b, front_faces(cam, *b)});
  if (near.empty()) return false;
  for (int f : front_faces(cam, solid)) {
    const auto& tri = solid.triangles[f];
    const Tetrahedron tet(cam.position, solid.points[tri[0]], solid.points[tri[1]],
                          solid.points[tri[2]]);
    const CGAL::Bbox_3 tet_box = tet.bbox();
    for (const auto& [b, front] : near) {
      if (!CGAL::do_overlap(tet_box, b->bbox)) continue;
      for (int g : front) {
        const Triangle gt = b->triangle(g);
        if (CGAL::do_overlap(tet_box, gt.bbox()) && CGAL::do_intersect(tet, gt)) return true;
      }
    }
  }
  return false;
}

/// The silhouette cone of the visible part of an occupying solid: rays from c whose first hit
/// among {solid} ∪ blockers is on the solid (c outside all of them; blockers occlude).
///
/// For each front face f: K(f) ∖ ∪ K(g ∩ H̄_f), g a front face of a blocker meeting conv(c, f),
/// H̄_f the closed half-space of f's plane on the camera's side. A ray toward f that meets a
/// blocker first is free up to the blocker and lies in its shadow beyond, so removing the whole
/// ray from K(f) is exact. The reference construction (ExactOptions::face_cones): the pipeline
/// builds the same set from outlines (occupied_outline, outline_cone).
inline Nef occupied_cone(const ViewPoint& cam, const Solid& solid,
                         const std::vector<const Solid*>& blockers) {
  const auto front = front_faces(cam, solid);
  if (front.empty()) return Nef();
  // For each front face f: the front faces g of blockers that meet conv(c, f).
  std::vector<std::vector<std::pair<const Solid*, int>>> blocking(front.size());
  bool any_blocking = false;
  for (std::size_t k = 0; k < front.size(); ++k) {
    const auto& tri = solid.triangles[front[k]];
    const Tetrahedron tet(cam.position, solid.points[tri[0]], solid.points[tri[1]],
                          solid.points[tri[2]]);
    const CGAL::Bbox_3 tet_box = tet.bbox();
    for (const Solid* b : blockers) {
      if (!CGAL::do_overlap(tet_box, b->bbox)) continue;
      for (int g : front_faces(cam, *b)) {
        const Triangle gt = b->triangle(g);
        if (CGAL::do_overlap(tet_box, gt.bbox()) && CGAL::do_intersect(tet, gt)) {
          blocking[k].push_back({b, g});
          any_blocking = true;
        }
      }
    }
  }
  if (solid.convex && !any_blocking) {
    const FT t = scale_for(cam, convex_distance_lower(cam, solid, front));
    auto pts = scaled(cam, solid.points, t);
    pts.push_back(cam.position);
    return hull_nef(pts);
  }
  std::vector<Nef> cones;
  for (std::size_t k = 0; k < front.size(); ++k) {
    const auto& tri = solid.triangles[front[k]];
    const Plane& fplane = solid.planes[front[k]];
    const FT t = scale_for(cam, plane_distance_lower(cam, fplane));
    auto pts = scaled(cam, {solid.points[tri[0]], solid.points[tri[1]], solid.points[tri[2]]}, t);
    pts.push_back(cam.position);
    Nef cone = hull_nef(pts);
    std::vector<Nef> blocked_parts;
    for (const auto& [b, g] : blocking[k]) {
      // g ∩ H̄_f: the part of g on the camera's side of f's plane (c is on the positive side).
      const auto& gt = b->triangles[g];
      std::vector<Point> piece;
      for (int j = 0; j < 3; ++j) {
        const Point& p = b->points[gt[j]];
        const Point& q = b->points[gt[(j + 1) % 3]];
        const auto sp = fplane.oriented_side(p), sq = fplane.oriented_side(q);
        if (sp != CGAL::ON_NEGATIVE_SIDE) piece.push_back(p);
        if ((sp == CGAL::ON_POSITIVE_SIDE && sq == CGAL::ON_NEGATIVE_SIDE) ||
            (sp == CGAL::ON_NEGATIVE_SIDE && sq == CGAL::ON_POSITIVE_SIDE)) {
          const auto x = CGAL::intersection(Segment(p, q), fplane);
          const Point* xp = x ? boost::get<Point>(&*x) : nullptr;
          CAMPLACE_ASSERT(xp != nullptr);
          if (xp) piece.push_back(*xp);
        }
      }
      if (piece.size() < 3) continue;
      const FT tg = scale_for(cam, plane_distance_lower(cam, b->planes[g]));
      auto bpts = scaled(cam, piece, tg);
      bpts.push_back(cam.position);
      blocked_parts.push_back(hull_nef(bpts));
    }
    const Nef blocked = union_all(std::move(blocked_parts));
    if (!blocked.is_empty()) cone -= blocked;
    cones.push_back(std::move(cone));
  }
  return union_all(std::move(cones));
}

/// The cone from c over a simple cycle of the image plane, cut beyond the clip box: a closed
/// polyhedron, star-shaped from c (triangles c, p'_{i+1}, p'_i on the sides and the cycle's
/// triangles scaled from c by T as the far cap, all outward: the cycle turns counter-clockwise
/// about the viewing direction). T puts every cap triangle beyond the clip box: each lies at
/// T times the distance from c to its unscaled triangle, which misses c (its image is a proper
/// triangle).
inline Nef cycle_cone(const ViewPoint& cam, const OutlineCycle& cycle) {
  double h = HUGE_VAL;
  for (const auto& t : cycle.triangles) {
    const Triangle tri(cycle.points[t[0]], cycle.points[t[1]], cycle.points[t[2]]);
    h = std::min(h, sqrt_lower(CGAL::squared_distance(cam.position, tri)));
  }
  const auto far = scaled(cam, cycle.points, scale_for(cam, h));
  std::vector<Point> pts{cam.position};
  pts.insert(pts.end(), far.begin(), far.end());
  const std::size_t n = cycle.points.size();
  std::vector<std::vector<std::size_t>> faces;
  for (std::size_t i = 0; i < n; ++i) faces.push_back({0, 1 + (i + 1) % n, 1 + i});
  for (const auto& tri : cycle.triangles)
    faces.push_back({1 + std::size_t(tri[0]), 1 + std::size_t(tri[1]), 1 + std::size_t(tri[2])});
  SurfaceMesh sm;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(pts, faces, sm);
  return Nef(sm);
}

/// The silhouette cones of occupying solids from their outline (occupied_outline), cut beyond the
/// clip box: for each region, the cones over its outer cycles minus those over its holes. The
/// same point set as the union of occupied_cone over the solids within the FOV, up to boundaries,
/// so the regularised model is the same.
inline Nef outline_cone(const ViewPoint& cam, const std::vector<OutlineRegion>& regions) {
  std::vector<Nef> parts;
  for (const auto& region : regions) {
    std::vector<Nef> outer, holes;
    for (const auto& cycle : region.outer) outer.push_back(cycle_cone(cam, cycle));
    for (const auto& cycle : region.holes) holes.push_back(cycle_cone(cam, cycle));
    Nef cone = union_all(std::move(outer));
    const Nef removed = union_all(std::move(holes));
    if (!removed.is_empty()) cone -= removed;
    parts.push_back(std::move(cone));
  }
  return union_all(std::move(parts));
}

/// Certified bounds of the image-plane coordinates (s, r) of points that all lie strictly in front
/// of the camera ((x − c)·d > 0); nullopt when some point may not.
struct ImageBounds {
  double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
};
inline std::optional<ImageBounds> image_bounds(const ImagePlane& plane,
                                               const std::vector<Point>& pts) {
  using I = CGAL::Interval_nt<>;
  auto iv = [](const FT& x) { return I(CGAL::to_interval(x)); };
  const I c[3] = {iv(plane.c.x()), iv(plane.c.y()), iv(plane.c.z())};
  const I d[3] = {iv(plane.d.x()), iv(plane.d.y()), iv(plane.d.z())};
  const I a[3] = {iv(plane.a.x()), iv(plane.a.y()), iv(plane.a.z())};
  const I b[3] = {iv(plane.b.x()), iv(plane.b.y()), iv(plane.b.z())};
  ImageBounds out;
  for (const auto& p : pts) {
    const I x[3] = {iv(p.x()) - c[0], iv(p.y()) - c[1], iv(p.z()) - c[2]};
    const I depth = x[0] * d[0] + x[1] * d[1] + x[2] * d[2];
    if (!(depth.inf() > 0.0)) return std::nullopt;
    const I st[2] = {(x[0] * a[0] + x[1] * a[1] + x[2] * a[2]) / depth,
                     (x[0] * b[0] + x[1] * b[1] + x[2] * b[2]) / depth};
    for (int k = 0; k < 2; ++k) {
      out.lo[k] = std::min(out.lo[k], st[k].inf());
      out.hi[k] = std::max(out.hi[k], st[k].sup());
    }
  }
  return out;
}

/// False only when no ray from c through one of the solids meets the convex region with the
/// corners `region` (then no shadow or silhouette cone of theirs meets it: each lies in
/// {c + t(x − c) : x ∈ conv(solid), t ≥ 0}). Decided in the image plane: with the region and a
/// solid wholly in front of c, a common point's image lies in both convex images, so in both
/// images' bounds (docs/design/exact-model.md E3).
inline bool sight_may_meet(const ImagePlane& plane, const std::vector<const Solid*>& solids,
                           const std::vector<Point>& region) {
  if (solids.empty()) return false;
  const auto r = image_bounds(plane, region);
  if (!r) return true;
  for (const Solid* s : solids) {
    const auto b = image_bounds(plane, s->points);
    if (!b) return true;
    if (b->lo[0] <= r->hi[0] && r->lo[0] <= b->hi[0] && b->lo[1] <= r->hi[1] &&
        r->lo[1] <= b->hi[1])
      return true;
  }
  return false;
}

/// True when c lies in one of the closed solids (such a camera sees nothing, SPEC §3.3).
inline bool camera_inside(const ViewPoint& cam, const std::vector<const Solid*>& solids) {
  for (const Solid* s : solids)
    if (CGAL::do_overlap(s->bbox, cam.position.bbox()) && solid_contains(*s, cam.position))
      return true;
  return false;
}

}  // namespace camplace::exact::internal
