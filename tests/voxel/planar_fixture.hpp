#pragma once
// A planar test room: S = [0,4]×[0,4]×[0,0.25] m cut into 16×16×1 voxels of 0.25 m, one
// camera at (0, 2, 0.125) looking along +x with pitch 0, so every voxel centre lies in the
// camera's horizontal plane and labels follow from 2-D slopes s = |y − 2| / x by hand.
#include <cmath>

#include "camplace/voxel/evaluator.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {

inline core::Box3 planar_area() { return {core::Vec3(0, 0, 0), core::Vec3(4, 4, 0.25)}; }

/// Planar scene with one cone camera of half angle 30°, a critical box and the given targets.
/// The default target sits in the corner (0..0.25, 3.75..4): outside the FOV.
inline core::Scene planar_scene(std::vector<core::SceneObject> targets = {}) {
  if (targets.empty()) {
    targets.push_back(box_object("corner target", {0, 3.75, 0}, {0.25, 4, 0.25}));
  }
  return simple_scene(planar_area(), {16, 16, 1}, 1, 30.0,
                      {box_object("critical", {1.0, 1.9, 0}, {1.1, 2.1, 0.25})},
                      std::move(targets));
}

inline core::CameraSetting planar_camera() { return camera_at({0, 2, 0.125}, 0, 0); }

/// Voxel (i, j) centre in the plane.
inline double cx(int i) { return 0.125 + 0.25 * i; }
inline double cy(int j) { return 0.125 + 0.25 * j; }
/// |y − 2| / x of voxel (i, j)'s centre.
inline double slope(int i, int j) { return std::abs(cy(j) - 2.0) / cx(i); }
inline bool near(double a, double b) { return std::abs(a - b) < 1e-9; }

}  // namespace camplace::testing
