// The viewer's meshes: the voxel model's merged boundary against the voxels themselves (volume,
// inside/outside by winding number) and the clipped FOV against hand-computed pyramids and the
// FOV's own point test.
#include "camplace/view/meshing.hpp"

#include <gtest/gtest.h>

#include <random>

#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using core::Vec3;

const core::Box3 kArea{Vec3(0, 0, 0), Vec3(4, 3, 3)};

TEST(VoxelBoundaryMesh, FullGridIsSixRectangles) {
  const voxel::Grid grid = voxel::make_grid(kArea, {16, 12, 12});
  const core::TriangleMesh mesh =
      view::voxel_boundary_mesh(grid, std::vector<std::uint8_t>(grid.count(), 1));
  EXPECT_EQ(mesh.triangles.size(), 12u);
  EXPECT_NEAR(core::signed_volume(mesh), 36.0, 1e-12);
}

TEST(VoxelBoundaryMesh, EmptyModelHasNoFaces) {
  const voxel::Grid grid = voxel::make_grid(kArea, {4, 3, 3});
  EXPECT_TRUE(view::voxel_boundary_mesh(grid, std::vector<std::uint8_t>(grid.count(), 0))
                  .triangles.empty());
}

TEST(VoxelBoundaryMesh, RandomModelsKeepVolumeAndInsideOutside) {
  std::mt19937 rng(3);
  const voxel::Grid grid = voxel::make_grid(kArea, {7, 5, 4});
  for (int trial = 0; trial < 20; ++trial) {
    std::bernoulli_distribution in_model(trial % 2 ? 0.7 : 0.3);
    std::vector<std::uint8_t> model(grid.count());
    int count = 0, naive_faces = 0;
    for (auto& m : model) count += (m = in_model(rng));
    // The faces a cube-per-voxel mesh would need: model voxel next to a non-model one or S.
    for (int v = 0; v < grid.count(); ++v) {
      if (!model[v]) continue;
      const int i = v % 7, j = (v / 7) % 5, k = v / 35;
      const int nb[6][3] = {{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k},
                            {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}};
      for (const auto& c : nb) {
        const bool inside = c[0] >= 0 && c[0] < 7 && c[1] >= 0 && c[1] < 5 && c[2] >= 0 && c[2] < 4;
        naive_faces += !inside || !model[c[0] + 7 * (c[1] + 5 * c[2])];
      }
    }
    const core::TriangleMesh mesh = view::voxel_boundary_mesh(grid, model);
    EXPECT_NEAR(core::signed_volume(mesh), count * grid.voxel_volume(), 1e-9) << trial;
    EXPECT_LE(mesh.triangles.size(), 2u * naive_faces) << trial;
    if (count > 0 && count < grid.count()) {
      EXPECT_LT(mesh.triangles.size(), 2u * naive_faces) << trial;  // some faces were merged
    }
    // Closed and outward: every voxel centre is inside exactly when the voxel is in the model.
    for (int v = 0; v < grid.count(); ++v) {
      EXPECT_EQ(core::inside_mesh(mesh, grid.voxel_center(v)), model[v] != 0)
          << trial << " voxel " << v;
    }
    for (const Vec3& p : mesh.vertices) EXPECT_TRUE(kArea.contains(p));
  }
}

/// A k-sided inscribed pyramid of half angle α cut at depth h (nothing else cutting it) has
/// volume (1/3)·h·(k/2)·r²·sin(2π/k), r = h·tan α.
double pyramid_volume(int k, double half_angle, double h) {
  const double r = h * std::tan(half_angle);
  return h / 3.0 * 0.5 * k * r * r * std::sin(2.0 * core::kPi / k);
}

TEST(FovMesh, DownwardPyramidReachingTheFloor) {
  core::CameraModel spec;
  spec.fov = core::FovShape::pyramid;
  spec.sides = 4;
  spec.half_angle = 30.0 * core::kDegree;
  // Apex 2 m above the floor at S's centre: S's floor cuts it at depth 2, the diamond of
  // half-diagonal 2·tan 30° = 1.155 m fits inside S.
  const core::TriangleMesh mesh = view::fov_mesh(camera_at({2, 1.5, 2}, 0, -90), spec, kArea);
  EXPECT_NEAR(core::signed_volume(mesh), 2.0 / 3.0 * 8.0 / 3.0, 1e-12);  // (2/3) h³ tan²α
  EXPECT_NEAR(core::signed_volume(mesh), pyramid_volume(4, spec.half_angle, 2.0), 1e-12);
  for (const Vec3& p : mesh.vertices) EXPECT_TRUE(kArea.contains(p));
}

TEST(FovMesh, RangeCutsThePyramid) {
  core::CameraModel spec;
  spec.fov = core::FovShape::pyramid;
  spec.sides = 6;
  spec.half_angle = 25.0 * core::kDegree;
  spec.range = 1.0;
  const core::TriangleMesh mesh = view::fov_mesh(camera_at({1.5, 1.5, 1.5}, 0, 0), spec, kArea);
  EXPECT_NEAR(core::signed_volume(mesh), pyramid_volume(6, spec.half_angle, 1.0), 1e-12);
  double far = 0;
  for (const Vec3& p : mesh.vertices) far = std::max(far, p.x() - 1.5);
  EXPECT_NEAR(far, 1.0, 1e-12);
}

TEST(FovMesh, ClippedFovAgreesWithTheFovPointTest) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ux(0, 4), uy(0, 3), uz(0, 3);
  struct Case {
    Vec3 position;
    double yaw, pitch;
    core::FovShape shape;
    std::optional<double> range;
  } cases[] = {{{0.3, 0.2, 2.8}, 30, -40, core::FovShape::pyramid, std::nullopt},
               {{4.0, 3.0, 3.0}, -143.13, -35, core::FovShape::cone, std::nullopt},
               {{-1.0, 1.5, 1.0}, 10, 5, core::FovShape::pyramid, 3.0},
               {{2.0, 1.5, 0.5}, 0, 90, core::FovShape::cone, std::nullopt}};
  for (const Case& c : cases) {
    core::CameraModel spec;
    spec.fov = c.shape;
    spec.sides = 16;
    spec.half_angle = 30.0 * core::kDegree;
    spec.range = c.range;
    const core::CameraSetting camera = camera_at(c.position, c.yaw, c.pitch);
    const core::TriangleMesh mesh = view::fov_mesh(camera, spec, kArea);
    ASSERT_FALSE(mesh.triangles.empty());
    // The drawn shape: the inscribed pyramid (k = 16, or kConeDrawSides for a cone).
    const int sides = c.shape == core::FovShape::pyramid ? 16 : view::kConeDrawSides;
    const core::Fov fov(camera, core::FovShape::pyramid, spec.half_angle, sides, spec.range);
    int checked = 0, inside = 0;
    for (int n = 0; n < 4000; ++n) {
      const Vec3 p(ux(rng), uy(rng), uz(rng));
      // Skip points within 1e-6 m of the FOV's planes (the winding number may go either way).
      double margin = 1e300;
      for (const Vec3& normal : fov.pyramid_normals()) {
        margin = std::min(margin, std::abs(normal.dot(p - fov.apex())));
      }
      if (spec.range) margin = std::min(margin, std::abs((p - fov.apex()).dot(fov.axis()) - 3.0));
      if (margin < 1e-6) continue;
      ++checked;
      inside += fov.contains(p);
      EXPECT_EQ(core::inside_mesh(mesh, p), fov.contains(p)) << p.transpose();
    }
    EXPECT_GT(checked, 3900);
    EXPECT_GT(inside, 40);  // the case tests something
    for (const Vec3& p : mesh.vertices) {
      EXPECT_TRUE((p.array() >= kArea.min.array() - 1e-12).all() &&
                  (p.array() <= kArea.max.array() + 1e-12).all());
    }
  }
}

TEST(FovMesh, CameraLookingAwayFromSHasNoMesh) {
  core::CameraModel spec;
  spec.half_angle = 30.0 * core::kDegree;
  EXPECT_TRUE(view::fov_mesh(camera_at({-1, 1.5, 1.5}, 180, 0), spec, kArea).triangles.empty());
}

}  // namespace
}  // namespace camplace::testing
