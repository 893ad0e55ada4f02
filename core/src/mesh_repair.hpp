#pragma once
// Repair of meshes that fail the checks: an enclosing alpha wrap or the convex hull
// (docs/scene-format.md#repair). Private to core.
#include <optional>
#include <string>

#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::core {
class JsonNode;
}  // namespace camplace::core

namespace camplace::core::detail {

/// alpha and offset defaults, relative to the diagonal d of the mesh's bounding box: alpha =
/// d / kDefaultRelativeAlpha, offset = alpha / kDefaultAlphaPerOffset, as CGAL's examples (d/20,
/// d/600): coarse but cheap (two overlapping unit boxes wrap into ~1,600 triangles; d/50 gives
/// ~8,200, which the exact pipeline's Nef polyhedra would pay for at every use).
constexpr double kDefaultRelativeAlpha = 20.0;
constexpr double kDefaultAlphaPerOffset = 30.0;
/// Smallest alpha accepted, d / kMaxRelativeAlpha, and smallest offset, alpha /
/// kMaxAlphaPerOffset: the wrap's work and size grow as (d/alpha)² and with alpha/offset, so
/// tiny values are refused before any work (two overlapping unit boxes at alpha = d/100, offset
/// = alpha/100: ~44,000 triangles, ~3 s; at d/200 and d/100,000 it was ~270,000 and ~15 s). The
/// wrap also stops once it has more vertices than max_triangles (finish_mesh).
constexpr double kMaxRelativeAlpha = 100.0;
constexpr double kMaxAlphaPerOffset = 100.0;
/// Largest "max_triangles" accepted.
constexpr int kMaxRepairTriangles = 1'000'000;

/// What the "repair" key asks for.
struct RepairOptions {
  enum class Method { none, wrap, hull } method = Method::none;
  double offset = 0.0;        ///< wrap: offset (m); 0 = the default alpha / 30
  double alpha = 0.0;         ///< wrap: alpha (m); 0 = the default (bounding-box diagonal / 20)
  int max_triangles = 20000;  ///< the repaired mesh may have at most this many triangles
  bool always = false;        ///< repair even a mesh that passes the checks
};

/// Parses the value of a "repair" key: "none", "wrap", "hull" or {"method", "offset_m",
/// "alpha_m", "max_triangles", "always"}. Fails naming the entry for any other value.
RepairOptions parse_repair(const JsonNode& node);

/// Validates and orients `mesh`; when it fails (or always) and `repair` asks for one, repairs,
/// validates the result and returns the record (role left empty, for the caller to fill).
/// Throws InputError(file, entry, ...) as validate_and_orient (plus the hint) or when the
/// repair fails / exceeds its budget.
std::optional<MeshRepair> finish_mesh(TriangleMesh& mesh, const RepairOptions& repair,
                                      const std::string& file, const std::string& entry,
                                      const std::string& object_name);

/// The enclosing alpha wrap of the triangles of `mesh` (CGAL::alpha_wrap_3): closed,
/// 2-manifold, free of self-intersections, containing the input at a distance of about
/// `offset`. alpha and offset in metres, > 0. std::nullopt once the wrap inserts more than
/// `max_steiner_points` points (its vertices are among them). Not validated (finish_mesh does).
std::optional<TriangleMesh> alpha_wrap(const TriangleMesh& mesh, double alpha, double offset,
                                       std::size_t max_steiner_points);

/// The convex hull of the vertices of `mesh` (CGAL::convex_hull_3), outward; std::nullopt when
/// they are coplanar.
std::optional<TriangleMesh> convex_hull(const TriangleMesh& mesh);

}  // namespace camplace::core::detail
