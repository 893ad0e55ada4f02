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
/// (outward; m, world frame): the `model.sides`-sided pyramid when model.fov is pyramid
/// (SPEC §1), the frustum over the image rectangle (turned by the camera's roll) when it is a
/// frustum, for a cone the inscribed kConeDrawSides-sided pyramid; cut at the model's near and
/// far planes when set. Empty when the FOV misses the box.
core::TriangleMesh fov_mesh(const core::CameraSetting& camera, const core::CameraModel& model,
                            const core::Box3& area);

}  // namespace camplace::view
