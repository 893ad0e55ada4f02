// The voxel pipeline on data/paper_basic.json with the corners configuration
// (data/paper_basic_corners.json), the measurements of the fast labeller:
//  - BM_Evaluate/<mode>/<r>/<threads>: one full evaluation (labelling, components, distances);
//  - BM_EvaluateRandom/<mode>/<r>: the same over the corners and seven random configurations
//    (seed 1), closer to what an optimizer asks;
//  - BM_Construct/<mode>/<r>: building the evaluator (obstacle interiors, critical distances,
//    conservative lower bound);
//  - BM_EvaluateRefine/corners/<L> and BM_EvaluateRefine/random/<L>: conservative mode at
//    16×12×12 with `refine` = L levels, the corners configuration / the corners
//    and the seven random ones in turn; the evaluator is built and warmed first (one evaluation
//    of each configuration), as an optimizer's is after its first evaluations (node distances
//    are cached lazily);
//  - BM_ConstructRefine/<L>: building that evaluator (octree obstacle tables, refined bound);
//  - BM_LegacyLabelling/<mode>/<r>: the labelling stage of the labeller the fast one replaced
//    (tests/support/legacy_labeller.cpp), same configuration;
//  - BM_ReferenceLabelling/<mode>/<r>: the brute-force reference labelling of that mode's model
//    (tests/support/reference.cpp: every voxel, state and camera, every triangle; center: the ray
//    through the voxel centre, conservative: each triangle's cone against the voxel box);
// with r = 0..3 for 16×12×12, 36×27×27, 64×48×48 and 128×96×96. At the end it prints the
// speed-ups of a full evaluation over the legacy labelling, over the brute-force reference of
// the same mode and, for conservative mode, over the center reference too (CPU time). Without
// --benchmark_filter it runs the short default set (r ≤ 1, single thread, and the construction at r
// ≤ 2); `--benchmark_filter=.` runs everything.
//   build/release/bench/evaluate_bench [--benchmark_filter=REGEX]
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>
#include <map>
#include <random>
#include <string>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "legacy_labeller.hpp"
#include "paper_basic.hpp"
#include "reference.hpp"
#include "scene_builder.hpp"

namespace {

using namespace camplace;

using bench::corners;
using bench::paper_scene;

// Eight configurations: the corners heuristic and seven random ones (seed 1).
const std::vector<core::CameraConfig>& configs() {
  static const std::vector<core::CameraConfig> list = [] {
    std::vector<core::CameraConfig> out{corners()};
    std::mt19937 rng(1);
    for (int i = 0; i < 7; ++i) out.push_back(testing::random_config(rng, paper_scene()));
    return out;
  }();
  return list;
}

constexpr std::array<std::array<int, 3>, 4> kResolutions{
    {{16, 12, 12}, {36, 27, 27}, {64, 48, 48}, {128, 96, 96}}};
const char* const kResolutionNames[] = {"16x12x12", "36x27x27", "64x48x48", "128x96x96"};

voxel::VoxelOptions options(voxel::LabelMode mode, std::int64_t r, std::int64_t threads = 1) {
  voxel::VoxelOptions o;
  o.mode = mode;
  o.resolution = kResolutions.at(static_cast<std::size_t>(r));
  o.threads = static_cast<int>(threads);
  return o;
}

void report_timing(benchmark::State& state, const voxel::Timing& sum, int voxels) {
  const double n = static_cast<double>(state.iterations());
  state.counters["labelling_ms"] = sum.labelling_ms / n;
  state.counters["clustering_ms"] = sum.clustering_ms / n;
  state.counters["distance_ms"] = sum.distance_ms / n;
  state.counters["voxels"] = voxels;
}

void BM_Evaluate(benchmark::State& state, voxel::LabelMode mode) {
  const voxel::VoxelEvaluator evaluator(paper_scene(),
                                        options(mode, state.range(0), state.range(1)));
  voxel::Timing sum;
  for (auto _ : state) {
    const auto e = evaluator.evaluate(corners());
    benchmark::DoNotOptimize(e.err);
    sum.labelling_ms += e.timing.labelling_ms;
    sum.clustering_ms += e.timing.clustering_ms;
    sum.distance_ms += e.timing.distance_ms;
  }
  report_timing(state, sum, evaluator.grid().count());
}

void BM_EvaluateRandom(benchmark::State& state, voxel::LabelMode mode) {
  const voxel::VoxelEvaluator evaluator(paper_scene(), options(mode, state.range(0)));
  std::size_t k = 0;
  voxel::Timing sum;
  for (auto _ : state) {
    const auto e = evaluator.evaluate(configs()[k++ % configs().size()]);
    benchmark::DoNotOptimize(e.err);
    sum.labelling_ms += e.timing.labelling_ms;
    sum.clustering_ms += e.timing.clustering_ms;
    sum.distance_ms += e.timing.distance_ms;
  }
  report_timing(state, sum, evaluator.grid().count());
}

void BM_Construct(benchmark::State& state, voxel::LabelMode mode) {
  for (auto _ : state) {
    const voxel::VoxelEvaluator evaluator(paper_scene(), options(mode, state.range(0)));
    benchmark::DoNotOptimize(evaluator.err_lower_bound());
  }
}

voxel::VoxelOptions refine_options(std::int64_t levels) {
  voxel::VoxelOptions o = options(voxel::LabelMode::conservative, 0);
  o.refine = static_cast<int>(levels);
  return o;
}

void BM_EvaluateRefine(benchmark::State& state, bool random) {
  const voxel::VoxelEvaluator evaluator(paper_scene(), refine_options(state.range(0)));
  for (const auto& config : configs()) benchmark::DoNotOptimize(evaluator.err(config));
  std::size_t k = 0;
  voxel::Timing sum;
  for (auto _ : state) {
    const auto e = evaluator.evaluate(random ? configs()[k++ % configs().size()] : corners());
    benchmark::DoNotOptimize(e.err);
    sum.labelling_ms += e.timing.labelling_ms;
    sum.clustering_ms += e.timing.clustering_ms;
    sum.distance_ms += e.timing.distance_ms;
  }
  report_timing(state, sum, evaluator.grid().count());
}

void BM_ConstructRefine(benchmark::State& state) {
  for (auto _ : state) {
    const voxel::VoxelEvaluator evaluator(paper_scene(), refine_options(state.range(0)));
    benchmark::DoNotOptimize(evaluator.err_lower_bound());
  }
}

void BM_LegacyLabelling(benchmark::State& state, voxel::LabelMode mode) {
  const testing::LegacyLabeller legacy(paper_scene(), options(mode, state.range(0)));
  for (auto _ : state) {
    const auto models = legacy.raw_models(corners());
    benchmark::DoNotOptimize(models.data());
  }
}

// The brute-force reference labelling of one mode (tests/support/reference.cpp): every voxel,
// state and camera (until one sees the voxel free), every triangle; then the model (free for
// some camera → out). Center mode: the ray through the voxel centre against every triangle;
// conservative mode: every triangle's cone against the voxel box (reference_box_label).
void BM_ReferenceLabelling(benchmark::State& state, voxel::LabelMode mode) {
  const core::Scene& scene = paper_scene();
  const voxel::VoxelEvaluator evaluator(scene, options(mode, state.range(0)));
  const auto all_states = core::states(scene);
  for (auto _ : state) {
    int in_model = 0;
    for (const auto& st : all_states) {
      for (int v = 0; v < evaluator.grid().count(); ++v) {
        bool free = false;
        for (const auto& camera : corners()) {
          const testing::ReferenceLabel label =
              mode == voxel::LabelMode::center
                  ? testing::reference_label(scene, st.time_step, st.event, camera,
                                             evaluator.grid().voxel_center(v))
                  : testing::reference_box_label(scene, st.time_step, st.event, camera,
                                                 evaluator.grid().voxel_box(v));
          free = label.label == voxel::Label::free;
          if (free) break;
        }
        in_model += !free;
      }
    }
    benchmark::DoNotOptimize(in_model);
  }
}

using voxel::LabelMode;
BENCHMARK_CAPTURE(BM_Evaluate, conservative, LabelMode::conservative)
    ->ArgsProduct({{0, 1, 2, 3}, {1, 2}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Evaluate, center, LabelMode::center)
    ->ArgsProduct({{0, 1, 2, 3}, {1, 2}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EvaluateRandom, conservative, LabelMode::conservative)
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EvaluateRandom, center, LabelMode::center)
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Construct, conservative, LabelMode::conservative)
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Construct, center, LabelMode::center)
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EvaluateRefine, corners, false)
    ->DenseRange(0, 4)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EvaluateRefine, random, true)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ConstructRefine)->DenseRange(1, 4)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_LegacyLabelling, conservative, LabelMode::conservative)
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_LegacyLabelling, center, LabelMode::center)
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ReferenceLabelling, conservative, LabelMode::conservative)
    ->DenseRange(0, 1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ReferenceLabelling, center, LabelMode::center)
    ->DenseRange(0, 1)
    ->Unit(benchmark::kMillisecond);

// Remembers each run's CPU time per iteration (the median of repetitions) so main can print
// the ratios.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      // With --benchmark_repetitions, the median stands for the run.
      if (r.run_type == Run::RT_Aggregate && r.aggregate_name != "median") continue;
      const std::string name =
          r.run_type == Run::RT_Aggregate ? r.run_name.str() : r.benchmark_name();
      times_[name] = r.GetAdjustedCPUTime();
    }
    ConsoleReporter::ReportRuns(runs);
  }
  std::map<std::string, double> times_;
};

// The default set: everything at r ≤ 1 single-threaded, the construction up to r = 2.
constexpr const char* kDefaultFilter =
    "^(BM_Evaluate/[a-z]+/[01]/1|BM_(LegacyLabelling|EvaluateRandom)/[a-z]+/[01]|"
    "BM_ReferenceLabelling/[a-z]+/[01]|BM_Construct/[a-z]+/[012])$";

}  // namespace

int main(int argc, char** argv) {
  std::vector<char*> args(argv, argv + argc);
  bool filtered = false;
  for (int i = 1; i < argc; ++i) filtered = filtered || std::strstr(argv[i], "--benchmark_filter");
  std::string filter = std::string("--benchmark_filter=") + kDefaultFilter;
  if (!filtered) args.push_back(filter.data());
  int count = static_cast<int>(args.size());
  benchmark::Initialize(&count, args.data());
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  auto& t = reporter.times_;
  for (int r = 0; r < 4; ++r) {
    for (const char* mode : {"conservative", "center"}) {
      const std::string fast = "BM_Evaluate/" + std::string(mode) + "/" + std::to_string(r) + "/1";
      if (!t.count(fast)) continue;
      const std::string legacy =
          "BM_LegacyLabelling/" + std::string(mode) + "/" + std::to_string(r);
      const std::string ref =
          "BM_ReferenceLabelling/" + std::string(mode) + "/" + std::to_string(r);
      const std::string center_ref = "BM_ReferenceLabelling/center/" + std::to_string(r);
      std::printf("%s, %s: a full evaluation (%.3f ms CPU)", kResolutionNames[r], mode, t[fast]);
      const char* joint = " is";
      if (t.count(legacy)) {
        std::printf("%s %.1fx faster than the legacy labelling alone", joint, t[legacy] / t[fast]);
        joint = ",";
      }
      if (t.count(ref)) {
        std::printf("%s %.1fx faster than the brute-force %s reference labelling", joint,
                    t[ref] / t[fast], mode);
        joint = ",";
      }
      if (ref != center_ref && t.count(center_ref)) {
        std::printf("%s %.1fx faster than the brute-force center reference labelling", joint,
                    t[center_ref] / t[fast]);
      }
      std::printf("\n");
    }
  }
  benchmark::Shutdown();
  return 0;
}
