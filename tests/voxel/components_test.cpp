// The component filter alone (SPEC §4–5), on grids small enough to count by hand.
#include "camplace/voxel/components.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <queue>
#include <random>

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

// Breadth-first flood fill over the 6 face neighbours, components numbered in the order of
// their first voxel: the labels component_labels must give (an independent method).
std::vector<int> flood_fill_labels(const std::vector<std::uint8_t>& model, const voxel::Grid& g) {
  const int nx = g.n[0], ny = g.n[1], nz = g.n[2];
  std::vector<int> labels(model.size(), -1);
  int next = 0;
  for (int start = 0; start < g.count(); ++start) {
    if (!model[start] || labels[start] >= 0) continue;
    std::queue<int> queue;
    queue.push(start);
    labels[start] = next;
    while (!queue.empty()) {
      const int v = queue.front();
      queue.pop();
      const int i = v % nx, j = (v / nx) % ny, k = v / (nx * ny);
      const int step[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
      for (const auto& d : step) {
        const int a = i + d[0], b = j + d[1], c = k + d[2];
        if (a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= nz) continue;
        const int u = a + nx * (b + ny * c);
        if (model[u] && labels[u] < 0) {
          labels[u] = next;
          queue.push(u);
        }
      }
    }
    ++next;
  }
  return labels;
}

TEST(Components, LabelsEqualAFloodFillOnRandomModels) {
  // Rows of one 64-bit word and of several (runs that cross from one word into the next, rows
  // of exactly 64 and 128 voxels), sparse and dense models, and runs of random lengths (long
  // runs of 1 and of 0 along x).
  std::mt19937 rng(4242);
  long voxels = 0;
  for (const std::array<int, 3> n : {std::array<int, 3>{5, 4, 3},
                                     {9, 5, 4},
                                     {17, 6, 5},
                                     {36, 7, 6},
                                     {64, 3, 3},
                                     {77, 3, 3},
                                     {128, 2, 2},
                                     {150, 3, 2}}) {
    const voxel::Grid grid = voxel::make_grid({core::Vec3(0, 0, 0), core::Vec3(1, 1, 1)}, n);
    for (const double density : {0.1, 0.5, 0.9}) {
      for (int trial = 0; trial < 4; ++trial) {
        std::vector<std::uint8_t> model(grid.count(), 0);
        std::bernoulli_distribution start(1.0 - density), stay(0.85);
        // Runs along x: each voxel repeats its left neighbour with probability 0.85.
        for (int v = 0; v < grid.count(); ++v) {
          const bool first = v % n[0] == 0;
          model[v] = first || !stay(rng) ? static_cast<std::uint8_t>(!start(rng)) : model[v - 1];
        }
        const std::vector<int> expected = flood_fill_labels(model, grid);
        ASSERT_EQ(voxel::component_labels(model, grid), expected)
            << n[0] << "x" << n[1] << "x" << n[2] << " density " << density;
        voxels += std::count(model.begin(), model.end(), 1);
        // Any byte other than 0 is in the model.
        std::uniform_int_distribution<int> value(1, 255);
        for (auto& b : model) b = b ? static_cast<std::uint8_t>(value(rng)) : 0;
        ASSERT_EQ(voxel::component_labels(model, grid), expected) << "bytes other than 1";
      }
    }
  }
  EXPECT_GT(voxels, 10000);
}

TEST(Components, FilterEqualsTheRuleOnFloodFillComponentsOfRandomModels) {
  // Volume and z-extent of each flood-fill component, the rule of SPEC §4 applied by hand;
  // rows of one and of several words (a removed run may span words).
  std::mt19937 rng(777);
  int removed_total = 0, kept_total = 0;
  for (const std::array<int, 3> n :
       {std::array<int, 3>{9, 5, 4}, {36, 7, 6}, {64, 4, 3}, {130, 4, 4}}) {
    const voxel::Grid grid = voxel::make_grid({core::Vec3(0, 0, 0), core::Vec3(1, 1, 1)}, n);
    for (const double density : {0.2, 0.5, 0.8}) {
      std::vector<std::uint8_t> model(grid.count(), 0);
      std::bernoulli_distribution on(density), stay(0.8);
      for (int v = 0; v < grid.count(); ++v) {
        model[v] = v % n[0] == 0 || !stay(rng) ? static_cast<std::uint8_t>(on(rng)) : model[v - 1];
      }
      const std::vector<int> labels = flood_fill_labels(model, grid);
      const int components = *std::max_element(labels.begin(), labels.end()) + 1;
      std::vector<int> cells(components, 0), kmin(components, n[2]), kmax(components, -1);
      for (int v = 0; v < grid.count(); ++v) {
        if (labels[v] < 0) continue;
        const int k = v / (n[0] * n[1]);
        ++cells[labels[v]];
        kmin[labels[v]] = std::min(kmin[labels[v]], k);
        kmax[labels[v]] = std::max(kmax[labels[v]], k);
      }
      core::Plausibility filter;
      filter.min_volume = 6.5 * grid.voxel_volume();  // 7 voxels or more
      filter.min_height = 1.5 * grid.step.z();        // 2 layers or more
      std::vector<std::uint8_t> expected(grid.count(), 0);
      int kept = 0;
      for (int c = 0; c < components; ++c) kept += cells[c] >= 7 && kmax[c] - kmin[c] >= 1;
      for (int v = 0; v < grid.count(); ++v) {
        const int c = labels[v];
        expected[v] = c >= 0 && cells[c] >= 7 && kmax[c] - kmin[c] >= 1;
      }
      const voxel::ComponentCount count = voxel::filter_components(model, grid, filter);
      EXPECT_EQ(count.kept, kept);
      EXPECT_EQ(count.removed, components - kept);
      ASSERT_EQ(model, expected) << n[0] << "x" << n[1] << "x" << n[2] << " density " << density;
      kept_total += kept;
      removed_total += components - kept;
    }
  }
  EXPECT_GT(kept_total, 10);
  EXPECT_GT(removed_total, 50);
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

TEST(Components, SharedCoreFilterEqualsEachModelsOwnFilter) {
  // Chunks of models that share a random base and each add voxels of their own (few or many,
  // touching the base or apart; one model with nothing of its own, and a chunk of one model):
  // filtered together (the components of the voxels all hold, then each model's others; C1),
  // each gets filter_components' result on it alone. Rows of one word and of several.
  std::mt19937 rng(99);
  int joined = 0, removed = 0;
  for (const std::array<int, 3> n :
       {std::array<int, 3>{9, 5, 4}, {36, 7, 6}, {64, 4, 3}, {130, 4, 4}}) {
    const voxel::Grid grid = voxel::make_grid({core::Vec3(0, 0, 0), core::Vec3(1, 1, 1)}, n);
    core::Plausibility filter;
    filter.min_volume = 6.5 * grid.voxel_volume();  // 7 voxels or more
    filter.min_height = 1.5 * grid.step.z();        // 2 layers or more
    for (const double base_density : {0.0, 0.2, 0.5, 0.8}) {
      for (const int count : {1, 5, 64}) {
        std::bernoulli_distribution base_on(base_density), stay(0.8);
        std::vector<std::uint8_t> base(grid.count(), 0);
        for (int v = 0; v < grid.count(); ++v) {
          base[v] =
              v % n[0] == 0 || !stay(rng) ? static_cast<std::uint8_t>(base_on(rng)) : base[v - 1];
        }
        std::vector<std::vector<std::uint8_t>> models(count, base);
        for (int m = 1; m < count; ++m) {
          std::bernoulli_distribution extra(m % 2 ? 0.02 : 0.3);
          for (auto& b : models[m]) b = b || extra(rng);
        }
        std::vector<std::vector<std::uint8_t>> expected = models;
        std::vector<voxel::ComponentCount> expected_counts;
        for (auto& model : expected) {
          expected_counts.push_back(voxel::filter_components(model, grid, filter));
        }
        const std::vector<voxel::ComponentCount> counts =
            voxel::filter_components_together(models, grid, filter);
        ASSERT_EQ(counts.size(), expected_counts.size());
        for (int m = 0; m < count; ++m) {
          EXPECT_EQ(counts[m].kept, expected_counts[m].kept) << m;
          EXPECT_EQ(counts[m].removed, expected_counts[m].removed) << m;
          ASSERT_EQ(models[m], expected[m]) << n[0] << "x" << n[1] << "x" << n[2] << " base "
                                            << base_density << " model " << m << " of " << count;
          joined += expected_counts[m].kept;
          removed += expected_counts[m].removed;
        }
      }
    }
  }
  EXPECT_GT(joined, 100);
  EXPECT_GT(removed, 100);
}

}  // namespace
}  // namespace camplace
