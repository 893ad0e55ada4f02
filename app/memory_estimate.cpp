#include "memory_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <unordered_set>

#include "camplace/core/table_text.hpp"
#include "camplace/voxel/evaluator.hpp"

namespace camplace::app {

VoxelWork voxel_work(const core::Scene& scene, std::array<int, 3> n, int refine, int threads,
                     bool diagnostics) {
  VoxelWork w;
  w.n = n == std::array<int, 3>{0, 0, 0} ? scene.voxels : n;
  w.cameras = static_cast<int>(scene.cameras.domains.size());
  w.time_steps = static_cast<int>(scene.time_steps.size());
  auto count = [&w](const std::vector<core::SceneObject>& objects) {
    for (const auto& o : objects) w.triangles += static_cast<long>(o.mesh.triangles.size());
  };
  count(scene.static_obstacles);
  for (const auto& step : scene.time_steps) {
    w.states += static_cast<int>(step.events.size());
    count(step.dynamic_obstacles);  // the critical objects are (by default) these
    for (const auto& event : step.events) count(event.targets);
  }
  w.refine = refine;
  w.threads = std::max(threads, 1);
  w.diagnostics = diagnostics;
  return w;
}

double voxel_memory_bytes(const VoxelWork& w) {
  const double v = static_cast<double>(w.n[0]) * w.n[1] * w.n[2];
  double bytes =
      v * w.time_steps * 17.0 + v * w.states + w.threads * v * 16.0 +
      static_cast<double>(w.cameras) * w.threads * static_cast<double>(w.triangles) * 320.0;
  if (w.diagnostics) bytes += v * (w.cameras + 6.0);
  bytes += voxel::refine_memory_estimate(w.n, w.refine, w.time_steps, w.states);
  return bytes;
}

std::optional<double> available_memory_bytes() {
  if (const char* fake = std::getenv("CAMPLACE_MEM_AVAILABLE_KB")) {
    char* end = nullptr;
    const double kb = std::strtod(fake, &end);
    if (end != fake && kb >= 0) return kb * 1024.0;
  }
  std::ifstream in("/proc/meminfo");
  std::string key;
  double kb = 0;
  std::string unit;
  while (in >> key >> kb >> unit) {
    if (key == "MemAvailable:") return kb * 1024.0;
  }
  return std::nullopt;
}

namespace {

/// `bytes` as "1.25 GiB", in GiB when it or `other` (the figure printed beside it) reaches
/// 0.1 GiB, else in MiB (a test's tiny fake MemAvailable).
std::string size_text(double bytes, double other) {
  const bool gib = std::max(bytes, other) >= 0.1 * 1024 * 1024 * 1024;
  char text[64];
  std::snprintf(text, sizeof text, "%.2f %s", bytes / (gib ? 1024.0 * 1024 * 1024 : 1024.0 * 1024),
                gib ? "GiB" : "MiB");
  return text;
}

}  // namespace

void check_memory(const VoxelWork& work, const std::string& option) {
  const std::optional<double> available = available_memory_bytes();
  const double need = voxel_memory_bytes(work);
  if (!available || need <= *available) return;
  const std::string refine =
      work.refine > 0 ? " and --refine " + std::to_string(work.refine) : std::string();
  throw std::runtime_error(option + " " + std::to_string(work.n[0]) + "x" +
                           std::to_string(work.n[1]) + "x" + std::to_string(work.n[2]) + " with " +
                           std::to_string(work.cameras) + " cameras" + refine + " needs about " +
                           size_text(need, *available) + ", more than the " +
                           size_text(*available, need) + " available; use a coarser grid" +
                           (work.refine > 0 ? " or fewer levels" : ""));
}

namespace {

long triangles_of(const std::vector<core::SceneObject>& objects) {
  long n = 0;
  for (const auto& o : objects) n += static_cast<long>(o.mesh.triangles.size());
  return n;
}

/// A hash of a mesh's vertices and triangles (equal meshes, equal hashes).
std::size_t mesh_hash(const core::TriangleMesh& mesh) {
  std::size_t h = mesh.vertices.size() * 1000003u + mesh.triangles.size();
  auto mix = [&h](double x) { h = (h ^ std::hash<double>{}(x)) * 1099511628211ull; };
  for (const auto& v : mesh.vertices) {
    mix(v.x());
    mix(v.y());
    mix(v.z());
  }
  for (const auto& t : mesh.triangles)
    for (int i : t) mix(i);
  return h;
}

}  // namespace

ExactWork exact_work(const core::Scene& scene, int threads) {
  ExactWork w;
  w.cameras = static_cast<int>(scene.cameras.domains.size());
  const int cores = static_cast<int>(std::max(std::thread::hardware_concurrency(), 1u));
  // Every thread counts: a worker per task, and the threads left over help build camera parts
  // ahead, each in a pipeline of its own.
  w.threads = std::max(1, threads > 0 ? threads : cores);
  const long statics = triangles_of(scene.static_obstacles);
  std::unordered_set<std::size_t> poses;
  for (const auto& step : scene.time_steps) {
    const long step_triangles = statics + triangles_of(step.dynamic_obstacles);
    for (const auto& event : step.events) {
      w.state_triangles = std::max(w.state_triangles, step_triangles + triangles_of(event.targets));
      for (const auto& t : event.targets) {
        if (poses.insert(mesh_hash(t.mesh)).second) {
          w.pose_triangles += static_cast<long>(t.mesh.triangles.size());
        }
      }
    }
  }
  return w;
}

double exact_memory_bytes(const ExactWork& w) {
  // Fitted to two cells (docs/development.md, "Memory of the exact pipeline").
  constexpr double kMiB = 1024.0 * 1024.0, kBase = 96.0 * kMiB, kA = 3.8 * kMiB, kP = 0.38;
  const double t = static_cast<double>(w.state_triangles + w.pose_triangles);
  return kBase + static_cast<double>(w.threads) * w.cameras * kA * std::pow(std::max(t, 1.0), kP);
}

void check_exact_memory(const ExactWork& work) {
  const std::optional<double> available = available_memory_bytes();
  const double need = exact_memory_bytes(work);
  if (!available || need <= *available) return;
  throw std::runtime_error(
      "the exact pipeline with " + std::to_string(work.cameras) + " cameras, " +
      std::to_string(work.threads) + (work.threads == 1 ? " thread" : " threads") + " and up to " +
      core::thousands(work.state_triangles) + " triangles per state needs about " +
      size_text(need, *available) + ", more than the " + size_text(*available, need) +
      " available; use fewer threads (--threads) or coarser meshes");
}

}  // namespace camplace::app
