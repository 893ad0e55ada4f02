// The exact pipeline (SPEC §6) on data/paper_basic.json with the corner cameras
// (data/paper_basic_corners.json): one state's model and the whole configuration (six states)
// with one thread and with one thread per core; then two families, each run with the silhouette
// cones from image-plane outlines (the default, `outline`) and as the union of per-face cones
// (ExactOptions::face_cones, `faces`), one thread:
//   triangles  the person of every event replaced by one ellipsoid of N triangles in its bounding
//              box (tests/support ellipsoid_mesh), N = 48, 200, 800, 3200; 1 state and 6 states
//   cameras    paper_basic with 3, 6 and 12 cameras (the corners, then 6 more at mid height), 1
//              state
//   cell       (outlines only) paper_basic's 6 states with each robot one ellipsoid of 5,000
//              triangles and each person one of 2,000; with the targets' cones shared between
//              states of the same pose (ExactOptions::reuse_poses, the default) and without
//              (`outline-each-state`), and with the obstacles subtracted first, the former order
//              (`outline-obstacles-first`, ExactOptions::obstacles_last off)
//   occluding  the cell in modelled mode (the robot occludes: a shadow per camera and time step)
//              with each robot one dented ellipsoid of N triangles (non-convex: not one hull) and
//              each person one ellipsoid of 2,000; the shadows from patches of front faces found
//              in the image plane (the default, `patches`) and as the union of per-face shadows
//              (ExactOptions::face_shadows, `faces`), N = 800, 5000 (`faces` up to 800 by default;
//              CAMPLACE_BENCH_FACE_SHADOWS_MAX=N raises it)
// The families run with one thread, or CAMPLACE_BENCH_THREADS=N threads (with one state, the
// threads beyond the first build camera parts ahead: ExactOptions::threads).
// One iteration each (a full evaluation takes seconds to minutes); prints the figures, the
// growth exponents (least-squares slope of log CPU time against log N over the family, and the
// slope between neighbouring N) and the peak memory.
//   build/release/bench/exact_bench
//   build/release/bench/exact_bench --benchmark_filter='outline'   (the new construction only)
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/exact/evaluator.hpp"
#include "paper_basic.hpp"
#include "scene_builder.hpp"

namespace {

/// The whole number ≥ 1 in environment variable `name`, or `fallback` when it is not set; exits
/// with a message naming the variable when it is set to anything else.
int env_count(const char* name, int fallback) {
  const char* text = std::getenv(name);
  if (text == nullptr) return fallback;
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || value < 1 || value > 1000000) {
    std::fprintf(stderr, "exact_bench: %s=\"%s\": expected a whole number from 1 to 1000000\n",
                 name, text);
    std::exit(2);
  }
  return int(value);
}

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

// paper_basic with each event's person one ellipsoid of `triangles` triangles; `states` 1 (the
// first time step's first event) or all 6.
core::Scene fine_person_scene(int triangles, int states) {
  core::Scene scene = paper_scene();
  for (auto& step : scene.time_steps) {
    for (auto& event : step.events) {
      core::Box3 box = event.targets.front().bounds;
      for (const auto& t : event.targets) {
        box.min = box.min.cwiseMin(t.bounds.min);
        box.max = box.max.cwiseMax(t.bounds.max);
      }
      event.targets = {testing::ellipsoid_object("person", box, triangles)};
    }
  }
  if (states == 1) {
    scene.time_steps.resize(1);
    scene.time_steps[0].events.resize(1);
  }
  return scene;
}

// paper_basic with each time step's robot one ellipsoid of `robot` triangles in the bounding box
// of its links and each event's person one of `person` triangles (masked mode: both occupy).
core::Scene fine_cell_scene(int robot, int person) {
  core::Scene scene = fine_person_scene(person, 6);
  for (auto& step : scene.time_steps) {
    core::Box3 box = step.dynamic_obstacles.front().bounds;
    for (const auto& o : step.dynamic_obstacles) {
      box.min = box.min.cwiseMin(o.bounds.min);
      box.max = box.max.cwiseMax(o.bounds.max);
    }
    step.dynamic_obstacles = {testing::ellipsoid_object("robot", box, robot)};
    step.critical = step.dynamic_obstacles;
  }
  return scene;
}

// A closed mesh of `triangles` triangles in `box`: its ellipsoid with each vertex moved along its
// ray from the centre by four fixed dents and bumps (star-shaped, so still a closed outward mesh
// without self-intersections; non-convex).
core::TriangleMesh dented_mesh(const core::Box3& box, int triangles) {
  core::TriangleMesh m = testing::ellipsoid_mesh(box, triangles);
  const core::Vec3 center = 0.5 * (box.min + box.max);
  const std::pair<core::Vec3, double> bumps[] = {{core::Vec3(1, 0, 0), -0.35},
                                                 {core::Vec3(0, 1, 0.5).normalized(), -0.3},
                                                 {core::Vec3(-1, -1, 0).normalized(), 0.2},
                                                 {core::Vec3(0, 0, 1), -0.25}};
  for (core::Vec3& v : m.vertices) {
    const core::Vec3 r = v - center;
    double f = 1.0;
    for (const auto& [dir, amplitude] : bumps)
      f += amplitude * std::exp(-(r.normalized() - dir).squaredNorm() / 0.3);
    v = center + f * r;
  }
  return m;
}

// fine_cell_scene in modelled mode with each robot one dented ellipsoid (dented_mesh) of `robot`
// triangles: the robot occludes.
core::Scene occluding_cell_scene(int robot, int person) {
  core::Scene scene = fine_cell_scene(robot, person);
  scene.dynamic_mode = core::DynamicMode::modelled;
  for (auto& step : scene.time_steps) {
    for (auto& o : step.dynamic_obstacles)
      o = testing::mesh_object(o.name, dented_mesh(o.bounds, robot));
    step.critical = step.dynamic_obstacles;
  }
  return scene;
}

// paper_basic, time step 0 event 0, with `cameras` cameras: the first of the corner
// configuration, then copies of the corners at z = 2 m turned by 20° and looking 15° down.
std::pair<core::Scene, core::CameraConfig> camera_scene(int cameras) {
  core::Scene scene = paper_scene();
  scene.time_steps.resize(1);
  scene.time_steps[0].events.resize(1);
  core::CameraConfig config;
  for (int i = 0; i < cameras; ++i) {
    core::CameraSetting s = corners()[i % corners().size()];
    if (i >= int(corners().size())) {
      s.position.z() = 2.0;
      s.yaw += 20.0 * core::kDegree;
      s.pitch = -15.0 * core::kDegree;
    }
    config.push_back(s);
  }
  scene.cameras.resize(cameras);
  return {scene, config};
}

void run(benchmark::State& state, const core::Scene& scene, const core::CameraConfig& config,
         bool face_cones, bool reuse_poses = true, bool obstacles_last = true,
         bool face_shadows = false) {
  exact::ExactOptions options;
  // CAMPLACE_BENCH_THREADS=N: N threads (default 1); one state then has N - 1 helpers.
  options.threads = env_count("CAMPLACE_BENCH_THREADS", 1);
  options.face_cones = face_cones;
  options.face_shadows = face_shadows;
  options.reuse_poses = reuse_poses;
  options.obstacles_last = obstacles_last;
  for (auto _ : state) {
    const exact::ExactEvaluation e = exact::evaluate_exact(scene, config, options);
    benchmark::DoNotOptimize(e.err);
    state.counters["err_m2"] = e.err;
    state.counters["labelling_ms"] = e.timing.labelling_ms;
    state.counters["clustering_ms"] = e.timing.clustering_ms;
    state.counters["distance_ms"] = e.timing.distance_ms;
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  state.counters["peak_rss_mb"] = double(usage.ru_maxrss) / 1024.0;  // of the process so far
}

// Registered by hand so that the names carry the construction; the per-face construction only
// up to 800 triangles for 6 states (≈ 8 min at 3,200).
void register_families() {
  for (const bool faces : {false, true}) {
    const char* method = faces ? "faces" : "outline";
    for (const int states : {1, 6}) {
      for (const int n : {48, 200, 800, 3200}) {
        if (faces && states == 6 && n > 800) continue;
        benchmark::RegisterBenchmark(("triangles/" + std::string(method) + "/states:" +
                                      std::to_string(states) + "/n:" + std::to_string(n))
                                         .c_str(),
                                     [=](benchmark::State& state) {
                                       run(state, fine_person_scene(n, states), corners(), faces);
                                     })
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond)
            ->MeasureProcessCPUTime()
            ->UseRealTime();
      }
    }
    if (!faces) {
      // With the targets' cones shared between the states of the same pose (the default; the
      // people stand at the same places in both time steps) and built for every state; with the
      // obstacles subtracted last (the default) and first.
      for (const char* variant : {"outline", "outline-each-state", "outline-obstacles-first"}) {
        const std::string name = variant;
        benchmark::RegisterBenchmark(("cell/" + name + "/robot:5000/person:2000/states:6").c_str(),
                                     [name](benchmark::State& state) {
                                       run(state, fine_cell_scene(5000, 2000), corners(), false,
                                           name != "outline-each-state",
                                           name != "outline-obstacles-first");
                                     })
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond)
            ->MeasureProcessCPUTime()
            ->UseRealTime();
      }
    }
    {
      // The robot occluding (modelled mode), its shadows from patches or per face.
      const char* shadows = faces ? "faces" : "patches";
      const int faces_max = env_count("CAMPLACE_BENCH_FACE_SHADOWS_MAX", 800);
      for (const int n : {800, 5000}) {
        if (faces && n > faces_max) continue;
        benchmark::RegisterBenchmark(
            ("occluding/" + std::string(shadows) + "/person:2000/states:6/n:" + std::to_string(n))
                .c_str(),
            [=](benchmark::State& state) {
              run(state, occluding_cell_scene(n, 2000), corners(), false, true, true, faces);
            })
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond)
            ->MeasureProcessCPUTime()
            ->UseRealTime();
      }
    }
    for (const int n : {3, 6, 12}) {
      benchmark::RegisterBenchmark(
          ("cameras/" + std::string(method) + "/n:" + std::to_string(n)).c_str(),
          [=](benchmark::State& state) {
            const auto [scene, config] = camera_scene(n);
            run(state, scene, config, faces);
          })
          ->Iterations(1)
          ->Unit(benchmark::kMillisecond)
          ->MeasureProcessCPUTime()
          ->UseRealTime();
    }
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

// Least-squares slope of log(CPU time) against log(n) over the runs named prefix + n.
void print_exponents(const FigureReporter& reporter, const std::string& family) {
  std::map<std::string, std::vector<std::pair<double, double>>> series;  // prefix → (n, CPU ms)
  for (const auto& [name, t] : reporter.times_) {
    if (name.rfind(family + "/", 0) != 0) continue;
    const auto at = name.find("/n:");
    if (at == std::string::npos) continue;
    series[name.substr(0, at)].push_back({std::stod(name.substr(at + 3)), t.second});
  }
  for (auto& [prefix, points] : series) {
    if (points.size() < 2) continue;
    std::sort(points.begin(), points.end());
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (const auto& [n, ms] : points) {
      const double x = std::log(n), y = std::log(ms);
      sx += x;
      sy += y;
      sxx += x * x;
      sxy += x * y;
    }
    const double k = double(points.size());
    std::printf("  %-40s exponent %.2f over n = %g..%g;", prefix.c_str(),
                (k * sxy - sx * sy) / (k * sxx - sx * sx), points.front().first,
                points.back().first);
    // Between neighbours too: a term cheaper than the others (in the cameras family the first
    // camera's free region, subtracted from S's box) weighs most at the smallest n and steepens
    // the fit over the whole range.
    for (std::size_t i = 1; i < points.size(); ++i)
      std::printf(" %g→%g: %.2f", points[i - 1].first, points[i].first,
                  std::log(points[i].second / points[i - 1].second) /
                      std::log(points[i].first / points[i - 1].first));
    std::printf("\n");
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_families();
  benchmark::Initialize(&argc, argv);
  FigureReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  std::printf("\nexact pipeline, paper_basic, corner cameras (wall ms, CPU ms of all threads):\n");
  for (const auto& [name, t] : reporter.times_)
    std::printf("  %-40s %9.0f %9.0f\n", name.c_str(), t.first, t.second);
  std::printf("growth of the CPU time:\n");
  print_exponents(reporter, "triangles");
  print_exponents(reporter, "cameras");
  print_exponents(reporter, "occluding");
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("peak resident memory of the whole run: %.0f MB\n", double(usage.ru_maxrss) / 1024.0);
  benchmark::Shutdown();
  return 0;
}
