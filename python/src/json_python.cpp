#include "json_python.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>

namespace py = pybind11;

namespace camplace::python {

namespace {

template <class Json>
py::object convert(const Json& j) {
  using Type = nlohmann::detail::value_t;
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
      for (const auto& element : j) list.append(convert(element));
      return std::move(list);
    }
    case Type::object: {
      py::dict dict;
      for (const auto& [key, value] : j.items()) dict[py::str(key)] = convert(value);
      return std::move(dict);
    }
    default:
      throw std::logic_error("internal error: a JSON value of no Python type");
  }
}

}  // namespace

py::object to_python(const nlohmann::json& j) { return convert(j); }
py::object to_python(const nlohmann::ordered_json& j) { return convert(j); }

nlohmann::json from_python(py::handle object, const std::string& where) {
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
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [key, value] : object.cast<py::dict>()) {
      if (!py::isinstance<py::str>(key)) {
        throw py::type_error(where + ": dictionary keys must be strings, not " +
                             py::str(py::type::of(key).attr("__name__")).cast<std::string>());
      }
      const std::string name = key.cast<std::string>();
      out[name] = from_python(value, where + "/" + name);
    }
    return out;
  }
  if (py::isinstance<py::sequence>(object)) {
    nlohmann::json out = nlohmann::json::array();
    const py::sequence sequence = py::reinterpret_borrow<py::sequence>(object);
    for (std::size_t i = 0; i < sequence.size(); ++i) {
      out.push_back(from_python(sequence[i], where + "/" + std::to_string(i)));
    }
    return out;
  }
  // numpy's floating scalars other than float64 (which is a float).
  if (py::hasattr(object, "__float__"))
    return py::float_(py::reinterpret_borrow<py::object>(object)).cast<double>();
  throw py::type_error(where + ": cannot use a " +
                       py::str(py::type::of(object).attr("__name__")).cast<std::string>() +
                       " here (expected dict, list, str, number, bool or None)");
}

}  // namespace camplace::python
