// One full voxel evaluation of data/paper_basic.json (conservative and center) at 16×12×12 and
// 36×27×27, and the brute-force reference labeller (tests/support/reference.cpp) on the same
// configurations in the same run; prints the speed-up over the reference at the end.
//   build/release/bench/evaluate_bench
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <random>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "reference.hpp"
#include "scene_builder.hpp"

namespace {

using namespace camplace;

const core::Scene& paper_scene() {
  static const core::Scene scene = core::load_scene(std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic.json");
  return scene;
}

// Eight configurations: the corners heuristic and seven random ones (seed 1).
const std::vector<core::CameraConfig>& configs() {
  static const std::vector<core::CameraConfig> list = [] {
    std::vector<core::CameraConfig> out;
    out.push_back(core::load_camera_config(std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic_corners.json",
                                           paper_scene()));
    std::mt19937 rng(1);
    for (int i = 0; i < 7; ++i) out.push_back(testing::random_config(rng, paper_scene()));
    return out;
  }();
  return list;
}

std::array<int, 3> resolution(int i) { return {16 + 4 * i, 12 + 3 * i, 12 + 3 * i}; }

void BM_Evaluate(benchmark::State& state, voxel::LabelMode mode) {
  const voxel::VoxelEvaluator evaluator(paper_scene(), {mode, resolution(static_cast<int>(state.range(0)))});
  std::size_t k = 0;
  voxel::Timing sum;
  for (auto _ : state) {
    const auto e = evaluator.evaluate(configs()[k++ % configs().size()]);
    benchmark::DoNotOptimize(e.err);
    sum.labelling_ms += e.timing.labelling_ms;
    sum.clustering_ms += e.timing.clustering_ms;
  }
  state.counters["labelling_ms"] = sum.labelling_ms / state.iterations();
  state.counters["clustering_ms"] = sum.clustering_ms / state.iterations();
  state.counters["voxels"] = evaluator.grid().count();
}

// The brute-force reference: every voxel centre, camera and state, ray against every triangle;
// then the model as in center mode (free for some camera → out). Labelling only.
void BM_ReferenceLabelling(benchmark::State& state) {
  const core::Scene& scene = paper_scene();
  const voxel::VoxelEvaluator evaluator(scene, {voxel::LabelMode::center, resolution(static_cast<int>(state.range(0)))});
  const auto all_states = core::states(scene);
  std::size_t k = 0;
  for (auto _ : state) {
    const auto& config = configs()[k++ % configs().size()];
    int in_model = 0;
    for (const auto& st : all_states) {
      for (int v = 0; v < evaluator.grid().count(); ++v) {
        bool free = false;
        for (const auto& camera : config) {
          free = testing::reference_label(scene, st.time_step, st.event, camera,
                                          evaluator.grid().voxel_center(v)).label == voxel::Label::free;
          if (free) break;
        }
        in_model += !free;
      }
    }
    benchmark::DoNotOptimize(in_model);
  }
}

BENCHMARK_CAPTURE(BM_Evaluate, conservative, voxel::LabelMode::conservative)->Arg(0)->Arg(5)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Evaluate, center, voxel::LabelMode::center)->Arg(0)->Arg(5)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReferenceLabelling)->Arg(0)->Arg(5)->Unit(benchmark::kMillisecond);

// Remembers each run's real time per iteration so main can print the ratios.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) times_[r.benchmark_name()] = r.GetAdjustedRealTime();
    ConsoleReporter::ReportRuns(runs);
  }
  std::map<std::string, double> times_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  for (const char* arg : {"0", "5"}) {
    const std::string ref = std::string("BM_ReferenceLabelling/") + arg;
    if (!reporter.times_.count(ref)) continue;
    for (const char* mode : {"conservative", "center"}) {
      const std::string name = std::string("BM_Evaluate/") + mode + "/" + arg;
      if (!reporter.times_.count(name)) continue;
      std::printf("resolution %s, %s: full evaluation is %.1fx faster than the reference labelling\n",
                  arg[0] == '0' ? "16x12x12" : "36x27x27", mode,
                  reporter.times_[ref] / reporter.times_[name]);
    }
  }
  benchmark::Shutdown();
  return 0;
}
