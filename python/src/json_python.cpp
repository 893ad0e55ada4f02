#include "json_python.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_set>

namespace py = pybind11;

namespace camplace::python {

namespace {

std::string nested_too_deep(const std::string& where, const char* containers) {
  return where + ": " + containers + " nested more than " + std::to_string(kMaxDepth) +
         " levels deep";
}

std::string type_name(py::handle object) {
  return py::str(py::type::of(object).attr("__name__")).cast<std::string>();
}

// Recursive: `depth` arrays and objects are open around j. A file's content may nest deeper than
// the stack allows (an ignored "description" 100,000 levels deep is valid); kMaxDepth stops it.
template <class Json>
py::object convert(const Json& j, const std::string& where, int depth) {
  using Type = nlohmann::detail::value_t;
  if (j.is_structured() && depth >= kMaxDepth)
    throw py::value_error(nested_too_deep(where, "arrays and objects"));
  switch (j.type()) {
    case Type::null:
      return py::none();
    case Type::boolean:
      return py::bool_(j.template get<bool>());
    case Type::number_integer:
      return py::int_(j.template get<std::int64_t>());
    case Type::number_unsigned:
      return py::int_(j.template get<std::uint64_t>());
    case Type::number_float:
      return py::float_(j.template get<double>());
    case Type::string:
      return py::str(j.template get_ref<const std::string&>());
    case Type::array: {
      py::list list;
      for (const auto& element : j) list.append(convert(element, where, depth + 1));
      return std::move(list);
    }
    case Type::object: {
      py::dict dict;
      for (const auto& [key, value] : j.items())
        dict[py::str(key)] = convert(value, where, depth + 1);
      return std::move(dict);
    }
    default:
      throw std::logic_error("internal error: a JSON value of no Python type");
  }
}

/// A conversion from Python under way: the argument's name and the dicts and sequences being
/// converted, i.e. the path from the argument down to the current object.
struct FromPython {
  std::string argument;
  std::unordered_set<PyObject*> open;
};

/// Marks the dict or sequence `object` at `where` as being converted; ValueError when it already
/// is (it contains itself: JSON has no cycles) or when kMaxDepth of them are open already (the
/// recursion would exhaust the stack long before a list nested 200,000 deep ended).
void enter(py::handle object, const std::string& where, FromPython& conversion) {
  if (conversion.open.size() >= static_cast<std::size_t>(kMaxDepth))
    throw py::value_error(nested_too_deep(conversion.argument, "lists and dicts"));
  if (!conversion.open.insert(object.ptr()).second)
    throw py::value_error(where + ": a " + type_name(object) + " that contains itself");
}

nlohmann::json convert(py::handle object, const std::string& where, FromPython& conversion) {
  if (object.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(object)) return object.cast<bool>();
  if (py::isinstance<py::str>(object)) return object.cast<std::string>();
  if (py::isinstance<py::float_>(object)) return object.cast<double>();
  // int and numpy's integer scalars (PyIndex_Check: they have __index__).
  if (PyIndex_Check(object.ptr())) {
    const py::int_ value = py::reinterpret_steal<py::int_>(PyNumber_Index(object.ptr()));
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
    if (overflow != 0) {
      throw py::value_error(where + ": integer " + py::repr(value).cast<std::string>() +
                            " is too large");
    }
    return v;
  }
  if (py::isinstance<py::dict>(object)) {
    enter(object, where, conversion);
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [key, value] : object.cast<py::dict>()) {
      if (!py::isinstance<py::str>(key)) {
        throw py::type_error(where + ": dictionary keys must be strings, not " + type_name(key));
      }
      const std::string name = key.cast<std::string>();
      out[name] = convert(value, where + "/" + name, conversion);
    }
    conversion.open.erase(object.ptr());
    return out;
  }
  if (py::isinstance<py::sequence>(object)) {
    enter(object, where, conversion);
    nlohmann::json out = nlohmann::json::array();
    const py::sequence sequence = py::reinterpret_borrow<py::sequence>(object);
    for (std::size_t i = 0; i < sequence.size(); ++i) {
      out.push_back(convert(sequence[i], where + "/" + std::to_string(i), conversion));
    }
    conversion.open.erase(object.ptr());
    return out;
  }
  // numpy's floating scalars other than float64 (which is a float).
  if (py::hasattr(object, "__float__"))
    return py::float_(py::reinterpret_borrow<py::object>(object)).cast<double>();
  throw py::type_error(where + ": cannot use a " + type_name(object) +
                       " here (expected dict, list, str, number, bool or None)");
}

}  // namespace

py::object to_python(const nlohmann::json& j, const std::string& where) {
  return convert(j, where, 0);
}
py::object to_python(const nlohmann::ordered_json& j, const std::string& where) {
  return convert(j, where, 0);
}

nlohmann::json from_python(py::handle object, const std::string& where) {
  FromPython conversion{where, {}};
  return convert(object, where, conversion);
}

}  // namespace camplace::python
