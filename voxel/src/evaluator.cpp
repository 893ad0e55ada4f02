// The voxel pipeline (SPEC §3–5): the public evaluator — labelling, the plausibility filter,
// refinement and d(C_h, M) per state, in that order — around the private Impl (impl.hpp, which
// says where each stage lives).
#include "camplace/voxel/evaluator.hpp"

#include <algorithm>
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
  const std::string refine = refine_problem(scene, m.options);
  if (!refine.empty()) throw core::OptionError("refine", refine);
  m.conservative = options.mode == LabelMode::conservative;
  m.grid = make_grid(scene.area, n);
  m.half_step = 0.5 * m.grid.step;
  m.voxel_radius = m.half_step.norm();
  m.voxel_volume = m.grid.voxel_volume();
  m.levels = options.refine;
  m.build();
}

VoxelEvaluator::~VoxelEvaluator() = default;
VoxelEvaluator::VoxelEvaluator(VoxelEvaluator&&) noexcept = default;
VoxelEvaluator& VoxelEvaluator::operator=(VoxelEvaluator&&) noexcept = default;

void VoxelEvaluator::Impl::filter_states(std::vector<detail::Rows>& models,
                                         std::vector<ComponentCount>& counts) const {
  const int state_count = static_cast<int>(models.size());
  const int chunks = (state_count + detail::kChunk - 1) / detail::kChunk;
  // Per calling thread, reused (a reference, so that the worker threads see this thread's).
  thread_local std::vector<detail::RowCore> core_buffers;
  std::vector<detail::RowCore>& cores = core_buffers;
  cores.resize(chunks);
  detail::parallel_for(chunks, options.threads, [&](int chunk) {
    const int first = chunk * detail::kChunk;
    const int count = std::min(detail::kChunk, state_count - first);
    const detail::Rows* chunk_models[detail::kChunk];
    for (int s = 0; s < count; ++s) chunk_models[s] = &models[first + s];
    detail::core_of_rows(chunk_models, count, grid, scene.plausibility, cores[chunk]);
  });
  detail::parallel_for(state_count, options.threads, [&](int s) {
    counts[s] = detail::filter_rows(models[s], cores[s / detail::kChunk], grid, scene.plausibility);
  });
}

Evaluation VoxelEvaluator::evaluate(const core::CameraConfig& config) const {
  const Impl& m = *impl_;
  const auto start = Clock::now();
  const int state_count = static_cast<int>(m.states.size());
  Evaluation result;
  auto t0 = Clock::now();
  // Per calling thread, reused: the optimizer evaluates thousands of configurations per
  // thread. (A reference, so that the worker threads below see this thread's buffers.)
  thread_local std::vector<detail::Rows> buffers;
  thread_local std::vector<detail::CellSet> leaf_buffers;
  std::vector<detail::Rows>& models = buffers;
  thread_local std::vector<detail::CameraSetup> camera_buffers;
  std::vector<detail::CameraSetup>& cameras = camera_buffers;
  m.all_raw_models(config, models, &cameras);
  result.timing.labelling_ms = ms_since(t0);
#if CAMPLACE_EXPENSIVE_CHECKS
  std::vector<std::vector<std::uint8_t>> raw(state_count), bytes(state_count);
  for (int s = 0; s < state_count; ++s) detail::bytes_from_rows(models[s], m.grid, raw[s]);
  m.check_labels(config, raw);
#endif
  std::vector<ComponentCount> filtered(state_count);
  t0 = Clock::now();
  m.filter_states(models, filtered);
  result.timing.clustering_ms = ms_since(t0);
#if CAMPLACE_EXPENSIVE_CHECKS
  for (int s = 0; s < state_count; ++s) detail::bytes_from_rows(models[s], m.grid, bytes[s]);
  m.check_filtered(raw, bytes);
#endif
  std::vector<Impl::ModelDistance> distances(state_count);
  if (m.levels > 0) {
    // Refinement of the kept base components (a cell component lies in one base component and
    // is not larger, so base components the filter removes hold none that it would keep).
    std::vector<ComponentCount> cells;
    m.refined_states(cameras, models, leaf_buffers, cells, distances, result.timing);
#if CAMPLACE_EXPENSIVE_CHECKS
    m.check_refined(bytes, leaf_buffers, distances);
#endif
    t0 = Clock::now();
    for (int s = 0; s < state_count; ++s) {
      filtered[s].kept = cells[s].kept;
      filtered[s].removed += cells[s].removed;
    }
  } else {
    t0 = Clock::now();
    detail::parallel_for(state_count, m.options.threads, [&](int s) {
      distances[s] = m.model_distance(models[s], m.states[s].time_step);
    });
#if CAMPLACE_EXPENSIVE_CHECKS
    for (int s = 0; s < state_count; ++s) {
      m.check_distance(bytes[s], m.states[s].time_step, distances[s]);
    }
#endif
  }
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
  result.timing.distance_ms += ms_since(t0);
  result.err = core::error_of(result.states);
  result.timing.total_ms = ms_since(start);
  return result;
}

double VoxelEvaluator::err(const core::CameraConfig& config) const { return evaluate(config).err; }

std::vector<Label> VoxelEvaluator::labels(const core::CameraSetting& camera, int state,
                                          int camera_index) const {
  const Impl& m = *impl_;
  m.states.at(state);  // throws std::out_of_range on a bad index
  detail::CameraSetup cam;
  m.camera_setup(camera, m.scene.cameras.models.at(camera_index), cam);
  return m.labels(cam, state);
}

detail::FilteredModels VoxelEvaluator::Impl::filtered_models(
    const core::CameraConfig& config) const {
  const Impl& m = *this;
  detail::FilteredModels out;
  std::vector<detail::CameraSetup> cameras;
  std::vector<detail::Rows> rows;
  m.all_raw_models(config, rows, &cameras);
  out.base.resize(rows.size());
  std::vector<ComponentCount> filtered(rows.size());
  m.filter_states(rows, filtered);
  for (std::size_t s = 0; s < rows.size(); ++s)
    detail::bytes_from_rows(rows[s], m.grid, out.base[s]);
  if (m.levels == 0) return out;
  std::vector<ComponentCount> counts;
  std::vector<ModelDistance> distances;
  core::Timing timing;
  m.refined_states(cameras, rows, out.cells, counts, distances, timing);
  return out;
}

std::vector<std::uint8_t> VoxelEvaluator::model(const core::CameraConfig& config, int state) const {
  impl_->states.at(state);  // throws std::out_of_range on a bad index
  return std::move(models(config)[state]);
}

std::vector<std::vector<std::uint8_t>> VoxelEvaluator::models(
    const core::CameraConfig& config) const {
  const Impl& m = *impl_;
  detail::FilteredModels models = m.filtered_models(config);
  if (m.levels == 0) return std::move(models.base);
  std::vector<std::vector<std::uint8_t>> out(m.states.size());
  for (std::size_t s = 0; s < out.size(); ++s) {
    out[s].assign(m.grid.count(), 0);
    const detail::CellSet& set = models.cells[s];
    for (std::size_t slot = 0; slot < set.voxels.size(); ++slot) {
      const auto begin = set.cells.begin() + slot * m.octree.cells;
      out[s][set.voxels[slot]] =
          std::find(begin, begin + m.octree.cells, 1) != begin + m.octree.cells;
    }
  }
  return out;
}

Grid VoxelEvaluator::leaf_grid() const {
  const Impl& m = *impl_;
  const int side = m.octree.side;
  return make_grid(m.grid.area, {m.grid.n[0] * side, m.grid.n[1] * side, m.grid.n[2] * side});
}

std::vector<std::uint8_t> VoxelEvaluator::leaf_model(const core::CameraConfig& config,
                                                     int state) const {
  impl_->states.at(state);  // throws std::out_of_range on a bad index
  return std::move(leaf_models(config)[state]);
}

std::vector<std::vector<std::uint8_t>> VoxelEvaluator::leaf_models(
    const core::CameraConfig& config) const {
  const Impl& m = *impl_;
  if (m.levels == 0) return models(config);
  const detail::FilteredModels models = m.filtered_models(config);
  const Grid fine = leaf_grid();
  const int side = m.octree.side, nx = m.grid.n[0], ny = m.grid.n[1];
  std::vector<std::vector<std::uint8_t>> out(m.states.size());
  for (std::size_t s = 0; s < out.size(); ++s) {
    out[s].assign(static_cast<std::size_t>(fine.count()), 0);
    const detail::CellSet& set = models.cells[s];
    for (std::size_t slot = 0; slot < set.voxels.size(); ++slot) {
      const int v = set.voxels[slot];
      const int i = v % nx, j = (v / nx) % ny, k = v / (nx * ny);
      for (int cell = 0; cell < m.octree.cells; ++cell) {
        if (!set.cells[slot * m.octree.cells + cell]) continue;
        const auto& c = m.octree.coords[cell];
        const long I = static_cast<long>(i) * side + c[0], J = static_cast<long>(j) * side + c[1],
                   K = static_cast<long>(k) * side + c[2];
        out[s][I + fine.n[0] * (J + fine.n[1] * K)] = 1;
      }
    }
  }
  return out;
}

double VoxelEvaluator::err_lower_bound() const { return impl_->err_lower_bound; }
const Grid& VoxelEvaluator::grid() const { return impl_->grid; }
const core::Scene& VoxelEvaluator::scene() const { return impl_->scene; }
const VoxelOptions& VoxelEvaluator::options() const { return impl_->options; }

}  // namespace camplace::voxel
