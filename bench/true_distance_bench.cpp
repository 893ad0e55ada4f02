// The exact true distance d(C, O_u) of every state of the bundled UR5e cell: camplace's
// filtered search (core::true_squared_distance) against measuring every triangle pair exactly,
// side by side in one run (the machine is shared: the ratio is what counts). And fine meshes:
//  - BM_FineTrueDistance: the true distances of a scene whose person and robot have 10,000
//    triangles each (data/paper_basic.json's first time step, its robot links replaced by one
//    finely triangulated box, each event's person by a fine ellipsoid close to it);
//  - BM_FineSetup/<mode>: building the voxel evaluator for that scene at 36×27×27, one thread,
//    center (0) and conservative (1) mode, no refinement.
// The fine cases compile against older versions of the library as well, to compare a build of
// this file there with this one.
#include <CGAL/squared_distance_3.h>
#include <benchmark/benchmark.h>

#include "../tests/core/fine_meshes.hpp"
#include "camplace/core/distance.hpp"
#include "camplace/core/internal/exact_kernel.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/voxel/evaluator.hpp"

namespace {

using namespace camplace;

const core::Scene& cell() {
  static const core::Scene scene =
      core::load_scene(std::string(CAMPLACE_SOURCE_DIR) + "/data/cell_ur.json");
  return scene;
}

void BM_TrueDistanceBranchAndBound(benchmark::State& state) {
  const core::Scene& scene = cell();
  for (auto _ : state) {
    for (const core::StateIndex& s : core::states(scene))
      benchmark::DoNotOptimize(core::true_squared_distance(scene, s));
  }
}

// Every pair of a critical triangle and a target triangle measured exactly (the targets and
// links of the cell are disjoint, so no containment test is needed for the minimum).
void BM_TrueDistanceAllPairs(benchmark::State& state) {
  using K = core::internal::Kernel;
  const core::Scene& scene = cell();
  auto tri = [](const core::TriangleMesh& m, const std::array<int, 3>& t) {
    return K::Triangle_3(core::internal::to_point(m.vertices[t[0]]),
                         core::internal::to_point(m.vertices[t[1]]),
                         core::internal::to_point(m.vertices[t[2]]));
  };
  for (auto _ : state) {
    for (const core::StateIndex& s : core::states(scene)) {
      const core::TimeStep& step = scene.time_steps[s.time_step];
      K::FT best = -1;
      for (const core::SceneObject& c : step.critical)
        for (const core::SceneObject& t : step.events[s.event].targets)
          for (const auto& x : c.mesh.triangles)
            for (const auto& y : t.mesh.triangles) {
              const K::FT d = CGAL::squared_distance(tri(c.mesh, x), tri(t.mesh, y));
              if (best < 0 || d < best) best = d;
            }
      benchmark::DoNotOptimize(best);
    }
  }
}

core::SceneObject object(const std::string& name, core::TriangleMesh mesh) {
  core::SceneObject o;
  o.name = o.entry = name;
  o.bounds = core::bounding_box(mesh);
  o.mesh = std::move(mesh);
  return o;
}

/// data/paper_basic.json's first time step with a 10,092-triangle robot (a box cut 29×29 on each
/// face, turned 20° about z) as its only dynamic and critical object, and a 10,000-triangle
/// person (ellipsoid 0.25 × 0.2 × 0.88 m, 100 meridians, 51 bands) in each of its 3 events, at
/// 0.05–0.3 m from the robot.
const core::Scene& fine_scene() {
  static const core::Scene scene = [] {
    core::Scene s = core::load_scene(std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic.json");
    s.time_steps.resize(1);
    core::TimeStep& step = s.time_steps[0];
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(20.0 * 3.14159265358979323846 / 180.0, core::Vec3::UnitZ())
            .toRotationMatrix();
    const core::TriangleMesh robot = testing::moved(
        testing::subdivided_box(core::Vec3(-0.25, -0.25, 0.0), core::Vec3(0.25, 0.25, 1.2), 29),
        turn, core::Vec3(2.85, 0.75, 0.0));
    step.dynamic_obstacles = {object("robot", robot)};
    step.critical = step.dynamic_obstacles;
    const core::Vec3 person_at[3] = {{2.3, 1.45, 0.9}, {2.45, 0.2, 0.9}, {3.55, 1.3, 0.9}};
    for (std::size_t l = 0; l < step.events.size() && l < 3; ++l) {
      step.events[l].targets = {
          object("person", testing::ellipsoid(person_at[l], core::Vec3(0.25, 0.2, 0.88), 100, 51))};
    }
    return s;
  }();
  return scene;
}

void BM_FineTrueDistance(benchmark::State& state) {
  const core::Scene& scene = fine_scene();
  for (auto _ : state) {
    for (const core::StateIndex& s : core::states(scene))
      benchmark::DoNotOptimize(core::true_squared_distance(scene, s));
  }
}

void BM_FineSetup(benchmark::State& state) {
  const core::Scene& scene = fine_scene();
  voxel::VoxelOptions options;
  options.mode = state.range(0) == 0 ? voxel::LabelMode::center : voxel::LabelMode::conservative;
  options.resolution = {36, 27, 27};
  options.threads = 1;
  for (auto _ : state) {
    voxel::VoxelEvaluator evaluator(scene, options);
    benchmark::DoNotOptimize(&evaluator);
  }
}

BENCHMARK(BM_FineTrueDistance)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_FineSetup)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_TrueDistanceBranchAndBound)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TrueDistanceAllPairs)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
