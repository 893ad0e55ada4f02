#pragma once
// Nef polyhedron → exact triangle soup (the boundary of marked volumes), and OFF export. Private
// to exact_pipeline.cpp.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Projection_traits_3.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/geometry.hpp"
#include "internal/kernel.hpp"

namespace camplace::exact::internal {

/// The boundary of marked volumes as an exact triangle soup.
///
/// CGAL 5.5's nef_to_pm::collect_polygon_mesh_info (convert_nef_polyhedron_to_polygon_mesh) is
/// not used: it takes every halffacet cycle for an SHalfedge cycle, but a cycle may also be an
/// SHalfloop — a vertex isolated in the facet's relative interior, e.g. the apex of a camera
/// pyramid on S's boundary (the free cone touches the model's facet on S's face only there).
/// For such a cycle it reads an empty polygon and calls front() on it (a crash). Here each
/// halffacet is triangulated in its own plane: a constrained Delaunay triangulation of its
/// boundary cycles (outer and holes) and isolated vertices under the exact projection along the
/// facet normal, keeping the faces of odd nesting depth (inside the outer cycle and outside the
/// holes). Only vertices of the Nef polyhedron are used, so the soup is exact.
struct TriangleSoup {
  std::vector<Point> points;
  std::vector<std::array<std::size_t, 3>> triangles;
  /// Appends the triangles of halffacet f, oriented outward of f's incident volume (Nef_3: the
  /// incident volume lies on the positive side of the halffacet's plane, cf. the point locator).
  void add_halffacet(Nef::Halffacet_const_handle f);

 private:
  std::unordered_map<const void*, std::size_t> index_;
  std::size_t index_of(Nef::Vertex_const_handle v) {
    const auto [it, inserted] = index_.emplace(&*v, points.size());
    if (inserted) points.push_back(v->point());
    return it->second;
  }
  /// True when the cycle turns strictly the same way at every vertex, seen along `normal`.
  static bool strictly_convex(const std::vector<Nef::Vertex_const_handle>& cycle,
                              const Vector& normal) {
    const std::size_t n = cycle.size();
    CGAL::Orientation turn = CGAL::COPLANAR;
    for (std::size_t i = 0; i < n; ++i) {
      const Point& a = cycle[i]->point();
      const auto o = CGAL::orientation(a, cycle[(i + 1) % n]->point(), cycle[(i + 2) % n]->point(),
                                       a + normal);
      if (o == CGAL::COPLANAR || (turn != CGAL::COPLANAR && o != turn)) return false;
      turn = o;
    }
    return true;
  }
  /// Appends triangle abc with its normal pointing the way of `outward`.
  void add_triangle(std::size_t a, std::size_t b, std::size_t c, const Vector& outward) {
    const Vector cross = CGAL::cross_product(points[b] - points[a], points[c] - points[a]);
    const auto side = CGAL::sign(cross * outward);
    CAMPLACE_ASSERT(side != CGAL::ZERO);
    if (side == CGAL::NEGATIVE) std::swap(b, c);
    triangles.push_back({a, b, c});
  }
};

struct FacetTriangulation {
  using Traits = CGAL::Projection_traits_3<Kernel>;
  using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::size_t, Traits>;
  using Fbi = CGAL::Triangulation_face_base_with_info_2<int, Traits>;  ///< nesting depth
  using Fb = CGAL::Constrained_triangulation_face_base_2<Traits, Fbi>;
  using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
  // Constraints of a valid facet meet only at common vertices; anything else throws rather than
  // inserting an inexact intersection point.
  using Cdt =
      CGAL::Constrained_Delaunay_triangulation_2<Traits, Tds, CGAL::No_constraint_intersection_tag>;
};

inline void TriangleSoup::add_halffacet(Nef::Halffacet_const_handle f) {
  const Vector normal = -f->plane().orthogonal_vector();  // outward of the incident volume
  std::vector<std::vector<Nef::Vertex_const_handle>> cycles;
  std::vector<Nef::Vertex_const_handle> isolated;
  for (auto fc = f->facet_cycles_begin(); fc != f->facet_cycles_end(); ++fc) {
    if (fc.is_shalfedge()) {
      Nef::SHalfedge_const_handle se(fc);
      Nef::SHalfedge_around_facet_const_circulator c(se), end(c);
      cycles.emplace_back();
      CGAL_For_all(c, end) cycles.back().push_back(c->source()->center_vertex());
    } else if (fc.is_shalfloop()) {
      Nef::SHalfloop_const_handle loop(fc);
      isolated.push_back(loop->incident_sface()->center_vertex());
    }
  }
  if (cycles.empty()) throw std::logic_error("exact pipeline: a facet without a boundary cycle");
  // Each cycle from its least vertex, the cycles and isolated vertices in the order of those
  // (CGAL::compare_xyz): the fan and the triangulation's insertion order, and so its triangles,
  // depend only on the facet, not on where the Nef polyhedron's lists start (which the order of
  // the Boolean operations that built it, e.g. on helper threads, can change).
  auto less = [](Nef::Vertex_const_handle a, Nef::Vertex_const_handle b) {
    return CGAL::compare_xyz(a->point(), b->point()) == CGAL::SMALLER;
  };
  for (auto& cycle : cycles)
    std::rotate(cycle.begin(), std::min_element(cycle.begin(), cycle.end(), less), cycle.end());
  std::sort(cycles.begin(), cycles.end(),
            [&](const auto& a, const auto& b) { return less(a.front(), b.front()); });
  std::sort(isolated.begin(), isolated.end(), less);
  if (cycles.size() == 1 && isolated.empty() && strictly_convex(cycles[0], normal)) {
    // A fan; the cycle of a facet is simple, so turning one way at every vertex means convex.
    const auto& cycle = cycles[0];
    for (std::size_t i = 1; i + 1 < cycle.size(); ++i)
      add_triangle(index_of(cycle[0]), index_of(cycle[i]), index_of(cycle[i + 1]), normal);
    return;
  }
  using Cdt = FacetTriangulation::Cdt;
  Cdt cdt{FacetTriangulation::Traits(normal)};
  try {
    for (const auto& cycle : cycles) {
      std::vector<Cdt::Vertex_handle> handles;
      for (const auto& v : cycle) {
        handles.push_back(cdt.insert(v->point()));
        handles.back()->info() = index_of(v);
      }
      for (std::size_t i = 0; i < handles.size(); ++i)
        cdt.insert_constraint(handles[i], handles[(i + 1) % handles.size()]);
    }
    for (const auto& v : isolated) cdt.insert(v->point())->info() = index_of(v);
  } catch (const Cdt::Intersection_of_constraints_exception&) {
    throw std::logic_error("exact pipeline: a facet whose boundary cycles cross");
  }
  if (cdt.dimension() != 2) throw std::logic_error("exact pipeline: a degenerate facet");
  // Nesting depth: 0 for the faces reachable from the infinite face without crossing a
  // constraint, +1 for each constraint crossed. Each constrained edge bounds the facet on
  // exactly one side, so the facet is the union of the faces of odd depth.
  for (auto fh : cdt.all_face_handles()) fh->info() = -1;
  std::vector<Cdt::Face_handle> stack{cdt.infinite_face()}, next;
  cdt.infinite_face()->info() = 0;
  for (int depth = 0; !stack.empty(); ++depth) {
    while (!stack.empty()) {
      const Cdt::Face_handle fh = stack.back();
      stack.pop_back();
      for (int i = 0; i < 3; ++i) {
        const Cdt::Face_handle nb = fh->neighbor(i);
        if (nb->info() != -1) continue;
        if (cdt.is_constrained(Cdt::Edge(fh, i))) {
          next.push_back(nb);
        } else {
          nb->info() = depth;
          stack.push_back(nb);
        }
      }
    }
    for (auto fh : next)
      if (fh->info() == -1) {
        fh->info() = depth + 1;
        stack.push_back(fh);
      }
    next.clear();
  }
  for (auto fh : cdt.finite_face_handles()) {
    CAMPLACE_ASSERT(fh->info() >= 0);
    if (fh->info() % 2 == 1)
      add_triangle(fh->vertex(0)->info(), fh->vertex(1)->info(), fh->vertex(2)->info(), normal);
  }
}

/// Boundary triangles of every marked volume of nef (the halffacets incident to them).
inline TriangleSoup nef_soup(const Nef& nef) {
  TriangleSoup soup;
  for (auto f = nef.halffacets_begin(); f != nef.halffacets_end(); ++f)
    if (f->incident_volume()->mark() && !f->twin()->incident_volume()->mark())
      soup.add_halffacet(f);
  return soup;
}

/// Writes a triangle mesh as an OFF file (core::write_file_atomically).
inline void write_off(const std::string& path, const std::vector<core::Vec3>& vertices,
                      const std::vector<std::array<std::size_t, 3>>& triangles) {
  std::ostringstream out;
  out << "OFF\n" << vertices.size() << " " << triangles.size() << " 0\n";
  out << std::setprecision(17);
  for (const auto& v : vertices) out << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (const auto& t : triangles) out << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  // Atomically, every write checked: a full disk is an error naming the file, not an empty file.
  core::write_file_atomically(path, out.str());
}

/// An exact soup in an order that depends only on its triangles, not on the order it lists them
/// and their vertices in (a Nef polyhedron's volumes, facets and vertices come in the order of
/// the operations that built it): equal points merged, points sorted by CGAL::compare_xyz, each
/// triangle started at its least vertex (its orientation kept), triangles sorted.
inline void canonical_order(std::vector<Point>& points,
                            std::vector<std::array<std::size_t, 3>>& triangles) {
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return CGAL::compare_xyz(points[a], points[b]) == CGAL::SMALLER;
  });
  std::vector<Point> sorted;
  std::vector<std::size_t> rank(points.size());
  for (const std::size_t i : order) {
    if (sorted.empty() || CGAL::compare_xyz(sorted.back(), points[i]) != CGAL::EQUAL)
      sorted.push_back(points[i]);
    rank[i] = sorted.size() - 1;
  }
  for (auto& t : triangles) {
    t = {rank[t[0]], rank[t[1]], rank[t[2]]};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  }
  std::sort(triangles.begin(), triangles.end());
  points = std::move(sorted);
}

/// Writes an exact soup rounded to double as an OFF file (atomically), in canonical order: the
/// same surface, triangulated the same way, gives the same file.
inline void export_soup(const std::string& path, std::vector<Point> points,
                        std::vector<std::array<std::size_t, 3>> triangles) {
  canonical_order(points, triangles);
  std::vector<core::Vec3> v;
  v.reserve(points.size());
  for (const auto& p : points) v.push_back(to_vec3(p));
  write_off(path, v, triangles);
}

}  // namespace camplace::exact::internal
