// The Python module's generate() and scene_families(): `camplace generate` (camplace::scenes).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "bindings.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/scenes/generator.hpp"
#include "json_python.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace camplace::python {

namespace {

py::dict generate(const std::string& family, std::optional<int> param, unsigned seed,
                  const std::optional<std::filesystem::path>& out) {
  std::string text;
  {
    py::gil_scoped_release release;
    if (out) {
      scenes::write_generated_scene(family, param, seed, out->string());
      text = core::read_json_file(out->string()).dump();
    } else {
      text = scenes::generate_scene_json(family, param, seed);
    }
  }
  return to_python(nlohmann::json::parse(text));
}

py::list scene_families() {
  py::list out;
  for (const scenes::SceneFamily& f : scenes::scene_families()) {
    py::dict d("name"_a = f.name, "has_param"_a = f.has_param, "random"_a = f.random,
               "what"_a = f.what);
    d["param_range"] =
        f.has_param ? py::object(py::make_tuple(f.min_param, f.max_param)) : py::object(py::none());
    out.append(d);
  }
  return out;
}

}  // namespace

void bind_generate(py::module_& m) {
  m.def("generate", &generate, "family"_a, "param"_a = py::none(), "seed"_a = 1u,
        "out"_a = py::none(),
        R"(A scene of the paper's examinations (SPEC §9): `camplace generate`.

family: a name of scene_families(); param: its parameter i (None for the families without
one); seed: the random placements' seed. With `out` the scene is also written to that file
(after checking that it loads). Returns the scene file's content as a dict.)");

  m.def("scene_families", &scene_families,
        "The families generate() knows: [{'name', 'has_param', 'param_range' (lo, hi) or None, "
        "'random', 'what'}].");
}

}  // namespace camplace::python
