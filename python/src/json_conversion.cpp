#include "json_conversion.hpp"

#include <string>

#include "mimpact/common/error.hpp"
#include "mimpact/kernel/json_document.hpp"

namespace py = pybind11;

namespace mimpact::python {

std::string short_repr(const py::handle& value) {
  std::string text;
  try {
    text = py::repr(value).cast<std::string>();
  } catch (const py::error_already_set&) {
    text = "<" + py::str(py::type::of(value).attr("__name__")).cast<std::string>() + ">";
  }
  return text.size() <= 80
             ? text
             : text.substr(0, 80) + "... (" + std::to_string(text.size()) + " characters)";
}

namespace {

// A Python int as JSON: an integer when it fits 64 bits, else the nearest double, refused
// beyond double precision
nlohmann::ordered_json integer(const py::handle& value, const std::string& where) {
  int overflow = 0;
  const long long small = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
  if (overflow == 0 && !PyErr_Occurred()) return small;
  PyErr_Clear();
  const double large = PyLong_AsDouble(value.ptr());
  if (large == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();
    throw InvalidInput(kernel::shortened_path(where) + " = " + short_repr(value) +
                       " is beyond double precision; allowed: a finite number of magnitude at "
                       "most 1.8e308");
  }
  return large;
}

nlohmann::ordered_json convert(const py::handle& value, const std::string& where, int depth) {
  if (value.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) return integer(value, where);
  if (py::isinstance<py::float_>(value)) return value.cast<double>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  const bool container = py::isinstance<py::dict>(value) || py::isinstance<py::list>(value) ||
                         py::isinstance<py::tuple>(value);
  if (container && depth >= kernel::kMaxJsonDepth)
    throw InvalidInput(kernel::shortened_path(where) + " nests dicts and lists deeper than " +
                       std::to_string(kernel::kMaxJsonDepth) +
                       " levels (or contains itself); allowed: at most " +
                       std::to_string(kernel::kMaxJsonDepth));
  if (py::isinstance<py::dict>(value)) {
    nlohmann::ordered_json object = nlohmann::ordered_json::object();
    for (const auto& [key, item] : value.cast<py::dict>()) {
      if (!py::isinstance<py::str>(key))
        throw InvalidInput(kernel::shortened_path(where) +
                           ": the keys of a scene are strings; got " + short_repr(key));
      const std::string name = key.cast<std::string>();
      object[name] = convert(item, where + "." + name, depth + 1);
    }
    return object;
  }
  // NumPy: arrays and their scalars through their Python equivalents
  if (!container && py::hasattr(value, "tolist") && py::hasattr(value, "dtype"))
    return convert(value.attr("tolist")(), where, depth);
  if (container) {
    nlohmann::ordered_json array = nlohmann::ordered_json::array();
    std::size_t index = 0;
    for (const auto& item : value)
      array.push_back(convert(item, where + "[" + std::to_string(index++) + "]", depth + 1));
    return array;
  }
  throw InvalidInput(kernel::shortened_path(where) + " = " + short_repr(value) + " (" +
                     py::str(py::type::of(value).attr("__name__")).cast<std::string>() +
                     ") is not allowed; allowed: dict, list, tuple, str, bool, int, float, None or "
                     "a NumPy number or array");
}

}  // namespace

nlohmann::ordered_json to_json(const py::handle& value, const std::string& where) {
  return convert(value, where, 0);
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
