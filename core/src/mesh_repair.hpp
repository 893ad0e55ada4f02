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
/// d / kDefaultRelativeAlpha, offset = alpha / kDefaultAlphaPerOffset (CGAL's examples use
/// alpha = d/20, offset = d/600).
constexpr double kDefaultRelativeAlpha = 50.0;
constexpr double kDefaultAlphaPerOffset = 30.0;
/// Smallest alpha accepted, d / kMaxRelativeAlpha: the wrap's work and size grow as (d/alpha)²,
/// so a tiny alpha is refused before any work.
constexpr double kMaxRelativeAlpha = 500.0;
/// Smallest offset accepted, d / kMaxRelativeOffset.
constexpr double kMaxRelativeOffset = 1e5;
/// Largest "max_triangles" accepted.
constexpr int kMaxRepairTriangles = 1'000'000;

/// What the "repair" key asks for.
struct RepairOptions {
  enum class Method { none, wrap, hull } method = Method::none;
  double offset = 0.0;        ///< wrap: offset (m); 0 = the default alpha / 30
  double alpha = 0.0;         ///< wrap: alpha (m); 0 = the default (bounding-box diagonal / 50)
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
/// 2-manifold, free of self-intersections, containing the input at a distance of at most
/// about `offset`. alpha and offset in metres, > 0. Not validated (finish_mesh does that).
TriangleMesh alpha_wrap(const TriangleMesh& mesh, double alpha, double offset);

/// The convex hull of the vertices of `mesh` (CGAL::convex_hull_3), outward; std::nullopt when
/// they are coplanar.
std::optional<TriangleMesh> convex_hull(const TriangleMesh& mesh);

}  // namespace camplace::core::detail
