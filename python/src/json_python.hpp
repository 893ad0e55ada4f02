#pragma once
// Conversions between nlohmann::json and Python objects (dict, list, str, int, float, bool,
// None), for the results the module returns and the camera lists it takes.
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>
#include <string>

namespace camplace::python {

/// The deepest nesting of arrays and objects (lists and dicts) converted either way: far above
/// any scene, camera list or result, far below what would exhaust the stack.
constexpr int kMaxDepth = 1000;

/// The Python object of a JSON value: objects become dicts (in the JSON's key order), arrays
/// lists, numbers int or float, null None. Throws pybind11::value_error naming `where` (what
/// the value is, e.g. its file) when it nests deeper than kMaxDepth.
pybind11::object to_python(const nlohmann::json& j, const std::string& where = "result");
pybind11::object to_python(const nlohmann::ordered_json& j, const std::string& where = "result");

/// The JSON value of a Python object built from dicts (string keys), sequences (list, tuple,
/// numpy arrays), str, bool, int, float (and numpy scalars) and None, for the argument `where`.
/// Throws pybind11::type_error naming `where` and the entry for anything else, and
/// pybind11::value_error for a dict or sequence that contains itself or nesting deeper than
/// kMaxDepth.
nlohmann::json from_python(pybind11::handle object, const std::string& where);

}  // namespace camplace::python
