// `camplace export` (docs/export.md): glTF per state, viewer page, poses, voxel files.
#include "camplace/view/export.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <nlohmann/json.hpp>
#include <numeric>
#include <optional>
#include <sstream>

#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/provenance.hpp"
#include "camplace/core/sensor_model.hpp"
#include "camplace/view/meshing.hpp"
#include "camplace/view/poses.hpp"
#include "camplace/view/voxel_files.hpp"
#include "gltf_builder.hpp"
#include "viewer_page.hpp"
#ifdef CAMPLACE_VIEW_HAVE_EXACT
#include "camplace/exact/evaluator.hpp"
#endif

namespace camplace::view {

namespace {

using core::Vec3;
using detail::GltfBuilder;
using json = nlohmann::ordered_json;

/// The three.js files the page loads, relative to libjs-three's directory, and their names
/// beside index.html (three/...).
const std::array<std::pair<const char*, const char*>, 3> kThreeFiles{{
    {"three.min.js", "three/three.min.js"},
    {"examples/js/controls/OrbitControls.js", "three/OrbitControls.js"},
    {"examples/js/loaders/GLTFLoader.js", "three/GLTFLoader.js"},
}};
/// three.js's licence as Debian ships it, copied beside the scripts when present.
constexpr const char* kThreeCopyright = "/usr/share/doc/libjs-three/copyright";

/// Colours per role (linear RGBA), shared by the glTF materials and the page's legend.
struct RoleStyle {
  const char* role;
  std::array<double, 4> rgba;
  bool double_sided;
};
constexpr std::array<RoleStyle, 9> kStyles{{
    {"static_obstacle", {0.50, 0.50, 0.53, 1.0}, false},
    {"dynamic_obstacle", {0.22, 0.42, 0.85, 1.0}, false},
    {"critical_object", {0.95, 0.30, 0.05, 0.45}, false},
    {"target", {0.15, 0.65, 0.25, 1.0}, false},
    {"model", {0.60, 0.25, 0.75, 0.55}, true},
    {"camera", {0.08, 0.08, 0.08, 1.0}, true},
    {"fov", {1.00, 0.80, 0.10, 0.10}, true},
    {"true_distance", {0.00, 0.55, 0.00, 1.0}, false},
    {"model_distance", {0.85, 0.00, 0.00, 1.0}, false},
}};

std::string read_binary(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string base64(const std::string& bytes) {
  static const char* kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    }
    for (std::size_t k = 0; k < 4; ++k) {
      out += k <= n ? kDigits[(v >> (18 - 6 * k)) & 63] : '=';
    }
  }
  return out;
}

json vec_json(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

std::string state_name(const core::StateIndex& s) {
  return "state-" + std::to_string(s.time_step) + "-" + std::to_string(s.event);
}

/// Reorients the triangles of a convex mesh outward (away from its vertices' centroid).
void orient_outward(core::TriangleMesh& mesh) {
  Vec3 center = Vec3::Zero();
  for (const Vec3& v : mesh.vertices) center += v;
  center /= static_cast<double>(mesh.vertices.size());
  for (auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    if ((b - a).cross(c - a).dot((a + b + c) / 3.0 - center) < 0) std::swap(t[1], t[2]);
  }
}

/// A small camera symbol in the camera node's frame (glTF camera: looks along −Z, +Y up): a
/// pyramid of depth `length` (m) with the FOV's opening, and a triangle on its up side.
core::TriangleMesh camera_glyph(double half_angle, double length) {
  const double w = length * std::tan(half_angle);
  core::TriangleMesh glyph;
  glyph.vertices = {Vec3(0, 0, 0), Vec3(-w, -w, -length), Vec3(w, -w, -length), Vec3(w, w, -length),
                    Vec3(-w, w, -length)};
  glyph.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}, {1, 3, 2}, {1, 4, 3}};
  orient_outward(glyph);
  const int first = static_cast<int>(glyph.vertices.size());
  glyph.vertices.push_back(Vec3(-0.6 * w, 1.1 * w, -length));
  glyph.vertices.push_back(Vec3(0.6 * w, 1.1 * w, -length));
  glyph.vertices.push_back(Vec3(0, 1.8 * w, -length));
  glyph.triangles.push_back({first, first + 1, first + 2});
  return glyph;
}

/// The pipeline's results for every state, and the means to get each state's model.
struct Evaluated {
  core::Evaluation evaluation;
  std::string mode;                        // voxel: labelling mode; exact: ""
  std::array<int, 3> resolution{0, 0, 0};  // voxel only
  std::string fov;                         // the FOV shape the pipeline used
  std::vector<core::TriangleMesh> model_meshes;
  std::vector<core::ClosestPoints> model_segments;
  std::vector<VoxelLayer> voxel_layers;  // voxel only, one per exported state
  std::optional<voxel::Grid> grid;
  std::vector<int> result_of;  // per exported state, its index in evaluation.states
};

std::vector<const core::TriangleMesh*> meshes_of(const std::vector<core::SceneObject>& objects) {
  std::vector<const core::TriangleMesh*> out;
  for (const auto& o : objects) out.push_back(&o.mesh);
  return out;
}

Evaluated evaluate_voxel(const core::Scene& scene, const core::CameraConfig& config,
                         const ExportOptions& options, const std::vector<int>& selected) {
  Evaluated out;
  const voxel::VoxelEvaluator evaluator(scene, options.voxel);
  out.evaluation = evaluator.evaluate(config);
  out.mode = core::name_of(options.voxel.mode);
  out.resolution = evaluator.grid().n;
  out.fov = core::name_of(scene.cameras.models.front().fov);
  out.grid = evaluator.grid();
  const auto all = core::states(scene);
  // The model as d(C, M) sees it: with refinement its finest cells (leaf_grid(), leaf_model()),
  // else the voxels; the voxel files keep the base voxels that hold M (VoxelEvaluator::model).
  const voxel::Grid cells = evaluator.leaf_grid();
  out.result_of = selected;
  for (int i : selected) {
    const std::vector<std::uint8_t> model = evaluator.leaf_model(config, i);
    out.model_meshes.push_back(voxel_boundary_mesh(cells, model));
    const auto critical = meshes_of(scene.time_steps[all[i].time_step].critical);
    const bool empty = std::none_of(model.begin(), model.end(), [](std::uint8_t b) { return b; });
    out.model_segments.push_back(
        empty || critical.empty()
            ? core::ClosestPoints{}
            : voxel_model_segment(cells, model, critical, options.voxel.mode));
    out.voxel_layers.push_back({all[i].time_step, all[i].event, evaluator.model(config, i)});
  }
  return out;
}

#ifdef CAMPLACE_VIEW_HAVE_EXACT
Evaluated evaluate_exact(const core::Scene& scene, const core::CameraConfig& config,
                         const ExportOptions& options, const std::vector<int>& selected) {
  Evaluated out;
  exact::ExactOptions exact_options;
  exact_options.keep_models = true;
  exact_options.threads = options.threads;
  exact_options.on_progress = options.on_exact_progress;
  const auto all = core::states(scene);
  // Exact work on the chosen states only (--state): Err then sums their terms alone.
  if (!options.states.empty())
    for (int i : selected) exact_options.states.push_back(all[i]);
  exact::ExactEvaluation e = exact::evaluate_exact(scene, config, exact_options);
  out.fov = core::name_of(core::FovShape::pyramid);  // SPEC §6: always the pyramid
  for (std::size_t k = 0; k < selected.size(); ++k) {
    const int i = selected[k];
    out.result_of.push_back(options.states.empty() ? i : static_cast<int>(k));
    core::TriangleMesh mesh = e.models[out.result_of.back()].boundary_mesh();
    const auto critical = meshes_of(scene.time_steps[all[i].time_step].critical);
    out.model_segments.push_back(
        mesh.triangles.empty() || critical.empty()
            ? core::ClosestPoints{}
            : core::closest_points(critical, std::vector<const core::TriangleMesh*>{&mesh}));
    out.model_meshes.push_back(std::move(mesh));
  }
  out.evaluation = std::move(e);
  return out;
}
#endif

/// One state's glTF file and what it holds.
std::string state_glb(const core::Scene& scene, const core::CameraConfig& config,
                      const Evaluated& ev, const core::StateResult& result, int exported,
                      const ExportOptions& options, ExportedState& info) {
  GltfBuilder gltf;
  std::map<std::string, int> materials;
  for (const RoleStyle& s : kStyles)
    materials[s.role] = gltf.material(s.role, s.rgba, s.double_sided);
  const core::TimeStep& step = scene.time_steps[info.state.time_step];
  const core::Event& event = step.events[info.state.event];
  const core::BuildInfo build = core::build_info();
  gltf.set_asset_extras(
      {{"generator", "camplace " + build.version + " (commit " + build.commit + ")"},
       {"units", "metres"},
       {"source_frame", "camplace world: right-handed, z up (docs/scene-format.md)"},
       {"up_axis_conversion",
        "glTF (X, Y, Z) = camplace (x, z, -y): camplace's z-up world rotated by -90 degrees "
        "about x; camplace (x, y, z) = glTF (X, -Z, Y)"},
       {"camera_nodes",
        "glTF convention: a camera looks along its node's local -Z with +Y up (camplace's up "
        "vector u) and +X right; yfov = 2 * half angle"},
       {"node_extras",
        "every node's extras.role is one of static_obstacle, dynamic_obstacle, "
        "critical_object, target, model, camera, fov, true_distance, model_distance; points "
        "in extras (from, to, position) are in camplace's z-up frame"}});

  auto count = [&](const char* role) { ++info.nodes[role]; };
  auto object_nodes = [&](const std::vector<core::SceneObject>& objects, const char* role,
                          const std::string& label) {
    for (const core::SceneObject& o : objects) {
      const int mesh = gltf.triangle_mesh(label + ": " + o.name, o.mesh, materials[role]);
      gltf.node(label + ": " + o.name, mesh,
                {{"role", role}, {"object", o.name}, {"entry", o.entry}});
      count(role);
    }
  };
  object_nodes(scene.static_obstacles, "static_obstacle", "static obstacle");
  object_nodes(step.dynamic_obstacles, "dynamic_obstacle", "dynamic obstacle");
  object_nodes(step.critical, "critical_object", "critical object");
  object_nodes(event.targets, "target", "target");

  // The model: its outer boundary (voxel faces merged, or the exact boundary mesh).
  const core::TriangleMesh& model = ev.model_meshes[exported];
  info.model_empty = model.triangles.empty();
  json model_extras = {{"role", "model"},
                       {"pipeline", core::name_of(options.pipeline)},
                       {"volume_m3", result.model_volume},
                       {"components", result.components},
                       {"empty", info.model_empty}};
  if (options.pipeline == core::Pipeline::voxel) {
    model_extras["mode"] = ev.mode;
    model_extras["resolution"] = {ev.resolution[0], ev.resolution[1], ev.resolution[2]};
  }
  gltf.node("model", info.model_empty ? -1 : gltf.triangle_mesh("model", model, materials["model"]),
            model_extras);
  count("model");

  // Cameras: a glTF camera with the pose, and the FOV clipped to S (in the pipeline's shape).
  core::CameraSpec cameras = scene.cameras;
  if (options.pipeline == core::Pipeline::exact) core::use_exact_models(cameras);
  Eigen::Matrix3d to_gltf;  // camplace → glTF axes
  to_gltf << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  const int glyph_mesh = gltf.triangle_mesh(
      "camera symbol",
      camera_glyph(cameras.models.front().bounding_half_angle(), 0.03 * scene.area.diagonal()),
      materials["camera"], false);
  for (std::size_t c = 0; c < config.size(); ++c) {
    const core::CameraModel& spec = cameras.models[c];
    const std::string name = "camera " + std::to_string(c);
    const Vec3 d = core::view_direction(config[c]);
    const Vec3 u = core::up_vector(config[c]);
    Eigen::Matrix3d frame;  // glTF camera axes X right, Y up, Z backward, in camplace's frame
    frame.col(0) = d.cross(u);
    frame.col(1) = u;
    frame.col(2) = -d;
    const Eigen::Vector4d q = quaternion_xyzw(to_gltf * frame);
    // zfar: beyond S and every object of the state (obstacles and critical objects may extend
    // beyond S, SPEC §2; they are drawn whole).
    double far = 1.0;
    for (const Vec3& corner : scene.area.corners()) {
      far = std::max(far, (corner - config[c].position).norm() + 1.0);
    }
    for (const auto* objects :
         {&scene.static_obstacles, &step.dynamic_obstacles, &step.critical, &event.targets}) {
      for (const core::SceneObject& o : *objects) {
        for (const Vec3& corner : o.bounds.corners()) {
          far = std::max(far, (corner - config[c].position).norm() + 1.0);
        }
      }
    }
    if (spec.range) far = *spec.range;
    // yfov: the frustum's vertical opening, else the cone's (pyramid's) full angle.
    const double yfov = spec.fov == core::FovShape::frustum ? spec.vertical : 2.0 * spec.half_angle;
    // A frustum's image is tan(H/2) : tan(V/2) wide; a cone's is left to the viewer.
    const double aspect = spec.fov == core::FovShape::frustum
                              ? std::tan(0.5 * spec.horizontal) / std::tan(0.5 * spec.vertical)
                              : 0.0;
    const int camera =
        gltf.perspective_camera(name, yfov, spec.near > 0.0 ? spec.near : 0.01, far, aspect);
    json camera_extras = {{"role", "camera"},
                          {"index", c},
                          {"model", spec.name},
                          {"position", vec_json(config[c].position)},
                          {"yaw_deg", config[c].yaw / core::kDegree},
                          {"pitch_deg", config[c].pitch / core::kDegree},
                          {"roll_deg", config[c].roll / core::kDegree}};
    if (spec.fov == core::FovShape::frustum) {
      camera_extras["horizontal_deg"] = spec.horizontal / core::kDegree;
      camera_extras["vertical_deg"] = spec.vertical / core::kDegree;
    } else {
      camera_extras["half_angle_deg"] = spec.half_angle / core::kDegree;
    }
    gltf.node(name, glyph_mesh, camera_extras, camera, {q[0], q[1], q[2], q[3]},
              detail::to_gltf(config[c].position));
    count("camera");
    const core::TriangleMesh fov = fov_mesh(config[c], spec, scene.area);
    gltf.node(
        "fov: " + name,
        fov.triangles.empty() ? -1 : gltf.triangle_mesh("fov: " + name, fov, materials["fov"]),
        {{"role", "fov"},
         {"camera", c},
         {"shape", core::name_of(spec.fov)},
         {"sides_drawn", spec.fov == core::FovShape::pyramid   ? spec.sides
                         : spec.fov == core::FovShape::frustum ? 4
                                                               : kConeDrawSides},
         {"clipped_to", "S"},
         {"empty", fov.triangles.empty()}});
    count("fov");
  }

  // The two distances between their closest points.
  const double marker = 0.01 * scene.area.diagonal();
  const auto critical = meshes_of(step.critical);
  const auto targets = meshes_of(event.targets);
  json true_extras = {{"role", "true_distance"},
                      {"length_m", result.d_true},
                      {"between", "critical objects (from) and targets (to)"},
                      {"empty", critical.empty() || targets.empty()}};
  int true_mesh = -1;
  if (!critical.empty() && !targets.empty()) {
    info.true_segment = core::closest_points(critical, targets);
    true_extras["from"] = vec_json(info.true_segment.a);
    true_extras["to"] = vec_json(info.true_segment.b);
    true_mesh = gltf.segment_mesh("d_true", info.true_segment.a, info.true_segment.b,
                                  materials["true_distance"], materials["true_distance"], marker);
  }
  gltf.node("d_true", true_mesh, true_extras);
  count("true_distance");
  info.model_segment = ev.model_segments[exported];
  json model_segment = {{"role", "model_distance"},
                        {"length_m", result.d_model},
                        {"between", "critical objects (from) and the model M (to)"},
                        {"empty", info.model_empty}};
  int segment_mesh = -1;
  if (!info.model_empty) {
    model_segment["from"] = vec_json(info.model_segment.a);
    model_segment["to"] = vec_json(info.model_segment.b);
    segment_mesh =
        gltf.segment_mesh("d_model", info.model_segment.a, info.model_segment.b,
                          materials["model_distance"], materials["model_distance"], marker);
  }
  gltf.node("d_model", segment_mesh, model_segment);
  count("model_distance");

  const double term = result.weight * std::pow(result.d_true - result.d_model, 2);
  json scene_extras = {{"time_step", info.state.time_step},
                       {"event", info.state.event},
                       {"weight", result.weight},
                       {"d_true", result.d_true},
                       {"d_model", result.d_model},
                       {"err_term", term},
                       {"err", ev.evaluation.err},
                       {"err_states", ev.evaluation.states.size()},
                       {"pipeline", core::name_of(options.pipeline)},
                       {"fov", ev.fov},
                       {"scene_file", options.scene_file},
                       {"cameras_file", options.cameras_file}};
  if (options.pipeline == core::Pipeline::voxel) {
    scene_extras["mode"] = ev.mode;
    scene_extras["resolution"] = {ev.resolution[0], ev.resolution[1], ev.resolution[2]};
  }
  gltf.set_scene_extras(scene_extras);
  return gltf.glb();
}

}  // namespace

core::ClosestPoints voxel_model_segment(const voxel::Grid& grid,
                                        const std::vector<std::uint8_t>& model,
                                        const std::vector<const core::TriangleMesh*>& critical,
                                        core::LabelMode mode) {
  std::vector<core::Box3> bounds;
  for (const auto* m : critical) bounds.push_back(core::bounding_box(*m));
  // Candidates in order of a lower bound (the gap to the nearest critical bounding box).
  std::vector<std::pair<double, int>> candidates;
  for (int v = 0; v < grid.count(); ++v) {
    if (!model[v]) continue;
    const core::Box3 box = mode == core::LabelMode::conservative
                               ? grid.voxel_box(v)
                               : core::Box3{grid.voxel_center(v), grid.voxel_center(v)};
    double lb = std::numeric_limits<double>::infinity();
    for (const auto& b : bounds) {
      const Vec3 gap = (box.min - b.max).cwiseMax(b.min - box.max).cwiseMax(0.0);
      lb = std::min(lb, gap.squaredNorm());
    }
    candidates.emplace_back(lb, v);
  }
  std::sort(candidates.begin(), candidates.end());
  core::ClosestPoints best;
  best.sq_distance = std::numeric_limits<double>::infinity();
  for (const auto& [lb, v] : candidates) {
    if (lb > best.sq_distance) break;
    const core::ClosestPoints pair = mode == core::LabelMode::conservative
                                         ? core::closest_points(critical, grid.voxel_box(v))
                                         : core::closest_points(critical, grid.voxel_center(v));
    if (pair.sq_distance < best.sq_distance) best = pair;
  }
  return best;
}

nlohmann::ordered_json role_colors_json() {
  json styles = json::object();
  for (const RoleStyle& s : kStyles) {
    styles[s.role] = {s.rgba[0], s.rgba[1], s.rgba[2], s.rgba[3]};
  }
  return styles;
}

void check_export_options(const core::Scene& scene, const ExportOptions& options) {
  if (options.pipeline == core::Pipeline::both) {
    throw core::OptionError("pipeline", "export takes voxel or exact (one model per file)");
  }
#ifndef CAMPLACE_VIEW_HAVE_EXACT
  if (options.pipeline == core::Pipeline::exact) {
    throw core::OptionError("pipeline", "this build has no exact pipeline");
  }
#endif
  for (const core::StateIndex& s : options.states) {
    const int steps = static_cast<int>(scene.time_steps.size());
    const std::string which = std::to_string(s.time_step) + "," + std::to_string(s.event);
    if (s.time_step < 0 || s.time_step >= steps) {
      throw core::OptionError("state", "no state " + which + ": " + scene.file +
                                           " has time steps 0.." + std::to_string(steps - 1));
    }
    const int events = static_cast<int>(scene.time_steps[s.time_step].events.size());
    if (s.event < 0 || s.event >= events) {
      throw core::OptionError("state", "no state " + which + ": time step " +
                                           std::to_string(s.time_step) + " of " + scene.file +
                                           " has events 0.." + std::to_string(events - 1));
    }
  }
  for (const auto& [source, target] : kThreeFiles) {
    const std::string path = options.three_dir + "/" + source;
    if (!std::ifstream(path)) {
      throw core::OptionError("three-dir", path +
                                               " cannot be read (install Debian's libjs-three, "
                                               "or pass the directory holding three.min.js)");
    }
  }
}

ExportResult export_scene(const core::Scene& scene, const core::CameraConfig& config,
                          const ExportOptions& options, const std::string& out_dir) {
  check_export_options(scene, options);
  core::check_configuration(scene, config);
  const auto all = core::states(scene);
  std::vector<int> selected;
  for (int i = 0; i < static_cast<int>(all.size()); ++i) {
    const bool wanted =
        options.states.empty() ||
        std::any_of(options.states.begin(), options.states.end(), [&](const core::StateIndex& s) {
          return s.time_step == all[i].time_step && s.event == all[i].event;
        });
    if (wanted) selected.push_back(i);
  }

  Evaluated ev;
#ifdef CAMPLACE_VIEW_HAVE_EXACT
  ev = options.pipeline == core::Pipeline::exact ? evaluate_exact(scene, config, options, selected)
                                                 : evaluate_voxel(scene, config, options, selected);
#else
  ev = evaluate_voxel(scene, config, options, selected);
#endif

  ExportResult result;
  result.err = ev.evaluation.err;
  result.err_states = static_cast<int>(ev.evaluation.states.size());
  std::vector<FileContent> files;
  json states = json::array();
  for (std::size_t k = 0; k < selected.size(); ++k) {
    ExportedState info;
    info.state = all[selected[k]];
    info.glb = state_name(info.state) + ".glb";
    info.result = ev.evaluation.states[ev.result_of[k]];
    const std::string glb =
        state_glb(scene, config, ev, info.result, static_cast<int>(k), options, info);
    const core::StateResult& r = info.result;
    json nodes = json::object();
    for (const char* role : kRoles) nodes[role] = info.nodes[role];
    states.push_back({{"name", state_name(info.state)},
                      {"file", info.glb},
                      {"time_step", info.state.time_step},
                      {"event", info.state.event},
                      {"weight", r.weight},
                      {"d_true", r.d_true},
                      {"d_model", r.d_model},
                      {"err_term", r.weight * std::pow(r.d_true - r.d_model, 2)},
                      {"model_volume", r.model_volume},
                      {"model_empty", info.model_empty},
                      {"nodes", nodes},
                      {"glb_base64", base64(glb)}});
    files.emplace_back(info.glb, glb);
    result.states.push_back(std::move(info));
  }

  // The page: index.html, its data as a script (a page opened from file:// may not fetch()
  // files beside it, so the glTF bytes travel inside), and three.js from libjs-three.
  json meta = {{"scene_file", options.scene_file},
               {"cameras_file", options.cameras_file},
               {"pipeline", core::name_of(options.pipeline)},
               {"fov", ev.fov},
               {"err", ev.evaluation.err},
               {"err_states", ev.evaluation.states.size()},
               {"states_total", all.size()},
               {"area", {{"min", vec_json(scene.area.min)}, {"max", vec_json(scene.area.max)}}},
               {"role_colors", role_colors_json()},
               {"camplace", core::build_info().version}};
  if (options.pipeline == core::Pipeline::voxel) {
    meta["mode"] = ev.mode;
    meta["resolution"] = {ev.resolution[0], ev.resolution[1], ev.resolution[2]};
  }
  const json data = {{"meta", meta}, {"states", states}};
  files.emplace_back("viewer-data.js",
                     "// Written by camplace export: the page's data (docs/export.md).\n"
                     "window.CAMPLACE_EXPORT = " +
                         data.dump() + ";\n");
  files.emplace_back("index.html", detail::viewer_page());
  for (const auto& [source, target] : kThreeFiles) {
    files.emplace_back(target, read_binary(options.three_dir + "/" + source));
  }
  if (std::ifstream(kThreeCopyright)) {
    files.emplace_back("three/COPYRIGHT", read_binary(kThreeCopyright));
  }
  files.emplace_back("poses.json", poses_json(config));
  files.emplace_back("poses.yaml", poses_yaml(config));
  if (ev.grid) {
    for (auto& file : voxel_files(*ev.grid, ev.voxel_layers, "voxels.npy",
                                  {{"pipeline", "voxel"},
                                   {"mode", ev.mode},
                                   {"scene_file", options.scene_file},
                                   {"cameras_file", options.cameras_file}})) {
      files.push_back(std::move(file));
    }
  }

  for (const auto& [name, content] : files) {
    try {
      core::write_file_atomically(out_dir + "/" + name, content);
    } catch (const std::runtime_error& e) {
      throw core::OptionError("out", e.what());
    }
    result.files.push_back(name);
  }
  return result;
}

}  // namespace camplace::view
