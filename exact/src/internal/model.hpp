#pragma once
// The model of one state after the Nef booleans: its components (connected through interiors),
// their exact volumes and z-extents, the plausibility filter (SPEC §4), and the exact distance
// from the critical objects to the kept model. Private to exact_pipeline.cpp.
#include <CGAL/Modifier_base.h>
#include <CGAL/squared_distance_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "camplace/core/error.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/exact/evaluator.hpp"
#include "internal/kernel.hpp"
#include "internal/near_pairs.hpp"
#include "internal/solids.hpp"
#include "internal/soup.hpp"

namespace camplace::exact {

/// The model of one state: the regularised Nef polyhedron before the filter and its components
/// (SPEC §4), each with its exact boundary, volume and z-extent.
struct ExactModel::Impl {
  using Nef = internal::Nef;
  using Point = internal::Point;
  using FT = internal::FT;
  using Triangle = internal::Triangle;

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

}  // namespace camplace::exact

namespace camplace::exact::internal {

/// Squared distance lower bound between two boxes.
inline double bbox_sq_distance(const CGAL::Bbox_3& a, const CGAL::Bbox_3& b) {
  double sum = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double gap = std::max({0.0, a.min(i) - b.max(i), b.min(i) - a.max(i)});
    sum += gap * gap;
  }
  return sum * (1.0 - 1e-9);
}

/// Unmarks the marked volumes of a regularised Nef polyhedron that the plausibility filter
/// certainly removes, judged by an upper bound of their volume and z-extent (the box of their
/// boundary vertices' coordinate intervals). Volume marks and the marks of the sfaces in them
/// (the volumes as the vertices' local views see them) change together, so the structure stays
/// valid for further booleans.
class UnmarkImplausible : public CGAL::Modifier_base<Nef::SNC_structure> {
 public:
  explicit UnmarkImplausible(const core::Plausibility& filter) : filter_(filter) {}
  int unmarked() const { return unmarked_; }

  void operator()(Nef::SNC_structure& snc) override {
    struct Extent {
      std::array<double, 3> lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    };
    std::unordered_map<const void*, Extent> extents;
    for (auto f = snc.halffacets_begin(); f != snc.halffacets_end(); ++f) {
      if (!f->incident_volume()->mark()) continue;
      Extent& e = extents[&*f->incident_volume()];
      for (auto cycle = f->facet_cycles_begin(); cycle != f->facet_cycles_end(); ++cycle) {
        if (!cycle.is_shalfedge()) continue;
        Nef::SNC_structure::SHalfedge_around_facet_circulator h(cycle), end(h);
        CGAL_For_all(h, end) {
          const Point& p = h->source()->source()->point();
          const std::array<std::pair<double, double>, 3> bounds{
              CGAL::to_interval(p.x()), CGAL::to_interval(p.y()), CGAL::to_interval(p.z())};
          for (int k = 0; k < 3; ++k) {
            e.lo[k] = std::min(e.lo[k], bounds[k].first);
            e.hi[k] = std::max(e.hi[k], bounds[k].second);
          }
        }
      }
    }
    for (auto v = snc.volumes_begin(); v != snc.volumes_end(); ++v) {
      const auto it = extents.find(&*v);
      if (it == extents.end()) continue;
      // Upper bounds: the rounding of these few double operations is far below the slack.
      constexpr double slack = 1.0 + 1e-9;
      const Extent& e = it->second;
      const double height = (e.hi[2] - e.lo[2]) * slack;
      const double box_volume = (e.hi[0] - e.lo[0]) * (e.hi[1] - e.lo[1]) * height * slack;
      if (filter_.keeps(box_volume, height)) continue;
      v->mark() = false;
      ++unmarked_;
    }
    if (unmarked_ == 0) return;
    for (auto sf = snc.sfaces_begin(); sf != snc.sfaces_end(); ++sf)
      if (sf->mark() && !sf->volume()->mark()) sf->mark() = false;
  }

 private:
  core::Plausibility filter_;
  int unmarked_ = 0;
};

/// Removes from a model under construction the pieces that the plausibility filter certainly
/// removes from the final model, and returns their number; `m` comes back regularised.
///
/// Sound because later booleans only subtract: each component of the final model lies in one
/// piece (component through interiors) of `m`, with no more volume and no more z-extent, and the
/// filter removes a component below either threshold (SPEC §4). So every final component inside
/// a discarded piece would be removed too, and the kept model, its volume and d(C, M) are the
/// same. Each discarded piece counts as one removed component, whatever later cameras would have
/// split it into.
inline int discard_implausible(Nef& m, const core::Plausibility& filter) {
  m = m.regularization();
  UnmarkImplausible unmark(filter);
  m.delegate(unmark, /*compute_external=*/false, /*do_simplify=*/false);
  if (unmark.unmarked() == 0) return 0;
  m = m.regularization();
  return unmark.unmarked();
}

/// Splits a regularised Nef model into components (its marked volumes: connected through
/// interiors), computes their exact volumes and z-extents and applies the filter (SPEC §4).
inline std::shared_ptr<ExactModel::Impl> cluster(Nef model, const core::Plausibility& filter) {
  auto impl = std::make_shared<ExactModel::Impl>();
  impl->nef = std::move(model);
  const Nef& nef = impl->nef;
  // Regularised and simplified: no facet separates two marked volumes, so the marked volumes
  // are exactly the components connected through interiors.
  for (auto f = nef.halffacets_begin(); f != nef.halffacets_end(); ++f)
    CAMPLACE_ASSERT(!(f->incident_volume()->mark() && f->twin()->incident_volume()->mark()));
  // The boundary of a marked volume (outer and inner shells) is the set of halffacets incident
  // to it; one pass over the halffacets sorts them by volume.
  std::vector<TriangleSoup> soups;
  std::unordered_map<const void*, std::size_t> soup_of;
  // The unbounded outer volume is unmarked (M ⊂ S is bounded); it is not always the first one.
  for (auto vol = nef.volumes_begin(); vol != nef.volumes_end(); ++vol) {
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
    const FT height = comp.z_max - comp.z_min;
    comp.kept = filter.keeps(comp.volume_exact, height);
    if (comp.kept)
      impl->kept_volume += comp.volume_exact;
    else
      impl->any_removed = true;
  }
  return impl;
}

/// True when the kept component `comp` of `model` touches or overlaps the union of the closed
/// solids `critical` (then d(C, M) = 0, SPEC §4): a vertex of a critical solid inside the
/// component, or a vertex of the component inside a critical solid.
inline bool touches_critical(const ExactModel::Impl& model, const ExactModel::Impl::Component& comp,
                             const std::vector<const Solid*>& critical) {
  for (const Solid* c : critical) {
    for (const auto& p : c->points) {
      const auto o = model.nef.locate(p);
      Nef::Volume_const_handle vol;
      if (CGAL::assign(vol, o) && vol == comp.volume) return true;
    }
    if (!comp.points.empty() && solid_contains(*c, comp.points.front())) return true;
  }
  return false;
}

/// Exact squared distance between the union of closed solids `critical` and the kept model;
/// nullopt when the model is empty. The reference (ExactOptions::filtered_distances off):
/// branch and bound on box distances alone, so that every pair whose boxes are nearer than the
/// best exact distance so far gets an exact distance.
inline std::optional<FT> model_squared_distance_by_boxes(
    const ExactModel::Impl& model, const std::vector<const Solid*>& critical) {
  std::optional<FT> best;
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
    if (touches_critical(model, comp, critical)) return FT(0);
    for (const Solid* c : critical) {
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

/// The triangle with double vertices for exact points: each coordinate's interval, its lower
/// end as the double and its width as the error; `box` receives the intervals' box.
inline ApproxTriangle approx_triangle(const Point& a, const Point& b, const Point& c,
                                      CGAL::Bbox_3& box) {
  ApproxTriangle t;
  const Point* pts[3] = {&a, &b, &c};
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (int k = 0; k < 3; ++k) {
    const std::pair<double, double> iv[3] = {CGAL::to_interval(pts[k]->x()),
                                             CGAL::to_interval(pts[k]->y()),
                                             CGAL::to_interval(pts[k]->z())};
    for (int i = 0; i < 3; ++i) {
      t.v[k][i] = iv[i].first;
      t.error = std::max(t.error, iv[i].second - iv[i].first);
      lo[i] = std::min(lo[i], iv[i].first);
      hi[i] = std::max(hi[i], iv[i].second);
    }
  }
  box = CGAL::Bbox_3(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  return t;
}

/// model_squared_distance_by_boxes with a floating-point filter, the same exact value: every
/// pair of a model triangle and a critical triangle whose boxes are near enough gets double
/// bounds (pair_bounds: an approximate distance and a certified lower bound); exact distances
/// are computed only for the pairs whose certified lower bound does not exceed the smallest
/// approximate distance (with a slack), nearest first, until the lower bounds exceed the best
/// exact distance. If the best exact distance came out above the slack threshold (never seen:
/// the double bounds are off by far less than the slack), the reference decides.
inline std::optional<FT> model_squared_distance(const ExactModel::Impl& model,
                                                const std::vector<const Solid*>& critical) {
  struct Approx {
    ApproxTriangle t;
    CGAL::Bbox_3 box;
    Triangle exact;
  };
  std::vector<Approx> tris;
  for (const auto& comp : model.components) {
    if (!comp.kept) continue;
    if (touches_critical(model, comp, critical)) return FT(0);
    for (const auto& t : comp.triangles) {
      Approx a;
      a.exact = Triangle(comp.points[t[0]], comp.points[t[1]], comp.points[t[2]]);
      a.t = approx_triangle(comp.points[t[0]], comp.points[t[1]], comp.points[t[2]], a.box);
      tris.push_back(std::move(a));
    }
  }
  // No kept component (or none with a boundary, which a kept component always has).
  if (tris.empty()) return model_squared_distance_by_boxes(model, critical);
  std::vector<Approx> crit;
  for (const Solid* c : critical)
    for (const auto& t : c->triangles) {
      Approx a;
      a.exact = Triangle(c->points[t[0]], c->points[t[1]], c->points[t[2]]);
      a.t = approx_triangle(c->points[t[0]], c->points[t[1]], c->points[t[2]], a.box);
      crit.push_back(std::move(a));
    }
  if (crit.empty()) return model_squared_distance_by_boxes(model, critical);
  // The threshold: the smallest approximate squared distance so far, widened by a nanometre and
  // a relative 1e-9. Seeded with the nearest pair of vertices.
  auto widened = [](double sq) {
    const double d = std::sqrt(sq) * (1.0 + 1e-9) + 1e-9;
    return d * d;
  };
  double threshold = HUGE_VAL;
  for (const auto& a : tris)
    for (const auto& b : crit) {
      if (bbox_sq_distance(a.box, b.box) > threshold) continue;
      for (const auto& p : a.t.v)
        for (const auto& q : b.t.v) threshold = std::min(threshold, widened((p - q).squaredNorm()));
    }
  struct Candidate {
    double lower;
    int i, j;
  };
  std::vector<Candidate> candidates;
  for (int i = 0; i < int(tris.size()); ++i)
    for (int j = 0; j < int(crit.size()); ++j) {
      const double box_lower = bbox_sq_distance(tris[i].box, crit[j].box);
      if (box_lower > threshold) continue;
      const PairBounds b = pair_bounds(tris[i].t, crit[j].t);
      threshold = std::min(threshold, widened(b.upper));
      const double lower = std::max(box_lower, b.lower);
      if (lower <= threshold) candidates.push_back({lower, i, j});
    }
  // Every pair left out has a certified lower bound above the threshold at its time, hence above
  // the final threshold.
  candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                  [&](const Candidate& c) { return c.lower > threshold; }),
                   candidates.end());
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return a.lower < b.lower || (a.lower == b.lower && (a.i < b.i || (a.i == b.i && a.j < b.j)));
  });
  std::optional<FT> best;
  for (const auto& c : candidates) {
    if (best && c.lower > CGAL::to_interval(*best).second) break;
    const FT d = CGAL::squared_distance(tris[c.i].exact, crit[c.j].exact);
    if (!best || d < *best) best = d;
    if (CGAL::is_zero(*best)) return best;
  }
  if (best && CGAL::to_interval(*best).second <= threshold) return best;
  return model_squared_distance_by_boxes(model, critical);
}

}  // namespace camplace::exact::internal
