#pragma once
/// Memory the voxel pipeline needs, estimated before any work starts, against what the machine
/// has available: a command refuses work that would not fit instead of ending in
/// std::bad_alloc after minutes.
#include <array>
#include <cstddef>
#include <optional>
#include <string>

#include "camplace/core/scene.hpp"

namespace camplace::app {

/// What sizes the voxel pipeline's memory.
struct VoxelWork {
  std::array<int, 3> n{0, 0, 0};  ///< voxels per axis
  int cameras = 0;
  int time_steps = 0;
  int states = 0;
  long triangles = 0;        ///< all objects' triangles (per-camera set-up)
  int refine = 0;            ///< voxel::VoxelOptions::refine
  int threads = 1;           ///< evaluations or states at a time, each with its own scratch
  bool diagnostics = false;  ///< evaluate's per-camera labels (compare::evaluate_json)
};

/// The work of `scene` at resolution `n` (all 0: the scene's).
VoxelWork voxel_work(const core::Scene& scene, std::array<int, 3> n, int refine, int threads,
                     bool diagnostics);

/// Bytes the voxel pipeline holds at most for `work` (voxel/src/impl.hpp, setup.cpp), with
/// V = n[0]·n[1]·n[2] voxels, T time steps, S states, C cameras, K threads:
/// set-up V·T·17 (per step an obstacle-interior byte and two doubles of critical distances),
/// models V·S (a byte per voxel and state), components K·V·16 (runs, labels, union–find per
/// thread), camera set-up C·K·triangles·320 (projected triangles, bins), diagnostics V·(C + 6)
/// (one label byte per camera, model, component label), and refinement
/// voxel::refine_memory_estimate().
double voxel_memory_bytes(const VoxelWork& work);

/// Bytes the system reports available (MemAvailable of /proc/meminfo), or, for tests, the
/// kB in the environment variable CAMPLACE_MEM_AVAILABLE_KB; none when unknown.
std::optional<double> available_memory_bytes();

/// Throws std::runtime_error "--resolution 512x512x128 with 256 cameras needs about N GiB,
/// more than the M GiB available" when voxel_memory_bytes(work) exceeds what is available.
/// `option`: the option that sized the grid ("--resolution", or "the scene's voxels" when none
/// was given).
void check_memory(const VoxelWork& work, const std::string& option);

/// What sizes the exact pipeline's memory (exact::evaluate_exact).
struct ExactWork {
  int cameras = 0;
  int threads = 1;           ///< threads, each with its own caches (workers and helpers)
  long state_triangles = 0;  ///< the most triangles of one state (static, dynamic, targets)
  long pose_triangles = 0;   ///< the triangles of the distinct target meshes (cached cones)
};

/// The exact work of `scene` with `threads` threads (0: one per core). All of them count: the
/// threads beyond one per task (fewer states than threads) help build camera parts ahead, each in
/// a pipeline of its own.
ExactWork exact_work(const core::Scene& scene, int threads);

/// Bytes the exact pipeline holds at most for `work`, fitted to the peak resident memory of
/// `evaluate --pipeline exact` on two cells (docs/development.md, "Memory of the exact
/// pipeline"): 96 MiB + K·C·3.8 MiB·T^0.38, K threads, C cameras, T = state_triangles +
/// pose_triangles: each thread keeps per camera one step's free region and the targets' cones
/// per pose, whose size grows with the triangles the cameras see, more slowly than linearly.
double exact_memory_bytes(const ExactWork& work);

/// Throws std::runtime_error "the exact pipeline with 6 cameras, 2 threads and up to 7,138
/// triangles per state needs about N GiB, more than the M GiB available; ..." when
/// exact_memory_bytes(work) exceeds what is available.
void check_exact_memory(const ExactWork& work);

}  // namespace camplace::app
