// The exact distance d(C, M) with the floating-point filter (ExactOptions::filtered_distances, the
// default) against the reference, branch and bound on box distances alone (filtered_distances
// off): the same exact fraction for critical meshes of 50–800 triangles placed at random about
// models with rational vertices, among them meshes that touch, cross or hold the model and meshes
// nearly parallel to its faces; and the same fractions state by state for whole evaluations of
// random scenes with fine meshes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "../core/fine_meshes.hpp"
#include "camplace/core/camera.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/exact/evaluator.hpp"
#include "scene_builder.hpp"

namespace camplace {
namespace {

using core::Vec3;

const std::string kSource = CAMPLACE_SOURCE_DIR;

/// A random rotation (uniform axis, angle in [0, π)).
Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> angle(0.0, 3.14159265358979);
  Vec3 axis(n(rng), n(rng), n(rng));
  axis.normalize();
  return Eigen::AngleAxisd(angle(rng), axis).toRotationMatrix();
}

/// An ellipsoid of 50–800 triangles (2·slices·(stacks − 1)) turned at random, centred near a
/// random point of `near` (the model's box) widened by `margin` (m), with semi-axes from 0.05 to
/// 0.6 m.
core::TriangleMesh random_solid(std::mt19937& rng, const core::Box3& near, double margin_m = 0.7) {
  std::uniform_int_distribution<int> slices(5, 20), stacks(4, 21);
  int s = slices(rng), t = stacks(rng);
  while (2 * s * (t - 1) > 800) --t;
  while (2 * s * (t - 1) < 50) ++t;
  std::uniform_real_distribution<double> u(0.0, 1.0), r(0.05, 0.6);
  const Vec3 margin = Vec3::Constant(margin_m);
  const Vec3 lo = near.min - margin, size = near.max + margin - lo;
  const Vec3 center = lo + Vec3(u(rng) * size.x(), u(rng) * size.y(), u(rng) * size.z());
  return testing::ellipsoid(center, Vec3(r(rng), r(rng), r(rng)), s, t, random_rotation(rng));
}

/// A thin slab a little outside one of the model's boundary triangles, parallel to it: many
/// pairs of triangles at nearly the same distance, the filter's hardest case.
core::TriangleMesh parallel_slab(std::mt19937& rng, const core::TriangleMesh& boundary) {
  std::uniform_int_distribution<std::size_t> pick(0, boundary.triangles.size() - 1);
  const auto& t = boundary.triangles[pick(rng)];
  const Vec3 a = boundary.vertices[t[0]], b = boundary.vertices[t[1]], c = boundary.vertices[t[2]];
  const Vec3 n = (b - a).cross(c - a).normalized();
  const Vec3 center = (a + b + c) / 3.0 + n * 1e-3;
  // An ellipsoid flattened along n (its local z), its wide face parallel to the triangle.
  Eigen::Matrix3d frame;
  const Vec3 e1 = (b - a).normalized();
  frame << e1, n.cross(e1), n;
  return testing::ellipsoid(center + n * 0.01, Vec3(0.3, 0.3, 0.01), 12, 6, frame);
}

/// Compares the filtered distance with the reference for `count` random solids (and as many
/// parallel slabs) about `model`; returns how many were at distance 0.
int expect_same_distances(const exact::ExactModel& model, std::mt19937& rng, int count) {
  const core::TriangleMesh boundary = model.boundary_mesh();
  EXPECT_FALSE(boundary.triangles.empty());
  core::Box3 box{boundary.vertices.front(), boundary.vertices.front()};
  for (const auto& v : boundary.vertices) {
    box.min = box.min.cwiseMin(v);
    box.max = box.max.cwiseMax(v);
  }
  int zero = 0;
  for (int k = 0; k < count; ++k) {
    std::vector<core::TriangleMesh> solids{random_solid(rng, box)};
    if (k % 3 == 0) solids.push_back(random_solid(rng, box));  // a union of two
    if (k % 4 == 1) {
      // Centred on a vertex of the model: they meet (distance 0).
      std::uniform_int_distribution<std::size_t> pick(0, boundary.vertices.size() - 1);
      const Vec3 v = boundary.vertices[pick(rng)];
      solids = {random_solid(rng, core::Box3{v, v}, 0.0)};
    }
    const std::string filtered = model.squared_distance_fraction(solids, true);
    const std::string reference = model.squared_distance_fraction(solids, false);
    EXPECT_EQ(filtered, reference) << "solid " << k;
    zero += reference == "0/1";
    const std::vector<core::TriangleMesh> slab{parallel_slab(rng, boundary)};
    EXPECT_EQ(model.squared_distance_fraction(slab, true),
              model.squared_distance_fraction(slab, false))
        << "slab " << k;
  }
  return zero;
}

// paper_basic's model (its corners configuration, state (0, 0)): few, long-rational vertices.
TEST(FilteredDistance, SameFractionsAsTheReferenceAboutPaperBasicsModel) {
  const core::Scene scene = core::load_scene(kSource + "/data/paper_basic.json");
  const core::CameraConfig config =
      core::load_camera_config(kSource + "/data/paper_basic_corners.json", scene);
  const exact::ExactModel model = exact::build_exact_model(scene, config, {0, 0});
  ASSERT_FALSE(model.empty());
  std::mt19937 rng(20261204);
  const int zero = expect_same_distances(model, rng, 30);
  // Some of the solids meet the model (distance 0), most do not.
  EXPECT_GT(zero, 0);
  EXPECT_LT(zero, 30);
}

// Models of random scenes whose targets are fine ellipsoids: many boundary triangles with the
// cone facets' long rationals.
TEST(FilteredDistance, SameFractionsAsTheReferenceAboutFineMeshModels) {
  std::mt19937 rng(7);
  int models = 0;
  for (int attempt = 0; attempt < 12 && models < 3; ++attempt) {
    const core::Scene scene = testing::with_fine_meshes(testing::random_scene(rng, {8, 6, 6}), 120);
    const core::CameraConfig config = testing::random_config(rng, scene);
    const exact::ExactModel model = exact::build_exact_model(scene, config, {0, 0});
    if (model.empty()) continue;
    ++models;
    expect_same_distances(model, rng, 10);
  }
  EXPECT_EQ(models, 3);
}

// Whole evaluations: every state's d_model² the same fraction with and without the filter.
TEST(FilteredDistance, WholeEvaluationsGiveTheSameFractions) {
  std::mt19937 rng(11);
  for (int k = 0; k < 4; ++k) {
    const core::Scene scene =
        testing::with_fine_meshes(testing::random_scene(rng, {8, 6, 6}), k % 2 ? 200 : 60);
    const core::CameraConfig config = testing::random_config(rng, scene);
    exact::ExactOptions options;
    options.threads = 1;
    const exact::ExactEvaluation filtered = exact::evaluate_exact(scene, config, options);
    options.filtered_distances = false;
    const exact::ExactEvaluation reference = exact::evaluate_exact(scene, config, options);
    ASSERT_EQ(filtered.states.size(), reference.states.size());
    for (std::size_t s = 0; s < filtered.states.size(); ++s) {
      EXPECT_EQ(filtered.states[s].d_model_sq_exact, reference.states[s].d_model_sq_exact)
          << "scene " << k << " state " << s;
      EXPECT_EQ(filtered.states[s].model_volume_exact, reference.states[s].model_volume_exact);
    }
  }
}

}  // namespace
}  // namespace camplace
