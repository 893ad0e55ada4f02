// The voxel pipeline (SPEC §3–5): the public evaluator. Its stages live in setup.cpp,
// labelling.cpp, components.cpp and distance.cpp around the private Impl (impl.hpp).
#include "camplace/voxel/evaluator.hpp"

#include <string>

#include "camplace/core/err.hpp"
#include "camplace/core/error.hpp"
#include "camplace/voxel/components.hpp"
#include "impl.hpp"

namespace camplace::voxel {

using detail::Clock;
using detail::ms_since;

VoxelEvaluator::VoxelEvaluator(const core::Scene& scene, const VoxelOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.scene = scene;
  m.options = options;
  std::array<int, 3> n = options.resolution;
  if (n[0] == 0 && n[1] == 0 && n[2] == 0) n = scene.voxels;
  const std::string problem = core::resolution_problem(n);
  if (!problem.empty()) throw core::InputError(scene.file, "resolution", problem);
  if (options.threads < 1 || options.threads > kMaxThreads) {
    throw core::InputError(
        scene.file, "threads",
        "must be 1.." + std::to_string(kMaxThreads) + ", got " + std::to_string(options.threads));
  }
  m.options.resolution = n;
  m.conservative = options.mode == LabelMode::conservative;
  m.grid = make_grid(scene.area, n);
  m.half_step = 0.5 * m.grid.step;
  m.voxel_radius = m.half_step.norm();
  m.voxel_volume = m.grid.voxel_volume();
  m.build();
}

VoxelEvaluator::~VoxelEvaluator() = default;
VoxelEvaluator::VoxelEvaluator(VoxelEvaluator&&) noexcept = default;
VoxelEvaluator& VoxelEvaluator::operator=(VoxelEvaluator&&) noexcept = default;

Evaluation VoxelEvaluator::evaluate(const core::CameraConfig& config) const {
  const Impl& m = *impl_;
  const auto start = Clock::now();
  const int state_count = static_cast<int>(m.states.size());
  Evaluation result;
  auto t0 = Clock::now();
  // Per calling thread, reused: the optimizer evaluates thousands of configurations per
  // thread. (A reference, so that the worker threads below see this thread's buffers.)
  thread_local std::vector<std::vector<std::uint8_t>> buffers;
  std::vector<std::vector<std::uint8_t>>& models = buffers;
  m.all_raw_models(config, models);
  result.timing.labelling_ms = ms_since(t0);
  std::vector<ComponentCount> filtered(state_count);
  t0 = Clock::now();
  detail::parallel_for(state_count, m.options.threads, [&](int s) {
    filtered[s] = filter_components(models[s], m.grid, m.scene.plausibility);
  });
  result.timing.clustering_ms = ms_since(t0);
  t0 = Clock::now();
  std::vector<Impl::ModelDistance> distances(state_count);
  detail::parallel_for(state_count, m.options.threads, [&](int s) {
    distances[s] = m.model_distance(models[s], m.states[s].time_step);
  });
  for (int s = 0; s < state_count; ++s) {
    const detail::StateInfo& state = m.states[s];
    StateResult out;
    out.time_step = state.time_step;
    out.event = state.event;
    out.weight = state.weight;
    out.d_true = state.d_true;
    out.d_model = distances[s].d_model;
    out.model_volume = distances[s].volume;
    out.components = filtered[s].kept;
    out.components_removed = filtered[s].removed;
    result.states.push_back(out);
  }
  result.timing.distance_ms = ms_since(t0);
  result.err = core::error_of(result.states);
  result.timing.total_ms = ms_since(start);
  return result;
}

double VoxelEvaluator::err(const core::CameraConfig& config) const { return evaluate(config).err; }

std::vector<Label> VoxelEvaluator::labels(const core::CameraSetting& camera, int state) const {
  const Impl& m = *impl_;
  m.states.at(state);  // throws std::out_of_range on a bad index
  return m.labels(m.camera_setup(camera), state);
}

std::vector<std::uint8_t> VoxelEvaluator::model(const core::CameraConfig& config, int state) const {
  const Impl& m = *impl_;
  m.states.at(state);
  std::vector<std::vector<std::uint8_t>> models;
  m.all_raw_models(config, models);
  std::vector<std::uint8_t> out = std::move(models[state]);
  filter_components(out, m.grid, m.scene.plausibility);
  return out;
}

double VoxelEvaluator::err_lower_bound() const { return impl_->err_lower_bound; }
const Grid& VoxelEvaluator::grid() const { return impl_->grid; }
const core::Scene& VoxelEvaluator::scene() const { return impl_->scene; }
const VoxelOptions& VoxelEvaluator::options() const { return impl_->options; }

}  // namespace camplace::voxel
