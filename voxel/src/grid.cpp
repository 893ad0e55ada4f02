// The voxel grid (SPEC §5).
#include "camplace/voxel/grid.hpp"

namespace camplace::voxel {

using core::Box3;
using core::Vec3;

Box3 Grid::voxel_box(int index) const {
  const int i = index % n[0], j = (index / n[0]) % n[1], k = index / (n[0] * n[1]);
  Box3 box;
  box.min = area.min + Vec3(i * step.x(), j * step.y(), k * step.z());
  box.max = box.min + step;
  return box;
}

Vec3 Grid::voxel_center(int index) const { return voxel_box(index).center(); }

Grid make_grid(const Box3& area, const std::array<int, 3>& n) {
  Grid grid;
  grid.area = area;
  grid.n = n;
  grid.step = area.size().cwiseQuotient(Vec3(n[0], n[1], n[2]));
  return grid;
}

}  // namespace camplace::voxel
