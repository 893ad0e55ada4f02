#pragma once
// Mesh reading (CGAL IO for OFF/OBJ/STL/PLY, assimp for COLLADA/glTF/GLB/3MF) and validity
// checks (CGAL Polygon Mesh Processing). Private to core.
#include <optional>
#include <string>

#include "camplace/core/geometry.hpp"

namespace camplace::core {
class JsonNode;
}  // namespace camplace::core

namespace camplace::core::detail {

/// How to turn a mesh file's coordinates into camplace's (metres, z up): scale first, then
/// rotate to z up; the object's own transform comes after both.
struct MeshFileOptions {
  /// Metres per file unit ("units": m 1, cm 0.01, mm 0.001, in 0.0254).
  double unit_scale = 1.0;
  /// Which way is up in the file: `file` the format's own convention (glTF y up, COLLADA its
  /// `<up_axis>`, everything else z up), `z` as written, `y` y up (rotated +90° about x).
  enum class UpAxis { file, z, y } up = UpAxis::file;
};

/// Reads "units" and "up_axis" of an object when present (fails naming the key for an unknown
/// value, or when the object has no "file").
MeshFileOptions parse_mesh_file_options(const JsonNode& object);

/// Reads a mesh file (format by extension: .off .obj .stl .ply with CGAL IO, .dae .gltf .glb
/// .3mf with assimp) into one triangle mesh in metres and z up (every part of the file's scene
/// graph, node transforms applied; polygons fanned). Throws InputError(scene_file, entry,
/// reason).
TriangleMesh read_mesh_file(const std::string& path, const std::string& scene_file,
                            const std::string& entry, const MeshFileOptions& options = {});

/// Why `mesh` is not a valid solid, and whether a repair (wrap or hull) could make it one.
struct MeshDefect {
  std::string reason;       ///< e.g. "mesh intersects itself"
  bool repairable = false;  ///< false for non-finite coordinates, bad indices, no triangles
};

/// As validate_and_orient, but returns the defect instead of throwing; orients `mesh` outward
/// (and drops unused vertices) when it is valid.
std::optional<MeshDefect> check_and_orient(TriangleMesh& mesh);

/// The text appended to a repairable defect's error: which "repair" would accept the mesh.
std::string repair_hint(const MeshDefect& defect);

/// Checks that the mesh is a closed, consistently oriented, non-self-intersecting,
/// non-degenerate triangle mesh; orients it outward. Throws InputError naming file and entry
/// (a repairable defect's reason ends with repair_hint).
void validate_and_orient(TriangleMesh& mesh, const std::string& file, const std::string& entry);

/// True when the closed solids bounded by a and b share a point (surfaces meet, or one
/// contains the other).
bool solids_intersect(const TriangleMesh& a, const TriangleMesh& b);

}  // namespace camplace::core::detail
