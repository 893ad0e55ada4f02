#pragma once
// The same closed solid cut into other triangles: every triangle of a mesh split into many
// coplanar ones, keeping the mesh closed and conforming (a new vertex on an edge is shared by
// both triangles of that edge, with the same coordinates), and its orientation.
#include <array>
#include <functional>
#include <random>

#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::testing {

/// Each triangle cut into k² by the lines parallel to its edges at 1/k steps (regular
/// subdivision). A point is computed from the corners' ids in ascending order, so the points
/// of a shared edge are equal on both of its triangles.
core::TriangleMesh subdivide(const core::TriangleMesh& mesh, int k);

/// Triangle t split at the point of weights `w` on its corners (summing to 1, all > 0) into a
/// fan of 3 (the first replaces t, the others are appended).
void split_inside(core::TriangleMesh& mesh, int t, const std::array<double, 3>& w);
/// The edge from corner e to corner e + 1 of triangle t split at the fraction `at` from corner
/// e, with the triangle across that edge: both become 2. False (and no change) when no
/// triangle lies across the edge.
bool split_edge(core::TriangleMesh& mesh, int t, int e, double at);

/// `splits` random splits, each of a random triangle: either an inner point (the triangle
/// becomes a fan of 3) or a point on one of its edges (both triangles of that edge become 2).
/// With `slivers`, the points lie within ~1e-7 to 1e-3 of the triangle's size from an edge or
/// a corner, which makes thin, nearly degenerate triangles.
core::TriangleMesh random_splits(const core::TriangleMesh& mesh, std::mt19937& rng, int splits,
                                 bool slivers);

/// The object with its mesh replaced by `mesh` (and its bounds recomputed).
core::SceneObject with_mesh(const core::SceneObject& object, core::TriangleMesh mesh);

/// The scene with the mesh of every object (static and dynamic obstacles, critical objects,
/// targets) replaced by `cut(mesh)`.
core::Scene cut_every_object(
    const core::Scene& scene,
    const std::function<core::TriangleMesh(const core::TriangleMesh&)>& cut);

/// The hand cases of docs/design/labelling.md L9, both with one cone camera (30°) meant to sit
/// at the origin looking along +x at the voxel (4, 5, 5) = [0.9, 1.1] × [−0.1, 0.1]², a small
/// target and a critical box out of the way, and one static obstacle below and beyond that
/// voxel. slab_scene: S = [0.1, 4.1] × [−1.1, 1.1]², 20 × 11 × 11 voxels, the box slab
/// [0.2, 3.5] × [−0.5, 0.5] × [−0.5, −0.3]. prism_scene: S = [0.1, 6.1] × [−1.1, 1.1]²,
/// 30 × 11 × 11 voxels, the convex prism over the quadrilateral (x, z) = (0.3, −0.6), (6, −0.6),
/// (6, −0.35), (3, −0.35) for y in [−0.5, 0.5] (12 triangles).
core::Scene slab_scene();
core::Scene prism_scene();

}  // namespace camplace::testing
