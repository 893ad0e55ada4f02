#pragma once
// The occupied part of one camera's view as outlines in its image plane (SPEC §3, the silhouette
// cones of the occupying objects), and the split of an occluding solid's front faces into patches
// whose shadows are simple polyhedra: exact 2D work on the projected faces instead of 3D Nef unions
// of per-face cones. Implemented in outline.cpp, which has no Nef code; the cones over the
// outlines and the patches' shadows are built in cones.hpp.
#include <array>
#include <vector>

#include "camplace/core/camera.hpp"
#include "internal/faces.hpp"

namespace camplace::exact::internal {

/// A camera's image plane {x : (x − c)·d = 1}, d its viewing direction (exact from the double
/// one), with exact axes a, b orthogonal to d and to each other, a × b pointing along d. The image
/// point of x is (s, r) = ((x − c)·a, (x − c)·b) / ((x − c)·d). The square window
/// |s|, |r| ≤ half_width holds the image of the FOV with a wide margin.
struct ImagePlane {
  Point c;
  Vector d, a, b;
  FT half_width;
};

/// The image plane of a camera with the FOV `model` (SPEC §1) at `setting`.
ImagePlane image_plane(const core::CameraSetting& setting, const core::CameraModel& model);

/// A simple polygon of the image plane: a point on the ray from c through each vertex (the scene
/// point that projects there when there is one, else the vertex on the image plane; each with
/// (x − c)·d > 0), in counter-clockwise order about d, and a triangulation of the polygon
/// (indices into `points`, counter-clockwise). The points need not be coplanar.
struct OutlineCycle {
  std::vector<Point> points;
  std::vector<std::array<int, 3>> triangles;
};

/// One connected piece of an outline: the union of `outer` minus the union of `holes`.
struct OutlineRegion {
  std::vector<OutlineCycle> outer, holes;
};

/// The directions in the window in which camera c (outside every solid given) first meets an
/// occupying solid, as image-plane regions: for each front face f of an occupying solid, the image
/// of f minus the images of the blockers' front faces g cut to the camera's side of f's plane
/// (g ∩ H̄_f: a ray through both meets that part of g first) — the per-face construction of
/// occupied_cone in cones.hpp, with the booleans done in 2D and the faces nothing hides joined
/// through their silhouette edges only. Directions outside the window are left out; the FOV holds
/// none of them.
std::vector<OutlineRegion> occupied_outline(const ImagePlane& plane,
                                            const std::vector<const Faces*>& occupying,
                                            const std::vector<const Faces*>& blockers);

/// The front faces of a closed solid (camera c outside it) grouped for its shadow (shadow in
/// cones.hpp), each face index into `solid.triangles`:
///   patches  groups of faces with every vertex strictly in front of c ((x − c)·d > 0) whose
///            images in the image plane have pairwise disjoint interiors and whose boundary (the
///            edges of one face of the group only) projects onto pairwise disjoint simple closed
///            polygons, each edge once: the shadow of such a group is bounded by the group, the
///            walls along the rays over its boundary edges and the group scaled from c (a closed
///            2-manifold);
///   single   faces with vertices on both sides of the plane (x − c)·d = 0 (their own hulls).
/// Faces with no vertex strictly in front of c are left out: their shadows meet the FOV, which
/// lies in {c} ∪ {(x − c)·d > 0}, nowhere.
struct ShadowPatches {
  std::vector<std::vector<int>> patches;
  std::vector<int> single;
};

/// The front faces of `solid` (outward faces, c = plane.c outside it) grouped as ShadowPatches:
/// the faces in front of c grown into layers through shared edges, each face joining the first
/// layer where its image's interior meets no other face's, and a layer whose boundary images
/// still touch split in two halves (in breadth-first order) until each part passes (a single face
/// always does). Every group is accepted only by the exact check of ShadowPatches.
ShadowPatches shadow_patches(const ImagePlane& plane, const Faces& solid);

}  // namespace camplace::exact::internal
