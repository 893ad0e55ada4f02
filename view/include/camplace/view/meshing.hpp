#pragma once
/// Meshes the viewer draws: the voxel model's outer boundary and each camera's FOV clipped to S.
#include <cstdint>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/voxel/grid.hpp"

namespace camplace::view {

/// The boundary of a voxel model: every face between a model voxel and a voxel outside the model
/// (or S's boundary), coplanar adjacent faces merged greedily into rectangles, two triangles
/// each, outward (normals point out of the model). `model`: one byte per voxel of `grid` in its
/// index order, 1 = in M. m, world frame; empty for an empty model. A closed surface (with
/// T-junctions where rectangles meet), so signed_volume() is the model's volume.
core::TriangleMesh voxel_boundary_mesh(const voxel::Grid& grid,
                                       const std::vector<std::uint8_t>& model);

/// Sides of the pyramid drawn for a cone FOV (inscribed, as SPEC §1 inscribes the k-sided one).
constexpr int kConeDrawSides = 64;

/// The camera's FOV intersected with the closed box `area`, as a closed convex triangle mesh
/// (outward; m, world frame): the inscribed `spec.sides`-sided pyramid when spec.fov is pyramid
/// (SPEC §1), for a cone the inscribed kConeDrawSides-sided one; cut at spec.range when set.
/// Empty when the FOV misses the box.
core::TriangleMesh fov_mesh(const core::CameraSetting& camera, const core::CameraSpec& spec,
                            const core::Box3& area);

}  // namespace camplace::view
