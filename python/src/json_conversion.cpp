#include "json_conversion.hpp"

#include <string>

#include "mimpact/common/error.hpp"

namespace py = pybind11;

namespace mimpact::python {

nlohmann::ordered_json to_json(const py::handle& value, const std::string& where) {
  if (value.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) return value.cast<long long>();
  if (py::isinstance<py::float_>(value)) return value.cast<double>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::dict>(value)) {
    nlohmann::ordered_json object = nlohmann::ordered_json::object();
    for (const auto& [key, item] : value.cast<py::dict>()) {
      if (!py::isinstance<py::str>(key))
        throw InvalidInput(where + ": the keys of a scene are strings; got " +
                           py::repr(key).cast<std::string>());
      const std::string name = key.cast<std::string>();
      object[name] = to_json(item, where + "." + name);
    }
    return object;
  }
  // NumPy: arrays and their scalars through their Python equivalents
  if (py::hasattr(value, "tolist") && py::hasattr(value, "dtype"))
    return to_json(value.attr("tolist")(), where);
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    nlohmann::ordered_json array = nlohmann::ordered_json::array();
    std::size_t index = 0;
    for (const auto& item : value)
      array.push_back(to_json(item, where + "[" + std::to_string(index++) + "]"));
    return array;
  }
  throw InvalidInput(where + " = " + py::repr(value).cast<std::string>() + " (" +
                     py::str(py::type::of(value).attr("__name__")).cast<std::string>() +
                     ") is not allowed; allowed: dict, list, tuple, str, bool, int, float, None or "
                     "a NumPy number or array");
}

py::object from_json(const nlohmann::ordered_json& value) {
  switch (value.type()) {
    case nlohmann::ordered_json::value_t::null:
      return py::none();
    case nlohmann::ordered_json::value_t::boolean:
      return py::bool_(value.get<bool>());
    case nlohmann::ordered_json::value_t::number_integer:
      return py::int_(value.get<long long>());
    case nlohmann::ordered_json::value_t::number_unsigned:
      return py::int_(value.get<unsigned long long>());
    case nlohmann::ordered_json::value_t::number_float:
      return py::float_(value.get<double>());
    case nlohmann::ordered_json::value_t::string:
      return py::str(value.get<std::string>());
    case nlohmann::ordered_json::value_t::array: {
      py::list list;
      for (const auto& item : value) list.append(from_json(item));
      return list;
    }
    default: {  // object
      py::dict dict;
      for (const auto& [key, item] : value.items()) dict[py::str(key)] = from_json(item);
      return dict;
    }
  }
}

}  // namespace mimpact::python
