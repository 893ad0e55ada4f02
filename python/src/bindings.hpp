#pragma once
// What the files of the Python module share: the Scene object, argument conversions and the
// functions that add each file's bindings to the module. Private to python/.
#include <pybind11/pybind11.h>

#include <array>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "camplace/core/error.hpp"
#include "camplace/core/names.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::python {

/// A loaded scene and the JSON text it came from.
struct PyScene {
  std::shared_ptr<const core::Scene> scene;
  nlohmann::json json;
};

/// The enum value named `name` of the option `option`; throws core::OptionError listing the
/// names otherwise.
template <class Enum>
Enum enum_argument(const std::string& option, const std::string& name) {
  if (const auto value = core::from_name<Enum>(name)) return *value;
  throw core::OptionError(option, "unknown " + option + " \"" + name + "\" (expected " +
                                      core::names_listed<Enum>() + ")");
}

/// None (the scene's), "NXxNYxNZ" or (nx, ny, nz); throws core::OptionError("resolution").
std::array<int, 3> resolution_argument(const pybind11::object& value);

/// Adds optimize() and algorithms() (optimize_bindings.cpp).
void bind_optimize(pybind11::module_& m);

/// Adds generate() and scene_families(), the scene generator (generate_bindings.cpp).
void bind_generate(pybind11::module_& m);

}  // namespace camplace::python
