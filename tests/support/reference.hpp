#pragma once
// Brute-force reference for the sensor model of SPEC §3: one point, one camera, every ray
// tested against every triangle with a plain ray–plane + barycentric test. Written
// independently of voxel/ (no culling, no shared helpers) so tests can use it as an oracle.
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/voxel/evaluator.hpp"

namespace camplace::testing {

struct ReferenceLabel {
  voxel::Label label = voxel::Label::undetectable;
  bool ambiguous = false;  ///< the point lies within `margin` of a boundary (tie)
};

/// κ(p) for one camera (with the model of the scene's camera `camera_index`) in state (h, l)
/// of the scene; ties flagged within `margin` metres.
ReferenceLabel reference_label(const core::Scene& scene, int time_step, int event,
                               const core::CameraSetting& camera, const core::Vec3& p,
                               double margin = 1e-7, int camera_index = 0);

/// The conservative label of a whole box (SPEC §5) for one camera in state (h, l), as the
/// voxel pipeline defines it, brute force: free only when the camera is outside the box's
/// bounding ball, all 8 corners are in the FOV, no triangle of an occupying object has a cone
/// (from the camera) meeting the box, and no other triangle both has such a cone and comes
/// nearer to the camera than the box's farthest corner; occupied when an occupying triangle's
/// cone meets the box, else undetectable. Back faces of a closed, outward object that the camera
/// lies outside of (clear of its surface) are not tested: the first meeting point of a segment
/// from the camera lies on a front face (SPEC §3), and the pipeline defines the label so (a back
/// face can come nearer than the box's farthest corner where the front faces over the same rays
/// lie beyond it: large obstacles, e.g. walls crossing S). Every other triangle is tested (no
/// bins); the cone–box test is an LP duality computation, not the pipeline's separating axes.
/// Ties (`ambiguous`) within `margin` metres, and where culling an object near its thresholds
/// would change the label.
ReferenceLabel reference_box_label(const core::Scene& scene, int time_step, int event,
                                   const core::CameraSetting& camera, const core::Box3& box,
                                   double margin = 1e-7, int camera_index = 0);

/// True when p is inside the closed mesh, by counting crossings of a fixed skew ray.
bool reference_inside(const core::TriangleMesh& mesh, const core::Vec3& p);

}  // namespace camplace::testing
