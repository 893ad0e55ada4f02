// The exact reference pipeline (SPEC §6). All Nef code of camplace lives in this one translation
// unit (STYLE.md: each Nef TU costs ~35 s and ~1.6 GB to compile).
//
// Construction, for camera c and one state (SPEC §3):
//   Free_c = (FOV_c ∩ S) ∖ (U ∪ V)
//   U = ∪ shadow volumes of the non-occupying objects (static; dynamic in `modelled` mode):
//       points p whose segment [c, p] meets the object;
//   V = ∪ over occupying objects O (targets; dynamic in `masked` mode) and their front faces f of
//       K(f) ∖ ∪ K(g ∩ H̄_f), g a front face of a non-occupying object meeting conv(c, f),
//       H̄_f the closed half-space of f's plane on the camera's side and K(X) the cone from c
//       through X. A ray toward f that meets a non-occupying object first is free up to that
//       object and lies in its shadow beyond, so removing the whole ray from K(f) is exact. A ray
//       whose first hit is occupying lies wholly in V (the silhouette cone).
//   M = reg(S ∖ obstacles ∖ ∪_c Free_c) (SPEC §4, regularised: closure of the interior).
// Cones and shadows are convex hulls of exact points: K(P) = conv(c, c + T(P − c)) and
// shadow(P) = conv(P, c + T(P − c)) for a convex P, with T large enough that the far cap lies
// outside S (only M ⊂ S matters). Every double input is converted exactly to a rational.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Nef_polyhedron_3.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Projection_traits_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/convex_hull_3.h>
#include <CGAL/intersections.h>
#include <CGAL/squared_distance_3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "camplace/core/distance.hpp"
#include "camplace/core/err.hpp"
#include "camplace/core/error.hpp"
#include "camplace/exact/evaluator.hpp"

namespace camplace::exact {
namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using FT = Kernel::FT;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using Plane = Kernel::Plane_3;
using Triangle = Kernel::Triangle_3;
using Segment = Kernel::Segment_3;
using Tetrahedron = Kernel::Tetrahedron_3;
using Nef = CGAL::Nef_polyhedron_3<Kernel>;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

Point to_point(const core::Vec3& v) { return Point(v.x(), v.y(), v.z()); }  // exact
Vector to_vector(const core::Vec3& v) { return Vector(v.x(), v.y(), v.z()); }
core::Vec3 to_vec3(const Point& p) {
  return {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())};
}

/// "p/q" of an exact rational.
std::string fraction_string(const FT& x) {
  const auto& e = CGAL::exact(x);
  using ET = std::decay_t<decltype(e)>;
  typename CGAL::Fraction_traits<ET>::Numerator_type num;
  typename CGAL::Fraction_traits<ET>::Denominator_type den;
  typename CGAL::Fraction_traits<ET>::Decompose()(e, num, den);
  std::ostringstream out;
  out << num << "/" << den;
  return out.str();
}

/// A lower bound (m) of sqrt of an exact non-negative squared length.
double sqrt_lower(const FT& sq) {
  const double lo = CGAL::to_interval(CGAL::exact(sq)).first;
  return lo <= 0.0 ? 0.0 : std::sqrt(lo) * (1.0 - 1e-12);
}

/// One scene object in exact coordinates.
struct Solid {
  std::vector<Point> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<Plane> planes;  ///< supporting planes, positive side = outside
  bool convex = true;
  CGAL::Bbox_3 bbox;
  mutable std::optional<Nef> nef;

  explicit Solid(const core::TriangleMesh& mesh) {
    points.reserve(mesh.vertices.size());
    for (const auto& v : mesh.vertices) points.push_back(to_point(v));
    triangles = mesh.triangles;
    for (const auto& t : triangles)
      planes.emplace_back(points[t[0]], points[t[1]], points[t[2]]);
    // Convex when every vertex lies on the closed inner side of every face plane.
    for (const auto& plane : planes) {
      for (const auto& p : points) {
        if (plane.oriented_side(p) == CGAL::ON_POSITIVE_SIDE) {
          convex = false;
          break;
        }
      }
      if (!convex) break;
    }
    bbox = CGAL::bbox_3(points.begin(), points.end());
  }

  Triangle triangle(int i) const {
    const auto& t = triangles[i];
    return Triangle(points[t[0]], points[t[1]], points[t[2]]);
  }

  const Nef& as_nef() const {
    if (!nef) {
      std::vector<std::vector<std::size_t>> polygons;
      for (const auto& t : triangles) polygons.push_back({std::size_t(t[0]), std::size_t(t[1]),
                                                          std::size_t(t[2])});
      SurfaceMesh sm;
      CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, polygons, sm);
      nef.emplace(sm);
    }
    return *nef;
  }
};

/// True when the Nef polyhedron contains p (closed sets: boundary items count by their mark).
bool nef_contains(const Nef& nef, const Point& p) {
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
bool solid_contains(const Solid& solid, const Point& p) {
  if (solid.convex) {
    for (const auto& plane : solid.planes)
      if (plane.oriented_side(p) == CGAL::ON_POSITIVE_SIDE) return false;
    return true;
  }
  return nef_contains(solid.as_nef(), p);
}

/// Nef polyhedron of the convex hull of the points; empty when they do not span 3D.
Nef hull_nef(const std::vector<Point>& pts) {
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
Nef union_all(std::vector<Nef> parts) {
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

Nef box_nef(const core::Box3& box) {
  std::vector<Point> pts;
  for (int i = 0; i < 8; ++i)
    pts.emplace_back((i & 1) ? box.max.x() : box.min.x(), (i & 2) ? box.max.y() : box.min.y(),
                     (i & 4) ? box.max.z() : box.min.z());
  return hull_nef(pts);
}

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
  using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Traits, Tds,
                                                         CGAL::No_constraint_intersection_tag>;
};

void TriangleSoup::add_halffacet(Nef::Halffacet_const_handle f) {
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
  if (cycles.empty())
    throw std::logic_error("exact pipeline: a facet without a boundary cycle");
  if (cycles.size() == 1 && isolated.empty() && cycles[0].size() == 3) {
    add_triangle(index_of(cycles[0][0]), index_of(cycles[0][1]), index_of(cycles[0][2]), normal);
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
TriangleSoup nef_soup(const Nef& nef) {
  TriangleSoup soup;
  for (auto f = nef.halffacets_begin(); f != nef.halffacets_end(); ++f)
    if (f->incident_volume()->mark() && !f->twin()->incident_volume()->mark())
      soup.add_halffacet(f);
  return soup;
}

void write_off(const std::string& path, const std::vector<core::Vec3>& vertices,
               const std::vector<std::array<std::size_t, 3>>& triangles) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw std::runtime_error(path + ": cannot write the exported mesh");
    out << "OFF\n" << vertices.size() << " " << triangles.size() << " 0\n";
    out << std::setprecision(17);
    for (const auto& v : vertices) out << v.x() << " " << v.y() << " " << v.z() << "\n";
    for (const auto& t : triangles) out << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
    if (!out) throw std::runtime_error(path + ": cannot write the exported mesh");
  }
  std::filesystem::rename(tmp, path);
}

/// Squared distance lower bound between two boxes.
double bbox_sq_distance(const CGAL::Bbox_3& a, const CGAL::Bbox_3& b) {
  double sum = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double gap = std::max({0.0, a.min(i) - b.max(i), b.min(i) - a.max(i)});
    sum += gap * gap;
  }
  return sum * (1.0 - 1e-9);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// The model of one state.

struct ExactModel::Impl {
  struct Component {
    Nef::Volume_const_handle volume;
    std::vector<Point> points;
    std::vector<std::array<std::size_t, 3>> triangles;  // outward
    FT volume_exact = 0;
    FT z_min = 0, z_max = 0;
    bool kept = true;
  };
  Nef nef;  ///< regularised model before the filter
  std::vector<Component> components;
  bool any_removed = false;
  FT kept_volume = 0;

  const Component* component_of(Nef::Volume_const_handle v) const {
    for (const auto& c : components)
      if (c.volume == v) return &c;
    return nullptr;
  }
  bool kept_volume_handle(Nef::Volume_const_handle v) const {
    const Component* c = component_of(v);
    return c != nullptr && c->kept;
  }
  bool contains(const Point& p) const {
    const auto o = nef.locate(p);
    Nef::Volume_const_handle vol;
    if (CGAL::assign(vol, o)) return vol->mark() && kept_volume_handle(vol);
    Nef::Halffacet_const_handle f;
    Nef::Halfedge_const_handle e;
    Nef::Vertex_const_handle v;
    bool marked = false;
    if (CGAL::assign(f, o)) {
      if (!f->mark()) return false;
      return kept_volume_handle(f->incident_volume()) ||
             kept_volume_handle(f->twin()->incident_volume());
    }
    if (CGAL::assign(e, o)) marked = e->mark();
    if (CGAL::assign(v, o)) marked = v->mark();
    if (!marked) return false;
    if (!any_removed) return true;
    // A boundary edge or vertex: in the kept model iff it lies on a kept component's boundary.
    for (const auto& c : components) {
      if (!c.kept) continue;
      for (const auto& t : c.triangles)
        if (CGAL::do_intersect(Triangle(c.points[t[0]], c.points[t[1]], c.points[t[2]]), p))
          return true;
    }
    return false;
  }
};

ExactModel::ExactModel() : impl_(std::make_shared<Impl>()) {}
ExactModel::ExactModel(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
bool ExactModel::contains(const core::Vec3& p) const { return impl_->contains(to_point(p)); }
bool ExactModel::empty() const {
  return std::none_of(impl_->components.begin(), impl_->components.end(),
                      [](const Impl::Component& c) { return c.kept; });
}
double ExactModel::volume() const { return CGAL::to_double(impl_->kept_volume); }
int ExactModel::components() const {
  return int(std::count_if(impl_->components.begin(), impl_->components.end(),
                           [](const Impl::Component& c) { return c.kept; }));
}
std::vector<ExactComponent> ExactModel::component_info() const {
  std::vector<ExactComponent> out;
  for (const auto& c : impl_->components)
    out.push_back({CGAL::to_double(c.volume_exact), CGAL::to_double(c.z_min),
                   CGAL::to_double(c.z_max), c.kept});
  return out;
}
core::TriangleMesh ExactModel::boundary_mesh() const {
  core::TriangleMesh mesh;
  for (const auto& c : impl_->components) {
    if (!c.kept) continue;
    const int base = int(mesh.vertices.size());
    for (const auto& p : c.points) mesh.vertices.push_back(to_vec3(p));
    for (const auto& t : c.triangles)
      mesh.triangles.push_back({base + int(t[0]), base + int(t[1]), base + int(t[2])});
  }
  return mesh;
}

namespace {

/// Splits a regularised Nef model into components (its marked volumes: connected through
/// interiors), computes their exact volumes and z-extents and applies the filter (SPEC §4).
std::shared_ptr<ExactModel::Impl> cluster(Nef model, const core::Plausibility& filter) {
  auto impl = std::make_shared<ExactModel::Impl>();
  impl->nef = std::move(model);
  const Nef& nef = impl->nef;
  const FT min_volume(filter.min_volume), min_height(filter.min_height);
  // Regularised and simplified: no facet separates two marked volumes, so the marked volumes
  // are exactly the components connected through interiors.
  for (auto f = nef.halffacets_begin(); f != nef.halffacets_end(); ++f)
    CAMPLACE_ASSERT(!(f->incident_volume()->mark() && f->twin()->incident_volume()->mark()));
  // The boundary of a marked volume (outer and inner shells) is the set of halffacets incident
  // to it; one pass over the halffacets sorts them by volume.
  std::vector<TriangleSoup> soups;
  std::unordered_map<const void*, std::size_t> soup_of;
  auto vol = nef.volumes_begin();
  if (vol != nef.volumes_end()) ++vol;  // the unbounded outer volume
  for (; vol != nef.volumes_end(); ++vol) {
    if (!vol->mark()) continue;
    soup_of.emplace(&*vol, soups.size());
    soups.emplace_back();
    ExactModel::Impl::Component comp;
    comp.volume = vol;
    impl->components.push_back(std::move(comp));
  }
  for (auto f = nef.halffacets_begin(); f != nef.halffacets_end(); ++f) {
    const auto it = soup_of.find(&*f->incident_volume());
    if (it != soup_of.end()) soups[it->second].add_halffacet(f);
  }
  for (std::size_t k = 0; k < soups.size(); ++k) {
    ExactModel::Impl::Component& comp = impl->components[k];
    comp.points = std::move(soups[k].points);
    comp.triangles = std::move(soups[k].triangles);
    FT six_volume = 0;
    for (const auto& t : comp.triangles) {
      const Vector a = comp.points[t[0]] - CGAL::ORIGIN, b = comp.points[t[1]] - CGAL::ORIGIN,
                   c = comp.points[t[2]] - CGAL::ORIGIN;
      six_volume += CGAL::determinant(a, b, c);
    }
    // The triangles are outward (TriangleSoup), so six_volume > 0; kept as a safeguard.
    CAMPLACE_ASSERT(!CGAL::is_negative(six_volume));
    if (CGAL::is_negative(six_volume)) {
      six_volume = -six_volume;
      for (auto& t : comp.triangles) std::swap(t[1], t[2]);
    }
    comp.volume_exact = six_volume / 6;
    if (!comp.points.empty()) {
      comp.z_min = comp.z_max = comp.points.front().z();
      for (const auto& p : comp.points) {
        if (p.z() < comp.z_min) comp.z_min = p.z();
        if (p.z() > comp.z_max) comp.z_max = p.z();
      }
    }
    comp.kept = !(comp.volume_exact < min_volume) && !(comp.z_max - comp.z_min < min_height);
    if (comp.kept)
      impl->kept_volume += comp.volume_exact;
    else
      impl->any_removed = true;
  }
  return impl;
}

/// Exact squared distance between the union of closed solids `critical` and the kept model;
/// nullopt when the model is empty.
std::optional<FT> model_squared_distance(const ExactModel::Impl& model,
                                         const std::vector<const Solid*>& critical) {
  std::optional<FT> best;
  // Contact or overlap → 0 (SPEC §4: closed sets).
  for (const auto& comp : model.components) {
    if (!comp.kept) continue;
    std::vector<Triangle> tris;
    std::vector<CGAL::Bbox_3> boxes;
    CGAL::Bbox_3 comp_box;
    for (const auto& t : comp.triangles) {
      tris.emplace_back(comp.points[t[0]], comp.points[t[1]], comp.points[t[2]]);
      boxes.push_back(tris.back().bbox());
      comp_box += boxes.back();
    }
    for (const Solid* c : critical) {
      // a vertex of C inside the component, or a vertex of the component inside C
      for (const auto& p : c->points) {
        const auto o = model.nef.locate(p);
        Nef::Volume_const_handle vol;
        if (CGAL::assign(vol, o) && vol == comp.volume) return FT(0);
      }
      if (!comp.points.empty() && solid_contains(*c, comp.points.front())) return FT(0);
      // boundaries: exact triangle–triangle distances, branch and bound on box distances
      struct Pair {
        double lower;
        int i, j;
      };
      std::vector<Pair> pairs;
      for (int j = 0; j < int(c->triangles.size()); ++j) {
        const CGAL::Bbox_3 cb = c->triangle(j).bbox();
        for (int i = 0; i < int(tris.size()); ++i)
          pairs.push_back({bbox_sq_distance(boxes[i], cb), i, j});
      }
      std::sort(pairs.begin(), pairs.end(),
                [](const Pair& a, const Pair& b) { return a.lower < b.lower; });
      for (const auto& pr : pairs) {
        if (best && pr.lower > CGAL::to_interval(*best).second) break;
        const FT d = CGAL::squared_distance(tris[pr.i], c->triangle(pr.j));
        if (!best || d < *best) best = d;
        if (CGAL::is_zero(*best)) return best;
      }
    }
  }
  return best;
}

// ---------------------------------------------------------------------------------------------
// The pipeline with its caches (static shadows per camera, dynamic cones per camera and step).

class Pipeline {
 public:
  Pipeline(const core::Scene& scene, const core::CameraConfig& config)
      : scene_(scene) {
    if (int(config.size()) != scene.cameras.count && scene.cameras.count != 0)
      throw std::invalid_argument("exact evaluation: the configuration has " +
                                  std::to_string(config.size()) + " cameras, the scene " +
                                  std::to_string(scene.cameras.count));
    area_ = box_nef(scene.area);
    for (const auto& o : scene.static_obstacles) static_.emplace_back(o.mesh);
    for (const auto& step : scene.time_steps) {
      dynamic_.emplace_back();
      for (const auto& o : step.dynamic_obstacles) dynamic_.back().emplace_back(o.mesh);
      critical_.emplace_back();
      for (const auto& o : step.critical) critical_.back().emplace_back(o.mesh);
      targets_.emplace_back();
      for (const auto& ev : step.events) {
        targets_.back().emplace_back();
        for (const auto& o : ev.targets) targets_.back().back().emplace_back(o.mesh);
      }
    }
    for (const auto& setting : config) cameras_.push_back(make_camera(setting));
    step_free_.resize(cameras_.size());
    step_area_.resize(scene.time_steps.size());
  }

  /// The regularised model of a state before the filter.
  Nef model(const core::StateIndex& s) {
    const int h = s.time_step;
    std::vector<Nef> frees;
    for (std::size_t c = 0; c < cameras_.size(); ++c) frees.push_back(state_free(c, s));
    const Nef free_union = union_all(std::move(frees));
    Nef m = step_area(h);
    if (!free_union.is_empty()) m -= free_union;
    return m.regularization();
  }

  std::vector<const Solid*> critical(int h) const {
    std::vector<const Solid*> out;
    const auto& list = critical_[h].empty() ? dynamic_[h] : critical_[h];
    for (const auto& s : list) out.push_back(&s);
    return out;
  }

  /// FOV ∩ S of camera c (for export).
  const Nef& fov(std::size_t c) const { return cameras_[c].fov; }
  std::size_t camera_count() const { return cameras_.size(); }

 private:
  struct Camera {
    Point position;
    core::Vec3 position_d;
    double reach = 0.0;  ///< upper bound of the distance from the camera to any point of S
    Nef fov;             ///< pyramid ∩ S
    std::optional<Nef> static_free;
  };

  Camera make_camera(const core::CameraSetting& setting) const {
    Camera cam;
    cam.position = to_point(setting.position);
    cam.position_d = setting.position;
    for (int i = 0; i < 8; ++i) {
      const core::Vec3 corner((i & 1) ? scene_.area.max.x() : scene_.area.min.x(),
                              (i & 2) ? scene_.area.max.y() : scene_.area.min.y(),
                              (i & 4) ? scene_.area.max.z() : scene_.area.min.z());
      cam.reach = std::max(cam.reach, (corner - setting.position).norm());
    }
    cam.reach = cam.reach * 1.01 + 1e-6;
    // SPEC §1: the inscribed regular k-sided pyramid, the edges shared with core (and thus the
    // voxel pipeline), optionally cut by the far plane (p − c)·d ≤ range.
    const core::Fov fov(setting, core::FovShape::pyramid, scene_.cameras.half_angle,
                        scene_.cameras.sides, scene_.cameras.range);
    std::vector<Point> pts{cam.position};
    if (scene_.cameras.range) {
      const Vector d = to_vector(core::view_direction(setting));
      const FT range(*scene_.cameras.range);
      for (const auto& e : fov.pyramid_edges()) {
        const Vector ev = to_vector(e);
        pts.push_back(cam.position + ev * (range / (ev * d)));
      }
    } else {
      const FT t(std::exp2(std::ceil(std::log2(2.0 * cam.reach))));
      for (const auto& e : fov.pyramid_edges()) pts.push_back(cam.position + to_vector(e) * t);
    }
    cam.fov = hull_nef(pts) * area_;
    return cam;
  }

  /// A power of two T with c + T(x − c) outside S for every x at distance ≥ h from c.
  static FT scale_for(const Camera& cam, double h) {
    CAMPLACE_ASSERT(h > 0.0);
    h = std::max(h, 1e-200);  // never reached for a camera outside the solid
    return FT(std::exp2(std::ceil(std::log2(2.0 * cam.reach / h))));
  }

  static std::vector<int> front_faces(const Camera& cam, const Solid& solid) {
    std::vector<int> out;
    for (int i = 0; i < int(solid.planes.size()); ++i)
      if (solid.planes[i].oriented_side(cam.position) == CGAL::ON_POSITIVE_SIDE) out.push_back(i);
    return out;
  }

  static double plane_distance_lower(const Camera& cam, const Plane& plane) {
    return sqrt_lower(CGAL::squared_distance(cam.position, plane));
  }

  /// Lower bound of the distance from the camera to a convex solid it lies outside of.
  static double convex_distance_lower(const Camera& cam, const Solid& solid,
                                      const std::vector<int>& front) {
    double h = 0.0;
    for (int i : front) h = std::max(h, plane_distance_lower(cam, solid.planes[i]));
    return h;
  }

  static std::vector<Point> scaled(const Camera& cam, const std::vector<Point>& pts, const FT& t) {
    std::vector<Point> out;
    out.reserve(pts.size());
    for (const auto& p : pts) out.push_back(cam.position + (p - cam.position) * t);
    return out;
  }

  /// Points p whose segment [c, p] meets the solid, within S (c outside the solid).
  Nef shadow(const Camera& cam, const Solid& solid) const {
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
    for (int i : front) {
      const FT t = scale_for(cam, plane_distance_lower(cam, solid.planes[i]));
      const auto& tri = solid.triangles[i];
      std::vector<Point> face{solid.points[tri[0]], solid.points[tri[1]], solid.points[tri[2]]};
      auto pts = face;
      const auto far = scaled(cam, face, t);
      pts.insert(pts.end(), far.begin(), far.end());
      parts.push_back(hull_nef(pts));
    }
    return union_all(std::move(parts));
  }

  /// The silhouette cone of the visible part of an occupying solid: rays from c whose first
  /// hit among {solid} ∪ blockers is on the solid (c outside all of them).
  Nef occupied_cone(const Camera& cam, const Solid& solid,
                    const std::vector<const Solid*>& blockers) const {
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

  bool camera_inside(const Camera& cam, const std::deque<Solid>& solids) const {
    for (const auto& s : solids)
      if (CGAL::do_overlap(s.bbox, cam.position.bbox()) &&
          solid_contains(s, cam.position))
        return true;
    return false;
  }

  bool modelled() const { return scene_.dynamic_mode == core::DynamicMode::modelled; }

  /// FOV ∩ S minus the static shadows (cached per camera).
  const Nef& static_free(std::size_t c) {
    Camera& cam = cameras_[c];
    if (!cam.static_free) {
      if (camera_inside(cam, static_)) {
        cam.static_free.emplace();
      } else {
        std::vector<Nef> parts;
        for (const auto& s : static_) parts.push_back(shadow(cam, s));
        const Nef shadows = union_all(std::move(parts));
        Nef f = cam.fov;
        if (!shadows.is_empty() && !f.is_empty()) f -= shadows;
        cam.static_free.emplace(std::move(f));
      }
    }
    return *cam.static_free;
  }

  /// static_free minus the dynamic obstacles' cones (masked) or shadows (modelled), per step.
  const Nef& step_free(std::size_t c, int h) {
    auto& slot = step_free_[c];
    if (slot.size() < scene_.time_steps.size()) slot.resize(scene_.time_steps.size());
    if (!slot[h]) {
      const Camera& cam = cameras_[c];
      Nef f = static_free(c);
      if (!f.is_empty() && camera_inside(cam, dynamic_[h])) f = Nef();
      if (!f.is_empty()) {
        std::vector<const Solid*> blockers;
        for (const auto& s : static_) blockers.push_back(&s);
        std::vector<Nef> parts;
        for (const auto& d : dynamic_[h])
          parts.push_back(modelled() ? shadow(cam, d) : occupied_cone(cam, d, blockers));
        const Nef removed = union_all(std::move(parts));
        if (!removed.is_empty()) f -= removed;
      }
      slot[h] = std::move(f);
    }
    return *slot[h];
  }

  /// Free_c of SPEC §3 for one state.
  Nef state_free(std::size_t c, const core::StateIndex& s) {
    const Camera& cam = cameras_[c];
    Nef f = step_free(c, s.time_step);
    const auto& targets = targets_[s.time_step][s.event];
    if (f.is_empty()) return f;
    if (camera_inside(cam, targets)) return Nef();
    std::vector<const Solid*> blockers;
    for (const auto& st : static_) blockers.push_back(&st);
    if (modelled())
      for (const auto& d : dynamic_[s.time_step]) blockers.push_back(&d);
    std::vector<Nef> parts;
    for (const auto& t : targets) parts.push_back(occupied_cone(cam, t, blockers));
    const Nef removed = union_all(std::move(parts));
    if (!removed.is_empty()) f -= removed;
    return f;
  }

  /// S minus the obstacles of step h.
  const Nef& step_area(int h) {
    if (!step_area_[h]) {
      Nef a = area_;
      std::vector<Nef> parts;
      for (const auto& s : static_) parts.push_back(s.as_nef());
      for (const auto& d : dynamic_[h]) parts.push_back(d.as_nef());
      const Nef obstacles = union_all(std::move(parts));
      if (!obstacles.is_empty()) a -= obstacles;
      step_area_[h] = std::move(a);
    }
    return *step_area_[h];
  }

  const core::Scene& scene_;
  Nef area_;
  std::deque<Solid> static_;
  std::deque<std::deque<Solid>> dynamic_, critical_;
  std::deque<std::deque<std::deque<Solid>>> targets_;
  std::vector<Camera> cameras_;
  std::vector<std::vector<std::optional<Nef>>> step_free_;
  std::vector<std::optional<Nef>> step_area_;
};

FT diagonal_squared(const core::Box3& box) {
  const Vector d = to_point(box.max) - to_point(box.min);
  return d.squared_length();
}

void export_soup(const std::string& path, const std::vector<Point>& points,
                 const std::vector<std::array<std::size_t, 3>>& triangles) {
  std::vector<core::Vec3> v;
  v.reserve(points.size());
  for (const auto& p : points) v.push_back(to_vec3(p));
  write_off(path, v, triangles);
}

}  // namespace

ExactEvaluation evaluate_exact(const core::Scene& scene, const core::CameraConfig& config,
                               const ExactOptions& options) {
  const auto t_total = Clock::now();
  ExactEvaluation result;
  Pipeline pipeline(scene, config);
  if (!options.export_dir.empty()) {
    std::filesystem::create_directories(options.export_dir);
    for (std::size_t c = 0; c < pipeline.camera_count(); ++c) {
      const TriangleSoup soup = nef_soup(pipeline.fov(c));
      std::vector<std::array<std::size_t, 3>> tris;
      for (const auto& t : soup.triangles) tris.push_back({t[0], t[1], t[2]});
      export_soup(options.export_dir + "/camera-" + std::to_string(c) + "-pyramid.off",
                  soup.points, tris);
    }
  }
  std::vector<core::ErrTerm> terms;
  for (const auto& s : core::states(scene)) {
    auto t0 = Clock::now();
    Nef m = pipeline.model(s);
    result.timing.model_ms += ms_since(t0);

    t0 = Clock::now();
    auto model = cluster(std::move(m), scene.plausibility);
    result.timing.clustering_ms += ms_since(t0);

    t0 = Clock::now();
    ExactStateResult r;
    r.time_step = s.time_step;
    r.event = s.event;
    r.weight = scene.time_steps[s.time_step].events[s.event].weight;
    const auto d_true = core::true_squared_distance(scene, s);
    r.d_true = std::sqrt(d_true.value);
    r.d_true_sq_exact = d_true.fraction;
    const auto d_model = model_squared_distance(*model, pipeline.critical(s.time_step));
    const FT d_model_sq = d_model ? *d_model : diagonal_squared(scene.area);
    r.d_model = std::sqrt(CGAL::to_double(d_model_sq));
    r.d_model_sq_exact = fraction_string(d_model_sq);
    result.timing.distance_ms += ms_since(t0);

    r.model_volume = CGAL::to_double(model->kept_volume);
    for (const auto& c : model->components) (c.kept ? r.components : r.components_removed)++;
    if (!options.export_dir.empty()) {
      std::vector<Point> pts;
      std::vector<std::array<std::size_t, 3>> tris;
      for (const auto& c : model->components) {
        if (!c.kept) continue;
        const std::size_t base = pts.size();
        pts.insert(pts.end(), c.points.begin(), c.points.end());
        for (const auto& t : c.triangles) tris.push_back({base + t[0], base + t[1], base + t[2]});
      }
      export_soup(options.export_dir + "/state-h" + std::to_string(s.time_step) + "-e" +
                      std::to_string(s.event) + "-model.off",
                  pts, tris);
    }
    terms.push_back({r.weight, r.d_true, r.d_model});
    result.states.push_back(std::move(r));
    if (options.keep_models) result.models.emplace_back(std::move(model));
  }
  result.err = core::error_functional(terms);
  result.timing.total_ms = ms_since(t_total);
  return result;
}

ExactModel build_exact_model(const core::Scene& scene, const core::CameraConfig& config,
                             const core::StateIndex& state) {
  Pipeline pipeline(scene, config);
  return ExactModel(cluster(pipeline.model(state), scene.plausibility));
}

}  // namespace camplace::exact
