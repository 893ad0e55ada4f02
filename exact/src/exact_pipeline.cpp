// The exact reference pipeline (SPEC §6). All Nef code of camplace lives in this one translation
// unit (STYLE.md: each Nef TU costs ~35 s and ~1.6 GB to compile); its stages are private headers
// that only this file includes:
//   internal/kernel.hpp    kernel, number type, exact conversions
//   internal/solids.hpp    scene objects in exact coordinates, convex hulls, unions
//   internal/cones.hpp     FOVs, shadow volumes and silhouette cones of one camera
//   internal/pipeline.hpp  the model of each state, with per-camera caches
//   internal/soup.hpp      Nef → exact triangle soup, OFF export
//   internal/model.hpp     components, exact volumes, plausibility filter, d(C, M)
// Every double input is converted exactly to a rational.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>

#include "camplace/core/distance.hpp"
#include "camplace/core/sensor_model.hpp"
#include "camplace/exact/evaluator.hpp"
#include "internal/kernel.hpp"
#include "internal/model.hpp"
#include "internal/pipeline.hpp"
#include "internal/soup.hpp"

namespace camplace::exact {

using namespace internal;

ExactModel::ExactModel() : impl_(std::make_shared<Impl>()) {}
ExactModel::ExactModel(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
bool ExactModel::contains(const core::Vec3& p) const { return impl_->contains(to_point(p)); }
bool ExactModel::empty() const {
  return std::none_of(impl_->components.begin(), impl_->components.end(),
                      [](const Impl::Component& c) { return c.kept; });
}
double ExactModel::volume() const { return nearest_double(impl_->kept_volume); }
int ExactModel::components() const {
  return int(std::count_if(impl_->components.begin(), impl_->components.end(),
                           [](const Impl::Component& c) { return c.kept; }));
}
std::vector<ExactComponent> ExactModel::component_info() const {
  std::vector<ExactComponent> out;
  for (const auto& c : impl_->components)
    out.push_back({nearest_double(c.volume_exact), nearest_double(c.z_min),
                   nearest_double(c.z_max), c.kept});
  return out;
}
core::TriangleMesh ExactModel::boundary_mesh() const {
  core::TriangleMesh mesh;
  for (const auto& c : impl_->components) {
    if (!c.kept) continue;
    const int base = int(mesh.vertices.size());
    for (const auto& p : c.points) mesh.vertices.push_back(to_vec3(p));
    for (const auto& t : c.triangles)
      mesh.triangles.push_back({base + int(t[0]), base + int(t[1]), base + int(t[2])});
  }
  return mesh;
}

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void export_fovs(const Pipeline& pipeline, const std::string& dir) {
  for (std::size_t c = 0; c < pipeline.camera_count(); ++c) {
    const TriangleSoup soup = nef_soup(pipeline.fov(c));
    export_soup(dir + "/camera-" + std::to_string(c) + "-pyramid.off", soup.points, soup.triangles);
  }
}

void export_model(const ExactModel::Impl& model, const core::StateIndex& s,
                  const std::string& dir) {
  std::vector<Point> pts;
  std::vector<std::array<std::size_t, 3>> tris;
  for (const auto& c : model.components) {
    if (!c.kept) continue;
    const std::size_t base = pts.size();
    pts.insert(pts.end(), c.points.begin(), c.points.end());
    for (const auto& t : c.triangles) tris.push_back({base + t[0], base + t[1], base + t[2]});
  }
  export_soup(dir + "/state-h" + std::to_string(s.time_step) + "-e" + std::to_string(s.event) +
                  "-model.off",
              pts, tris);
}

}  // namespace

ExactEvaluation evaluate_exact(const core::Scene& scene, const core::CameraConfig& config,
                               const ExactOptions& options) {
  const auto t_total = Clock::now();
  ExactEvaluation result;
  Pipeline pipeline(scene, config);
  if (!options.export_dir.empty()) {
    std::filesystem::create_directories(options.export_dir);
    export_fovs(pipeline, options.export_dir);
  }
  for (const auto& s : core::states(scene)) {
    auto t0 = Clock::now();
    Nef m = pipeline.model(s);
    result.timing.labelling_ms += ms_since(t0);

    t0 = Clock::now();
    auto model = cluster(std::move(m), scene.plausibility);
    result.timing.clustering_ms += ms_since(t0);

    t0 = Clock::now();
    core::StateResult r;
    r.time_step = s.time_step;
    r.event = s.event;
    r.weight = scene.time_steps[s.time_step].events[s.event].weight;
    const auto d_true = core::true_squared_distance(scene, s);
    r.d_true = std::sqrt(d_true.value);
    r.d_true_sq_exact = d_true.fraction;
    const auto d_model = model_squared_distance(*model, pipeline.critical(s.time_step));
    // SPEC §4: d(C, ∅) is S's diagonal.
    const FT d_model_sq = d_model ? *d_model : core::empty_model_squared_distance<FT>(scene.area);
    r.d_model = std::sqrt(nearest_double(d_model_sq));
    r.d_model_sq_exact = fraction_string(d_model_sq);
    result.timing.distance_ms += ms_since(t0);

    r.model_volume = nearest_double(model->kept_volume);
    r.model_volume_exact = fraction_string(model->kept_volume);
    for (const auto& c : model->components) (c.kept ? r.components : r.components_removed)++;
    if (!options.export_dir.empty()) export_model(*model, s, options.export_dir);
    result.states.push_back(std::move(r));
    if (options.keep_models) result.models.emplace_back(std::move(model));
  }
  result.err = core::error_of(result.states);
  result.timing.total_ms = ms_since(t_total);
  return result;
}

ExactModel build_exact_model(const core::Scene& scene, const core::CameraConfig& config,
                             const core::StateIndex& state) {
  Pipeline pipeline(scene, config);
  return ExactModel(cluster(pipeline.model(state), scene.plausibility));
}

}  // namespace camplace::exact
