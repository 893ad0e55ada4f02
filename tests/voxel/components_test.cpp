// The component filter alone (SPEC §4–5), on grids small enough to count by hand.
#include "camplace/voxel/components.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace camplace {
namespace {

// A 4×3×2 grid of 1 m voxels over [0,4]×[0,3]×[0,2]; voxel (i, j, k) = i + 4·(j + 3·k).
voxel::Grid unit_grid() {
  core::Box3 area{core::Vec3(0, 0, 0), core::Vec3(4, 3, 2)};
  return voxel::make_grid(area, {4, 3, 2});
}
int at(int i, int j, int k) { return i + 4 * (j + 3 * k); }

TEST(Components, EdgeAndCornerContactDoNotConnectFaceContactDoes) {
  const voxel::Grid grid = unit_grid();
  std::vector<std::uint8_t> model(grid.count(), 0);
  model[at(0, 0, 0)] = 1;
  model[at(1, 1, 0)] = 1;  // shares only an edge with (0,0,0)
  model[at(2, 2, 1)] = 1;  // shares only a corner with (1,1,0)
  model[at(3, 2, 1)] = 1;  // shares a face with (2,2,1)
  const voxel::ComponentCount count = voxel::filter_components(model, grid, {});
  EXPECT_EQ(count.kept, 3);
  EXPECT_EQ(count.removed, 0);
  EXPECT_EQ(std::count(model.begin(), model.end(), 1), 4);
}

TEST(Components, LabelsNumberComponentsInTheOrderOfTheirFirstVoxel) {
  const voxel::Grid grid = unit_grid();
  std::vector<std::uint8_t> model(grid.count(), 0);
  model[at(2, 0, 0)] = 1;  // component 0 (first voxel by index)
  model[at(2, 1, 0)] = 1;  // face neighbour of (2,0,0): component 0
  model[at(0, 2, 0)] = 1;  // component 1
  model[at(3, 2, 0)] = 1;  // shares only an edge with (2,1,0): component 2
  model[at(0, 2, 1)] = 1;  // above (0,2,0): component 1
  const std::vector<int> labels = voxel::component_labels(model, grid);
  ASSERT_EQ(labels.size(), model.size());
  EXPECT_EQ(labels[at(2, 0, 0)], 0);
  EXPECT_EQ(labels[at(2, 1, 0)], 0);
  EXPECT_EQ(labels[at(0, 2, 0)], 1);
  EXPECT_EQ(labels[at(3, 2, 0)], 2);
  EXPECT_EQ(labels[at(0, 2, 1)], 1);
  EXPECT_EQ(std::count(labels.begin(), labels.end(), -1), grid.count() - 5);
}

TEST(Components, FilterRemovesComponentsBelowVolumeOrHeightAndKeepsTheRest) {
  const voxel::Grid grid = unit_grid();
  std::vector<std::uint8_t> model(grid.count(), 0);
  // A: a 2-voxel column (volume 2 m³, height 2 m); B: a 3-voxel row on the floor (3 m³, 1 m);
  // C: one voxel (1 m³, 1 m).
  model[at(0, 0, 0)] = model[at(0, 0, 1)] = 1;
  model[at(1, 2, 0)] = model[at(2, 2, 0)] = model[at(3, 2, 0)] = 1;
  model[at(3, 0, 1)] = 1;
  core::Plausibility filter;
  filter.min_volume = 1.5;  // removes C
  filter.min_height = 2.0;  // removes B and C
  const voxel::ComponentCount count = voxel::filter_components(model, grid, filter);
  EXPECT_EQ(count.kept, 1);
  EXPECT_EQ(count.removed, 2);
  std::vector<std::uint8_t> expected(grid.count(), 0);
  expected[at(0, 0, 0)] = expected[at(0, 0, 1)] = 1;
  EXPECT_EQ(model, expected);
}

TEST(Components, ThresholdsAreInclusive) {
  // SPEC §4: removed when volume < min_volume or height < min_height; equal values stay.
  const voxel::Grid grid = unit_grid();
  std::vector<std::uint8_t> model(grid.count(), 0);
  model[at(1, 1, 0)] = model[at(1, 1, 1)] = 1;  // 2 m³, 2 m tall
  core::Plausibility filter;
  filter.min_volume = 2.0;
  filter.min_height = 2.0;
  EXPECT_EQ(voxel::filter_components(model, grid, filter).kept, 1);
  filter.min_volume = std::nextafter(2.0, 3.0);
  EXPECT_EQ(voxel::filter_components(model, grid, filter).removed, 1);
  EXPECT_EQ(std::count(model.begin(), model.end(), 1), 0);
}

}  // namespace
}  // namespace camplace
