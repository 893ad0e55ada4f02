// The exact pipeline (SPEC §6) on data/paper_basic.json with the corner cameras
// (data/paper_basic_corners.json): one state's model, and the whole configuration (six states)
// with one thread and with one thread per core. One iteration each (a full evaluation takes
// seconds); prints the figures at the end.
//   build/release/bench/exact_bench
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>
#include <thread>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/exact/evaluator.hpp"
#include "paper_basic.hpp"

namespace {

using namespace camplace;

using bench::corners;
using bench::paper_scene;

// The model of one state (time step 0, event 0), FOVs and per-camera caches included.
void BM_ExactState(benchmark::State& state) {
  for (auto _ : state) {
    const exact::ExactModel model = exact::build_exact_model(paper_scene(), corners(), {0, 0});
    benchmark::DoNotOptimize(model.volume());
    state.counters["volume_m3"] = model.volume();
    state.counters["components"] = model.components();
  }
}

// Every state of the configuration: Err and the split of the time (summed over the states).
void BM_ExactConfiguration(benchmark::State& state) {
  exact::ExactOptions options;
  options.threads = static_cast<int>(state.range(0));
  for (auto _ : state) {
    const exact::ExactEvaluation e = exact::evaluate_exact(paper_scene(), corners(), options);
    benchmark::DoNotOptimize(e.err);
    state.counters["err_m2"] = e.err;
    state.counters["labelling_ms"] = e.timing.labelling_ms;
    state.counters["clustering_ms"] = e.timing.clustering_ms;
    state.counters["distance_ms"] = e.timing.distance_ms;
  }
}

BENCHMARK(BM_ExactState)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_ExactConfiguration)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())))
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// Remembers each run's wall and CPU time so main can print the figures.
class FigureReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs)
      times_[r.benchmark_name()] = {r.GetAdjustedRealTime(), r.GetAdjustedCPUTime()};
    ConsoleReporter::ReportRuns(runs);
  }
  std::map<std::string, std::pair<double, double>> times_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  FigureReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  std::printf("\nexact pipeline, paper_basic, corner cameras (wall ms, CPU ms of all threads):\n");
  for (const auto& [name, t] : reporter.times_)
    std::printf("  %-40s %9.0f %9.0f\n", name.c_str(), t.first, t.second);
  benchmark::Shutdown();
  return 0;
}
