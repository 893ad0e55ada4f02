#pragma once
// Mesh reading (CGAL IO) and validity checks (CGAL Polygon Mesh Processing). Private to core.
#include <string>

#include "camplace/core/geometry.hpp"

namespace camplace::core::detail {

/// Reads an OFF/OBJ/STL/PLY file (by extension) into a triangle mesh (polygons fanned).
/// Throws InputError(file_for_errors, entry, reason).
TriangleMesh read_mesh_file(const std::string& path, const std::string& scene_file,
                            const std::string& entry);

/// Checks that the mesh is a closed, consistently oriented, non-self-intersecting,
/// non-degenerate triangle mesh; orients it outward. Throws InputError naming file and entry.
void validate_and_orient(TriangleMesh& mesh, const std::string& file, const std::string& entry);

/// True when the closed solids bounded by a and b share a point (surfaces meet, or one
/// contains the other).
bool solids_intersect(const TriangleMesh& a, const TriangleMesh& b);

}  // namespace camplace::core::detail
