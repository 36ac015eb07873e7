#pragma once

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "mimpact/common/fields.hpp"
#include "mimpact/kernel/json_document.hpp"

namespace mimpact::kernel {

// Named settings, e.g. {"delta_p": 1e-6}: the parameters a plugin is created with by name
// (registry.hpp), and the objects of a scene file. The keys are the fields an options
// struct lists in its visit_fields (common/fields.hpp): read_fields fills the struct from
// them, to_parameters writes them back. A JSON object, so that a scene, a C++ caller and a
// Python dict hand over the same thing.
using Parameters = nlohmann::json;

// Where parameters come from, for messages: "NAME: PATH = VALUE is invalid; allowed: ...", or
// "NAME:LINE:COLUMN: PATH = ..." when the locations of a JSON text are known.
struct ParameterSource {
  std::string name;                          // "impact problem \"lzb\"", or a scene file's path
  std::string path;                          // where the object sits in it: "impact"; "" at the top
  std::string_view unknown = "parameter";    // what a key is called in "unknown parameter \"x\""
  std::string_view top = {};                 // what the top level is called, e.g. "the top level"
  const JsonLocations* locations = nullptr;  // of the text the parameters were read from

  // "NAME" or "NAME:LINE:COLUMN" for the field at `field_path`
  std::string owner(std::string_view field_path) const {
    const std::string at = locations ? locations->of(field_path) : std::string();
    return at.empty() ? name : name + ":" + at;
  }
};

namespace detail {

// The names a struct's field list holds, in order.
struct FieldNames {
  std::vector<std::string_view> names;
  template <class T>
  void operator()(std::string_view name, const T&, const Allowed& = {}) {
    names.push_back(name);
  }
};

// Reads an object into a struct through its field list: each key must be a field (checked
// first, so that a misspelt key is named rather than the field it misses), each value of the
// field's type and in its range; fields marked needed() must be present.
class FieldReader {
 public:
  FieldReader(const Parameters& object, std::string path, const ParameterSource& source)
      : object_(object), path_(std::move(path)), source_(source) {
    if (!object_.is_object() && !object_.is_null())
      fail(path_, wrong_type(where(), object_) + "; allowed: an object {...}");
  }

  // Refuses a key that is not among `known`, suggesting the closest field.
  void check_keys(const std::vector<std::string_view>& known) const {
    if (!object_.is_object()) return;
    for (const auto& item : object_.items()) {
      if (std::find(known.begin(), known.end(), item.key()) != known.end()) continue;
      std::string allowed;
      for (std::string_view name : known)
        allowed += (allowed.empty() ? "" : ", ") + std::string(name);
      const std::string in = path_.empty() && source_.top.empty() ? "" : " in " + where();
      const std::string key = json_excerpt(Parameters(item.key()), 60);
      const std::string guess = fields::closest_name(item.key(), known);
      fail(fields::join(path_, item.key()),
           "unknown " + std::string(source_.unknown) + " " + key + in +
               (guess.empty() ? "" : " (did you mean \"" + guess + "\"?)") +
               "; allowed: " + (allowed.empty() ? "none" : allowed));
    }
  }

  template <class T>
  void operator()(std::string_view name, T& value, const Allowed& allowed = {}) {
    const std::string path = fields::join(path_, name);
    if (object_.is_null() || !object_.contains(name)) {
      if (allowed.required) fail(path_, "missing field " + path);
      return;
    }
    read(object_.at(std::string(name)), path, value, allowed);
  }

 private:
  // "PATH = VALUE (a TYPE) is invalid", the value cut to 80 characters
  static std::string wrong_type(const std::string& path, const Parameters& value) {
    const std::string type = value.type_name();
    const bool vowel = type.find_first_of("aeiou") == 0;
    return path + " = " + json_excerpt(value) + " (" + (vowel ? "an " : "a ") + type +
           ") is invalid";
  }

  template <class T>
  void read(const Parameters& value, const std::string& path, T& out, const Allowed& allowed) {
    if constexpr (fields::Number<T>) {
      if (!value.is_number())
        fail(path, wrong_type(path, value) + "; allowed: a number, " +
                       fields::describe(allowed, fields::Integer<T>));
      const double number = value.get<double>();
      checker(path).template check_number<T>(path, number, allowed);
      out = T(number);
    } else if constexpr (std::is_same_v<T, bool>) {
      if (!value.is_boolean()) fail(path, wrong_type(path, value) + "; allowed: true or false");
      out = value.get<bool>();
    } else if constexpr (std::is_same_v<T, std::string>) {
      if (!value.is_string()) fail(path, wrong_type(path, value) + "; allowed: a string");
      out = value.get<std::string>();
    } else if constexpr (fields::NamedEnum<T>) {
      const auto parsed =
          value.is_string() ? enum_from_name<T>(value.get<std::string>()) : std::nullopt;
      if (!parsed)
        fail(path,
             path + " = " + json_excerpt(value) + " is invalid; allowed: " + enum_choices<T>());
      out = *parsed;
    } else if constexpr (std::is_same_v<T, Parameters>) {
      out = value;  // handed on as it is, to whoever reads it next
    } else if constexpr (fields::IsOptional<T>::value) {
      if (value.is_null()) {
        out.reset();
        return;
      }
      if (!out) out.emplace();
      read(value, path, *out, allowed);
    } else if constexpr (fields::IsVector<T>::value) {
      if (!value.is_array()) fail(path, wrong_type(path, value) + "; allowed: an array [...]");
      out.assign(value.size(), typename T::value_type{});
      for (std::size_t k = 0; k < value.size(); ++k)
        read(value[k], fields::element(path, k), out[k], allowed);
    } else {
      static_assert(fields::Described<T>,
                    "a field must be a number, bool, string, named enum, "
                    "struct with visit_fields, optional or vector");
      FieldReader nested(value, path, source_);
      FieldNames names;
      T::visit_fields(out, names);
      nested.check_keys(names.names);
      T::visit_fields(out, nested);
    }
  }

  fields::Validator checker(std::string_view path) const {
    return fields::Validator(source_.owner(path), "");
  }
  std::string where() const {
    return path_.empty() ? (source_.top.empty() ? "the parameters" : std::string(source_.top))
                         : path_;
  }
  [[noreturn]] void fail(std::string_view path, const std::string& what) const {
    checker(path).fail(what);
  }

  const Parameters& object_;
  std::string path_;
  const ParameterSource& source_;
};

// Writes every field of a struct.
class FieldWriter {
 public:
  explicit FieldWriter(Parameters& object) : object_(object) {}

  template <class T>
  void operator()(std::string_view name, const T& value, const Allowed& = {}) {
    if constexpr (fields::IsOptional<T>::value) {
      if (value) object_[std::string(name)] = write(*value);
    } else {
      object_[std::string(name)] = write(value);
    }
  }

  template <class T>
  static Parameters write(const T& value) {
    if constexpr (fields::NamedEnum<T>) {
      return std::string(enum_name(value));
    } else if constexpr (fields::IsVector<T>::value) {
      Parameters array = Parameters::array();
      for (const auto& element : value) array.push_back(write(element));
      return array;
    } else if constexpr (fields::Described<T>) {
      Parameters object = Parameters::object();
      FieldWriter writer(object);
      T::visit_fields(value, writer);
      return object;
    } else {
      return Parameters(value);
    }
  }

 private:
  Parameters& object_;
};

}  // namespace detail

// Reads the fields of `options` that `parameters` holds (the others keep their values):
// throws InvalidInput naming the source, the field's path, its value and what is allowed, for
// an unknown key, a value of the wrong type or out of range, or a missing needed field.
template <fields::Described T>
void read_fields(const Parameters& parameters, T& options, const ParameterSource& source) {
  detail::FieldReader reader(parameters, source.path, source);
  detail::FieldNames names;
  T::visit_fields(options, names);
  reader.check_keys(names.names);
  T::visit_fields(options, reader);
}

// A default-constructed T with the fields `parameters` holds.
template <fields::Described T>
T options_from(const Parameters& parameters, const ParameterSource& source) {
  T options;
  read_fields(parameters, options, source);
  return options;
}

// Every field of `options` (optional ones when present), so that
// options_from<T>(to_parameters(options), ...) gives `options` back.
template <fields::Described T>
Parameters to_parameters(const T& options) {
  return detail::FieldWriter::write(options);
}

}  // namespace mimpact::kernel
