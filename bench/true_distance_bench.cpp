// The exact true distance d(C, O_u) of every state of the bundled UR5e cell: camplace's branch
// and bound (core::true_squared_distance) against measuring every triangle pair exactly, the
// method it replaced, side by side in one run (the machine is shared: the ratio is what counts).
#include <CGAL/squared_distance_3.h>
#include <benchmark/benchmark.h>

#include "camplace/core/distance.hpp"
#include "camplace/core/internal/exact_kernel.hpp"
#include "camplace/core/scene.hpp"

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

BENCHMARK(BM_TrueDistanceBranchAndBound)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TrueDistanceAllPairs)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
