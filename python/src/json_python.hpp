#pragma once
// Conversions between nlohmann::json and Python objects (dict, list, str, int, float, bool,
// None), for the results the module returns and the camera lists it takes.
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>

namespace camplace::python {

/// The Python object of a JSON value: objects become dicts (in the JSON's key order), arrays
/// lists, numbers int or float, null None.
pybind11::object to_python(const nlohmann::json& j);
pybind11::object to_python(const nlohmann::ordered_json& j);

/// The JSON value of a Python object built from dicts (string keys), sequences (list, tuple,
/// numpy arrays), str, bool, int, float (and numpy scalars) and None. Throws
/// pybind11::type_error naming `where` for anything else.
nlohmann::json from_python(pybind11::handle object, const std::string& where);

}  // namespace camplace::python
