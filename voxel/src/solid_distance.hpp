#pragma once
// Distances from voxel boxes and centres to closed solids, equal to core's
// box_solid_sq_distance / point_solid_sq_distance (same primitives on the same numbers, so the
// same doubles) but with bounding-box culling: a triangle, or one of the vertex, corner and
// edge pairs core's triangle–box distance takes the minimum over, is skipped only when a lower
// bound of its distance (the gap between bounding boxes) exceeds a known upper bound of the
// minimum by a margin (relative 1e-9 plus 1e-18 m², far above rounding). Every computed
// candidate is the distance between two actual points (core's closest-point routines clamp to
// the features), so a skipped one could not have been the minimum. The triangles are found
// through a bounding-volume hierarchy (whole subtrees skipped by the same test on their boxes),
// which changes which candidates are computed, not the minimum. Private to voxel/.
#include <array>
#include <vector>

#include "camplace/core/box_tree.hpp"
#include "camplace/core/geometry.hpp"

namespace camplace::voxel::detail {

/// One closed solid with the bounding boxes the culling needs.
struct IndexedSolid {
  const core::TriangleMesh* mesh = nullptr;
  core::Box3 bounds;  ///< of the vertices
  std::vector<std::array<core::Vec3, 3>> triangles;
  std::vector<core::Box3> triangle_bounds;
  std::vector<std::array<core::Box3, 3>> edge_bounds;  ///< edge i = vertices (i, i + 1)
  std::vector<core::Vec3> unit_normals;                ///< zero for a degenerate triangle
  /// Over the triangles' bounds (core::build_box_tree, leaves of 4): node 0 the root (none: no
  /// triangle); a leaf holds the triangles order[first .. first + count).
  std::vector<core::BoxTreeNode> nodes;
  std::vector<int> order;  ///< triangle indices in leaf order
  /// Every edge is used as often in one direction as in the other (a closed, consistently
  /// oriented surface): then the winding number is an integer off the surface, and inside_solid
  /// may count crossings instead of summing solid angles.
  bool closed = false;
};

IndexedSolid index_solid(const core::TriangleMesh& mesh);

/// True when the lower bound `lb` (m²) proves a distance larger than `cutoff` (m²).
inline bool beyond(double lb, double cutoff) { return lb > cutoff * (1.0 + 1e-9) + 1e-18; }

/// Smallest squared distance from `box` to any vertex of the solids: an upper bound of the
/// box–solid distance (vertices belong to the solids).
double vertex_upper_bound(const std::vector<IndexedSolid>& solids, const core::Box3& box);
double vertex_upper_bound(const std::vector<IndexedSolid>& solids, const core::Vec3& p);

/// min over the solids of core::box_solid_sq_distance(mesh, box) when that minimum is at most
/// `cutoff`; otherwise some value above `cutoff` (possibly infinity).
double box_solids_sq_distance(const std::vector<IndexedSolid>& solids, const core::Box3& box,
                              double cutoff);
/// A triangle of one of the solids: indices into a solids vector and its triangles.
struct NearestTriangle {
  int solid = -1;  ///< none
  int triangle = -1;
};

/// min over the solids of core::point_solid_sq_distance(mesh, p), same contract. Without
/// `inside_test`: the distance to the solids' surfaces (no point counts as inside), which is at
/// least that minimum. With `nearest`: a triangle whose distance is taken as a cutoff on entry
/// (when set; a neighbouring point's nearest one makes the search short), and on return the
/// triangle holding the minimum when one does (unchanged otherwise).
double point_solids_sq_distance(const std::vector<IndexedSolid>& solids, const core::Vec3& p,
                                double cutoff, bool inside_test = true,
                                NearestTriangle* nearest = nullptr);

/// core::inside_mesh(*s.mesh, p), the same answer: on a closed solid (IndexedSolid::closed),
/// from the signed crossings of the ray from p along +z with the triangles found through the
/// hierarchy, each decided only when its floating-point signs are certain (else, and on an
/// open mesh, the solid-angle sum itself). See solid_distance.cpp.
bool inside_solid(const IndexedSolid& s, const core::Vec3& p);

/// Whether a triangle of the solid meets `box` (core::triangle_box_overlap).
bool box_meets_surface(const IndexedSolid& s, const core::Box3& box);
/// Whether `box` lies wholly inside the solid: its centre is inside (inside_solid) and, with
/// `faces`, no triangle meets the box shrunk by `depth` on every side (faces lying on the box's
/// boundary do not count).
bool box_inside_solid(const IndexedSolid& s, const core::Box3& box, double depth,
                      bool faces = true);

}  // namespace camplace::voxel::detail
