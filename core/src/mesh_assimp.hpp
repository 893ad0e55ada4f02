#pragma once
// Mesh files read with assimp (COLLADA, glTF, GLB, 3MF). Private to core.
#include <cstdint>
#include <string>

#include "camplace/core/geometry.hpp"

namespace camplace::core::detail {

/// Largest mesh file handed to assimp (bytes): assimp reads a whole file into memory and
/// cannot be given a time limit, so size is the one bound on its work that can be set.
constexpr std::uintmax_t kMaxAssimpFileBytes = 256u << 20;
/// Largest number of vertices (and of triangles) accepted from one file, node instances
/// counted: beyond it the mesh checks and the models would exhaust memory anyway.
constexpr std::size_t kMaxAssimpElements = 5'000'000;

/// Reads every triangle of the file's scene graph with its node transforms applied into one
/// mesh, vertices with equal coordinates merged (so a part split by material or by normals
/// is closed again); points and lines are skipped. Coordinates as assimp gives them: COLLADA in
/// metres (its <unit> applied) and turned y up (its <up_axis> applied, unless
/// `ignore_collada_up`), other formats as written. Throws InputError(scene_file, entry,
/// "mesh file PATH cannot be read: " + assimp's reason) for corrupt, empty or oversized files.
TriangleMesh read_assimp_mesh_file(const std::string& path, const std::string& scene_file,
                                   const std::string& entry, bool ignore_collada_up);

}  // namespace camplace::core::detail
