#pragma once
// A check of the shadow construction for tests (no CGAL type here): the shadow of one solid built
// from patches in the image plane against the union of its front faces' shadows. Implemented in
// exact_pipeline.cpp.
#include "camplace/core/camera.hpp"
#include "camplace/core/geometry.hpp"

namespace camplace::exact::internal {

/// What check_shadow found.
struct ShadowCheck {
  bool camera_inside = false;  ///< c lies in the closed solid (nothing built)
  bool convex = false;         ///< the solid is convex (one hull either way)
  bool same = false;           ///< the two constructions agree within FOV ∩ box (regularised)
  int front_faces = 0;
  int patches = 0;  ///< shadow_patches' patches
  int single = 0;   ///< faces crossing the plane (x − c)·d = 0, built one by one
};

/// Builds the shadow of the closed solid `mesh` (outward triangles, m, world frame) for a camera
/// of FOV `model` at `setting` both ways (shadow in cones.hpp, with and without per_face) and
/// compares them within the camera's FOV cut to `box` (the clip box): the symmetric difference of
/// the two regularised is empty.
ShadowCheck check_shadow(const core::TriangleMesh& mesh, const core::CameraSetting& setting,
                         const core::CameraModel& model, const core::Box3& box);

}  // namespace camplace::exact::internal
