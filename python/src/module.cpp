// The Python module `camplace`: a thin layer over the C++ modules. Every result is
// what the command-line tool computes (the same library calls, the same JSON); the layer only
// converts arguments and results and releases the GIL while C++ works.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "camplace/compare/evaluation_json.hpp"
#include "camplace/core/camera.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/names.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/threads.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "camplace/voxel/grid.hpp"
#include "json_python.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace camplace::python {

// ---- arguments -------------------------------------------------------------------------------

std::array<int, 3> resolution_argument(const py::object& value) {
  if (value.is_none()) return {0, 0, 0};
  if (py::isinstance<py::str>(value)) {
    try {
      return core::parse_resolution(value.cast<std::string>(), "resolution");
    } catch (const core::InputError& e) {
      throw core::OptionError("resolution", e.reason());
    }
  }
  std::array<int, 3> n{};
  try {
    n = value.cast<std::array<int, 3>>();
  } catch (const py::cast_error&) {
    throw core::OptionError("resolution", "expected (nx, ny, nz) or \"NXxNYxNZ\", got " +
                                              py::repr(value).cast<std::string>());
  }
  const std::string problem = core::resolution_problem(n);
  if (!problem.empty()) throw core::OptionError("resolution", problem);
  return n;
}

namespace {

int threads_argument(int threads) {
  if (threads < 0 || threads > core::kMaxThreads) {
    throw core::OptionError(
        "threads", "must lie in [0, " + std::to_string(core::kMaxThreads) + "] (0 = one per core)");
  }
  return threads;
}

int resolved_threads(int threads) {
  if (threads > 0) return threads;
  return core::machine_cores();
}

/// The cameras argument: a camera file's path, a camera file's content (a dict with "cameras",
/// such as a run file) or its list of cameras. `file` receives the path ("" otherwise).
core::CameraConfig cameras_argument(const py::object& cameras, const core::Scene& scene,
                                    std::string& file) {
  if (py::isinstance<py::str>(cameras) || py::hasattr(cameras, "__fspath__")) {
    try {
      file = cameras.cast<std::filesystem::path>().string();
    } catch (const py::cast_error&) {
      // A NUL in the string, or an __fspath__ that gives no path: no file can have that name.
      throw py::value_error("cameras: not a file path: " + py::repr(cameras).cast<std::string>());
    }
    py::gil_scoped_release release;
    return core::load_camera_config(file, scene);
  }
  file.clear();
  nlohmann::json doc = from_python(cameras, "cameras");
  if (!doc.is_object()) doc = {{"cameras", std::move(doc)}};
  return core::camera_config_from_json(doc, "cameras argument", &scene);
}

/// The index into core::states() of state (h, l).
int state_argument(const core::Scene& scene, const std::pair<int, int>& state) {
  const auto all = core::states(scene);
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (all[i].time_step == state.first && all[i].event == state.second) {
      return static_cast<int>(i);
    }
  }
  throw core::OptionError(
      "state", "the scene " + scene.file + " has no state (" + std::to_string(state.first) + ", " +
                   std::to_string(state.second) + ") (time step h, event l; see Scene.states)");
}

/// The scene with the voxel pipeline's FOV: the scene's, or `fov` ("cone", "pyramid").
core::Scene scene_with_fov(const core::Scene& scene, const std::optional<std::string>& fov) {
  core::Scene out = scene;
  if (fov) {
    const core::FovShape shape = enum_argument<core::FovShape>("fov", *fov);
    for (core::CameraModel& model : out.cameras.models) {
      // A cone and its inscribed pyramid share the half angle; a frustum has neither.
      if ((model.fov == core::FovShape::frustum) != (shape == core::FovShape::frustum)) {
        throw core::OptionError("fov", "\"" + *fov + "\" does not apply to the scene's " +
                                           core::name_of(model.fov) + " model");
      }
      model.fov = shape;
    }
  }
  return out;
}

// ---- load_scene, load_cameras ----------------------------------------------------------------

PyScene load_scene(const std::filesystem::path& path) {
  PyScene out;
  py::gil_scoped_release release;
  auto scene = std::make_shared<core::Scene>(core::load_scene(path.string()));
  out.json = core::read_json_file(path.string());
  out.scene = std::move(scene);
  return out;
}

py::list load_cameras(const std::filesystem::path& path, const PyScene* scene) {
  nlohmann::json doc;
  {
    py::gil_scoped_release release;
    doc = core::read_json_file(path.string());
    core::camera_config_from_json(doc, path.string(), scene ? scene->scene.get() : nullptr);
  }
  // The entries as the file has them (the numbers unrounded), checked above.
  return to_python(doc["cameras"]);
}

// ---- evaluate ----------------------------------------------------------------------------------

/// Replaces the "p/q" strings of an exact result's states by fractions.Fraction.
void exact_fractions_to_python(py::dict exact) {
  const py::object fraction = py::module_::import("fractions").attr("Fraction");
  for (py::handle state : exact["states"].cast<py::list>()) {
    py::dict s = py::reinterpret_borrow<py::dict>(state);
    for (const char* key : {"d_true_sq_exact", "d_model_sq_exact", "model_volume_exact"}) {
      if (s.contains(key)) s[key] = fraction(s[key]);
    }
  }
}

py::dict evaluate(const PyScene& scene, const py::object& cameras, const std::string& pipeline,
                  const std::string& mode, const py::object& resolution, int refine, int threads,
                  bool fractions, const std::optional<std::filesystem::path>& export_mesh,
                  const std::optional<std::filesystem::path>& voxels_out) {
  compare::EvaluationOptions options;
  options.pipeline = enum_argument<core::Pipeline>("pipeline", pipeline);
  options.mode = enum_argument<core::LabelMode>("mode", mode);
  options.resolution = resolution_argument(resolution);
  options.refine = refine;
  options.threads = threads_argument(threads);
  const bool want_voxel = options.pipeline != core::Pipeline::exact;
  const bool want_exact = options.pipeline != core::Pipeline::voxel;
  if (!want_exact && (fractions || export_mesh)) {
    throw core::OptionError(fractions ? "fractions" : "export_mesh",
                            "needs pipeline \"exact\" or \"both\"");
  }
  if (!want_voxel && voxels_out) {
    throw core::OptionError("voxels_out", "needs pipeline \"voxel\" or \"both\"");
  }
  if (voxels_out) {
    const std::string problem = compare::voxel_models_path_problem(voxels_out->string());
    if (!problem.empty()) throw core::OptionError("voxels_out", problem);
    // As `camplace evaluate --voxels-out`: an unwritable folder is refused before the work.
    const std::filesystem::path parent = voxels_out->parent_path();
    try {
      core::probe_output_directory(parent.empty() ? "." : parent.string(), "voxels_out");
    } catch (const core::InputError& e) {
      throw core::OptionError("voxels_out", e.reason());
    }
  }
  const core::CameraConfig config = cameras_argument(cameras, *scene.scene, options.cameras_file);
  options.exact_fractions = fractions;
  options.voxel_models = voxels_out.has_value();
  compare::EvaluationJson evaluation;
  {
    py::gil_scoped_release release;
    if (export_mesh) {
      options.export_dir = export_mesh->string();
      try {
        core::create_output_directory(options.export_dir, "export_mesh");
      } catch (const core::InputError& e) {
        throw core::OptionError("export_mesh", e.reason());
      }
    }
    evaluation = compare::evaluate_json(*scene.scene, config, options);
    if (voxels_out) {
      // As `camplace evaluate --voxels-out`: an unwritable file is bad input.
      try {
        compare::write_voxel_models(evaluation, voxels_out->string());
      } catch (const std::runtime_error& e) {
        throw core::OptionError("voxels_out", e.what());
      }
    }
  }
  py::dict out = to_python(evaluation.result);
  if (options.cameras_file.empty()) out["cameras_file"] = py::none();
  if (fractions) {
    exact_fractions_to_python(
        options.pipeline == core::Pipeline::both ? out["exact"].cast<py::dict>() : out);
  }
  return out;
}

// ---- voxel grid, model, labels ---------------------------------------------------------------

py::dict grid_dict(const voxel::Grid& grid) {
  const auto& n = grid.n;
  return py::dict(
      "origin"_a = py::make_tuple(grid.area.min.x(), grid.area.min.y(), grid.area.min.z()),
      "spacing"_a = py::make_tuple(grid.step.x(), grid.step.y(), grid.step.z()),
      "resolution"_a = py::make_tuple(n[0], n[1], n[2]),
      "shape"_a = py::make_tuple(n[2], n[1], n[0]),
      "index_order"_a = "array[k, j, i] is voxel i + nx*(j + ny*k)");
}

py::dict voxel_grid(const PyScene& scene, const py::object& resolution) {
  std::array<int, 3> n = resolution_argument(resolution);
  if (n == std::array<int, 3>{0, 0, 0}) n = scene.scene->voxels;
  return grid_dict(voxel::make_grid(scene.scene->area, n));
}

/// The evaluator of the voxel functions (built with the GIL released by the caller).
voxel::VoxelEvaluator make_evaluator(const core::Scene& scene, const std::string& mode,
                                     const std::array<int, 3>& resolution, int threads) {
  voxel::VoxelOptions options;
  options.mode = enum_argument<core::LabelMode>("mode", mode);
  options.resolution = resolution;
  options.threads = resolved_threads(threads);
  return voxel::VoxelEvaluator(scene, options);
}

py::array_t<bool> voxel_model(const PyScene& scene, const py::object& cameras,
                              const std::optional<std::pair<int, int>>& state,
                              const std::string& mode, const py::object& resolution,
                              const std::optional<std::string>& fov, int threads) {
  const core::Scene voxel_scene = scene_with_fov(*scene.scene, fov);
  const std::array<int, 3> n_given = resolution_argument(resolution);
  threads_argument(threads);
  std::string file;
  const core::CameraConfig config = cameras_argument(cameras, voxel_scene, file);
  std::vector<int> indices;
  if (state) {
    indices.push_back(state_argument(voxel_scene, *state));
  } else {
    for (std::size_t i = 0; i < core::states(voxel_scene).size(); ++i) {
      indices.push_back(static_cast<int>(i));
    }
  }
  enum_argument<core::LabelMode>("mode", mode);
  std::vector<std::vector<std::uint8_t>> models;
  std::array<int, 3> n{};
  {
    py::gil_scoped_release release;
    const voxel::VoxelEvaluator evaluator = make_evaluator(voxel_scene, mode, n_given, threads);
    n = evaluator.grid().n;
    if (state) {
      models.push_back(evaluator.model(config, indices.front()));
    } else {
      models = evaluator.models(config);  // one labelling for every state
    }
  }
  std::vector<py::ssize_t> shape{n[2], n[1], n[0]};
  if (!state) shape.insert(shape.begin(), static_cast<py::ssize_t>(models.size()));
  py::array_t<bool> out(shape);
  bool* data = out.mutable_data();
  for (const auto& model : models)
    data = std::transform(model.begin(), model.end(), data, [](std::uint8_t b) { return b != 0; });
  return out;
}

py::array_t<std::uint8_t> labels(const PyScene& scene, const py::object& cameras,
                                 const std::pair<int, int>& state, std::optional<int> camera,
                                 const std::string& mode, const py::object& resolution,
                                 const std::optional<std::string>& fov, int threads) {
  const core::Scene voxel_scene = scene_with_fov(*scene.scene, fov);
  const std::array<int, 3> n_given = resolution_argument(resolution);
  threads_argument(threads);
  enum_argument<core::LabelMode>("mode", mode);
  std::string file;
  const core::CameraConfig config = cameras_argument(cameras, voxel_scene, file);
  const int index = state_argument(voxel_scene, state);
  if (camera && (*camera < 0 || *camera >= static_cast<int>(config.size()))) {
    throw core::OptionError("camera", "must lie in [0, " + std::to_string(config.size() - 1) +
                                          "] (one of the scene's " + std::to_string(config.size()) +
                                          " cameras)");
  }
  std::vector<std::vector<voxel::Label>> per_camera;
  std::array<int, 3> n{};
  {
    py::gil_scoped_release release;
    const voxel::VoxelEvaluator evaluator = make_evaluator(voxel_scene, mode, n_given, threads);
    n = evaluator.grid().n;
    for (std::size_t c = 0; c < config.size(); ++c) {
      if (!camera || *camera == static_cast<int>(c)) {
        per_camera.push_back(evaluator.labels(config[c], index, static_cast<int>(c)));
      }
    }
  }
  std::vector<py::ssize_t> shape{n[2], n[1], n[0]};
  if (!camera) shape.insert(shape.begin(), static_cast<py::ssize_t>(per_camera.size()));
  py::array_t<std::uint8_t> out(shape);
  std::uint8_t* data = out.mutable_data();
  for (const auto& labels : per_camera) {
    data = std::transform(labels.begin(), labels.end(), data,
                          [](voxel::Label l) { return static_cast<std::uint8_t>(l); });
  }
  return out;
}

}  // namespace

}  // namespace camplace::python

PYBIND11_MODULE(camplace, m) {
  using namespace camplace;
  using namespace camplace::python;
  m.doc() =
      "camplace: camera placement for human-robot work cells (visual hull distance).\n\n"
      "A thin layer over the C++ library: the same computations and the same JSON as the\n"
      "`camplace` command-line tool (docs/files.md). Lengths in metres, angles in degrees,\n"
      "Err in m². Bad input raises ValueError with the command line's message (file, entry,\n"
      "reason). The GIL is released while C++ works.";
  m.attr("__version__") = "0.1.0";
  m.attr("FREE") = static_cast<int>(voxel::Label::free);
  m.attr("OCCUPIED") = static_cast<int>(voxel::Label::occupied);
  m.attr("UNDETECTABLE") = static_cast<int>(voxel::Label::undetectable);

  // Bad user input: the message `camplace` prints after "error: ".
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const core::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  py::class_<PyScene>(m, "Scene",
                      "A scene (docs/scene-format.md), loaded and validated by load_scene().")
      .def_property_readonly(
          "file", [](const PyScene& s) { return s.scene->file; }, "The path it was loaded from.")
      .def_property_readonly(
          "area",
          [](const PyScene& s) {
            const auto& a = s.scene->area;
            return py::dict("min"_a = py::make_tuple(a.min.x(), a.min.y(), a.min.z()),
                            "max"_a = py::make_tuple(a.max.x(), a.max.y(), a.max.z()));
          },
          "The surveillance area S: {'min': (x, y, z), 'max': (x, y, z)} in m, world frame.")
      .def_property_readonly(
          "voxels",
          [](const PyScene& s) {
            return py::make_tuple(s.scene->voxels[0], s.scene->voxels[1], s.scene->voxels[2]);
          },
          "The scene's voxel resolution (nx, ny, nz).")
      .def_property_readonly(
          "camera_count", [](const PyScene& s) { return s.scene->cameras.count; },
          "The number of cameras n.")
      .def_property_readonly(
          "states",
          [](const PyScene& s) {
            py::list out;
            for (const core::StateIndex& st : core::states(*s.scene)) {
              const core::TimeStep& step = s.scene->time_steps[st.time_step];
              out.append(py::dict("time_step"_a = st.time_step, "event"_a = st.event,
                                  "t"_a = step.t, "weight"_a = step.events[st.event].weight));
            }
            return out;
          },
          "The states in Err's order: [{'time_step': h, 'event': l, 't': s, 'weight': ω}].")
      .def_property_readonly(
          "json", [](const PyScene& s) { return to_python(s.json, s.scene->file); },
          "The scene file's content as dicts and lists (a fresh copy on each access); ValueError\n"
          "when it nests more than 1000 levels deep (an ignored \"description\" may).")
      .def("__repr__", [](const PyScene& s) {
        const auto& n = s.scene->voxels;
        return "<camplace.Scene '" + s.scene->file +
               "': " + std::to_string(s.scene->cameras.count) + " cameras, " +
               std::to_string(core::states(*s.scene).size()) + " states, voxels " +
               std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" + std::to_string(n[2]) + ">";
      });

  m.def("load_scene", &load_scene, "path"_a,
        R"(Loads and validates a scene file (docs/scene-format.md).

path: str or path-like. Returns a Scene. Raises ValueError naming the file, the entry (a JSON
pointer) and the reason, exactly as `camplace evaluate` reports it.)");

  m.def("load_cameras", &load_cameras, "path"_a, "scene"_a = py::none(),
        R"(Reads a camera file (docs/files.md, "Camera files"; a run file is one too).

Returns the cameras as a list of dicts, as the file has them: {'position': [x, y, z] (m),
'yaw_deg': ψ, 'pitch_deg': θ, 'roll_deg': ρ (degrees; roll_deg optional, default 0), and 'name'
and 'model' where given}. With `scene` the count must be
the scene's camera count. Raises ValueError (file, entry, reason) on a bad file. Every function
taking `cameras` accepts this list, a camera file's path or a dict with a 'cameras' list.)");

  m.def("evaluate", &evaluate, "scene"_a, "cameras"_a, py::kw_only(), "pipeline"_a = "voxel",
        "mode"_a = "conservative", "resolution"_a = py::none(), "refine"_a = 0, "threads"_a = 0,
        "fractions"_a = false, "export_mesh"_a = py::none(), "voxels_out"_a = py::none(),
        R"(Err of one camera configuration, state by state: `camplace evaluate --json`.

scene: a Scene. cameras: a camera file's path, a list of camera dicts (load_cameras) or a dict
with a 'cameras' list (a run file's content).
pipeline: 'voxel', 'exact' (CGAL Nef, inscribed pyramids) or 'both' (the voxel pipeline then
uses the pyramid too). mode: 'center' or 'conservative' (voxel labelling).
resolution: None (the scene's), (nx, ny, nz) or 'NXxNYxNZ'. refine: conservative mode,
adaptive refinement levels as `--refine` (0 = none). threads: states evaluated in parallel,
0 = one per core.
fractions: exact pipeline: add 'd_true_sq_exact', 'd_model_sq_exact' (m²) and
'model_volume_exact' (m³) to each state as fractions.Fraction.
export_mesh: exact pipeline: a directory receiving each state's model and each camera's pyramid
as OFF files. voxels_out: voxel pipeline: a NAME.npy file receiving `--voxels-out`'s files (NAME.npy, NAME.json, NAME.vtk).

Returns a dict with exactly the keys and values of `camplace evaluate --json` (docs/files.md):
'err' (m²), 'states' [{'time_step', 'event', 'weight', 'd_true' (m), 'd_model' (m),
'model_volume' (m³), 'components', 'components_removed'}], 'timing_ms', 'tolerance' (m²), ...;
'cameras_file' is the path, or None for cameras given as a list or dict.)");

  m.def("voxel_grid", &voxel_grid, "scene"_a, "resolution"_a = py::none(),
        R"(The voxel grid over the scene's area S: the companion of voxel_model() and labels().

Returns {'origin': S's lowest corner (x, y, z) in m, 'spacing': the voxel edges (sx, sy, sz) in
m, 'resolution': (nx, ny, nz), 'shape': (nz, ny, nx), 'index_order'}. Element [k, j, i] of a
voxel array is the box origin + (i, j, k)·spacing to origin + (i+1, j+1, k+1)·spacing.)");

  m.def("voxel_model", &voxel_model, "scene"_a, "cameras"_a, py::kw_only(),
        "state"_a = std::make_pair(0, 0), "mode"_a = "conservative", "resolution"_a = py::none(),
        "fov"_a = py::none(), "threads"_a = 0,
        R"(The voxel model M after the plausibility filter: what `evaluate --voxels-out` writes.

Returns a numpy bool array of shape (nz, ny, nx), indexed [k, j, i] (z, y, x): True = voxel in
M. voxel_grid(scene, resolution) gives its origin and spacing (m). state: (h, l), a time step
and event of Scene.states; None = every state, shape (states, nz, ny, nx) in Scene.states'
order. fov: None (the scene's), 'cone' or 'pyramid' (`evaluate --pipeline both` models with
'pyramid'). mode, resolution, threads as in evaluate().)");

  m.def("labels", &labels, "scene"_a, "cameras"_a, py::kw_only(), "state"_a = std::make_pair(0, 0),
        "camera"_a = py::none(), "mode"_a = "conservative", "resolution"_a = py::none(),
        "fov"_a = py::none(), "threads"_a = 0,
        R"(Each camera's voxel labels κ in one state (SPEC §3).

Returns a numpy uint8 array of shape (cameras, nz, ny, nx), or (nz, ny, nx) for one `camera`
index, indexed [k, j, i] like voxel_model(): FREE (0), OCCUPIED (1) or UNDETECTABLE (2).
Conservative mode labels a voxel FREE only when every point of it is free. state: (h, l).
fov, mode, resolution, threads as in voxel_model().)");

  bind_optimize(m);

  bind_generate(m);
}
