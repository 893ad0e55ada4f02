#pragma once
/// The voxel grid over the surveillance area S (SPEC §5).
#include <array>

#include "camplace/core/geometry.hpp"

namespace camplace::voxel {

/// S cut into n[0]·n[1]·n[2] equal voxels; voxel (i, j, k) has index i + nx·(j + ny·k).
struct Grid {
  core::Box3 area;
  std::array<int, 3> n{0, 0, 0};
  core::Vec3 step = core::Vec3::Zero();  ///< voxel edge lengths (m)
  int count() const { return n[0] * n[1] * n[2]; }
  /// The closed box of voxel `index` (m, world frame).
  core::Box3 voxel_box(int index) const;
  core::Vec3 voxel_center(int index) const;
  /// Voxel volume (m³).
  double voxel_volume() const { return step.prod(); }
};

/// The grid of n voxels over `area`.
Grid make_grid(const core::Box3& area, const std::array<int, 3>& n);

}  // namespace camplace::voxel
