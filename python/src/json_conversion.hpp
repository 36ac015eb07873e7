#pragma once

#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>
#include <string>

// Python objects to JSON and back: a scene given as a dict goes through the same parser, with
// the same messages, as a scene file.
namespace mimpact::python {

// dict, list, tuple, str, bool, int, float, None and NumPy numbers and arrays; any other type
// throws InvalidInput (ValueError in Python) naming the value's place, `where` ("scene.chain").
nlohmann::ordered_json to_json(const pybind11::handle& value, const std::string& where);

pybind11::object from_json(const nlohmann::ordered_json& value);

// repr(value) cut to 80 characters, for messages; a repr that fails is named by its type.
std::string short_repr(const pybind11::handle& value);

}  // namespace mimpact::python
