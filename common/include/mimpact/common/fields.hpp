#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "mimpact/common/error.hpp"

// Options and scene structs list their fields once, in a static member
//
//   template <class Self, class Visit>
//   static void visit_fields(Self& self, Visit&& field) {
//     field("event_tolerance", self.event_tolerance, positive("s"));
//     ...
//   }
//
// (Self is the struct, const or not), as Drake's Serialize lists DRAKE_NVPs. That one list
// drives validate() below, the readers and writers of parameters and scene files
// (kernel/parameters.hpp) and every message about a field. A field is a number (integer
// types must hold whole numbers), a bool, a string, an enum with enum_names(), a struct with
// visit_fields, or a std::optional or std::vector of those.
namespace mimpact {

// What a field may hold, for the checks and the messages.
struct Allowed {
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  bool lower_open = false, upper_open = false;
  std::string_view note;    // units or a remark, shown after the range: "> 0 (s)"
  std::string_view text;    // a description in place of the generated one: "0 <= e <= 1"
  std::string_view symbol;  // "K": messages name the field "stiffness K"
  bool required = false;    // readers refuse input without the field (it has no default)

  constexpr Allowed described(std::string_view description) const {
    Allowed copy = *this;
    copy.text = description;
    return copy;
  }
  constexpr Allowed with_symbol(std::string_view name) const {
    Allowed copy = *this;
    copy.symbol = name;
    return copy;
  }
  constexpr Allowed needed() const {
    Allowed copy = *this;
    copy.required = true;
    return copy;
  }
};

constexpr Allowed any(std::string_view note = {}) { return {.note = note}; }
constexpr Allowed positive(std::string_view note = {}) {
  return {.lower = 0.0, .lower_open = true, .note = note};
}
constexpr Allowed at_least(double lower, std::string_view note = {}) {
  return {.lower = lower, .note = note};
}
// [lower, upper], either end excluded on request
constexpr Allowed within(double lower, double upper, std::string_view note = {},
                         bool lower_open = false, bool upper_open = false) {
  return {.lower = lower,
          .upper = upper,
          .lower_open = lower_open,
          .upper_open = upper_open,
          .note = note};
}

namespace fields {

template <class T>
concept Number = std::is_arithmetic_v<T> && !std::is_same_v<T, bool>;

template <class T>
concept Integer = Number<T> && std::is_integral_v<T>;

// an enum whose values have names: enum_names(E{}) returns pairs (value, name), found by ADL
template <class T>
concept NamedEnum = std::is_enum_v<T> && requires {
  enum_names(T{});
};

struct NoVisit {
  template <class... Arguments>
  void operator()(Arguments&&...) const {}
};

template <class T>
concept Described = requires(T& value, NoVisit visit) {
  T::visit_fields(value, visit);
};

template <class T>
struct IsOptional : std::false_type {};
template <class T>
struct IsOptional<std::optional<T>> : std::true_type {};

template <class T>
struct IsVector : std::false_type {};
template <class T>
struct IsVector<std::vector<T>> : std::true_type {};

// "a.b" and "a[3]", from the path of the enclosing struct
inline std::string join(std::string_view path, std::string_view name) {
  return path.empty() ? std::string(name) : std::string(path) + "." + std::string(name);
}
inline std::string element(std::string_view path, std::size_t index) {
  return std::string(path) + "[" + std::to_string(index) + "]";
}

// The name a message gives the field: its path, and its symbol when it has one.
inline std::string label(std::string_view path, const Allowed& allowed) {
  return allowed.symbol.empty() ? std::string(path)
                                : std::string(path) + " " + std::string(allowed.symbol);
}

// What messages call the fields of an options struct: "PREFIX" + name ("impact.delta_p" in a
// scene), or the name of the place that chose the field ("--delta-p" on the command line).
struct Labels {
  std::string prefix;
  std::vector<std::pair<std::string, std::string>> chosen;  // (field, its name)

  std::string operator()(std::string_view field) const {
    for (const auto& [name, label] : chosen)
      if (name == field) return label;
    return prefix + std::string(field);
  }
};

// "> 0 (s)", "an integer in [0, 10]", or the field's own text
std::string describe(const Allowed& allowed, bool integer);

// The name among `candidates` that `name` most likely misspells ("striker" for "strikers"):
// within an edit distance of a third of its length (at least 2), or "" when none is.
std::string closest_name(std::string_view name, const std::vector<std::string_view>& candidates);

// Whether a value fits: finite, within the range, whole for an integer field.
bool admits(const Allowed& allowed, double value, bool integer);

// The range an integer type can hold, intersected with the field's (and described by
// its bounds).
template <Integer T>
Allowed integer_range(Allowed allowed) {
  allowed.lower = std::max(allowed.lower, double(std::numeric_limits<T>::lowest()));
  // max + 1 is a power of two, exact in a double: the values below it fit
  const double past_max = double(std::numeric_limits<T>::max()) + 1.0;
  if (!(allowed.upper < past_max)) {
    allowed.upper = past_max;
    allowed.upper_open = true;
  }
  allowed.text = {};
  return allowed;
}

}  // namespace fields

// The name of an enum value, and the value of a name (nullopt for none).
template <fields::NamedEnum E>
std::string_view enum_name(E value) {
  for (const auto& [candidate, name] : enum_names(E{}))
    if (candidate == value) return name;
  return "?";
}
template <fields::NamedEnum E>
std::optional<E> enum_from_name(std::string_view text) {
  for (const auto& [candidate, name] : enum_names(E{}))
    if (name == text) return candidate;
  return std::nullopt;
}
// "\"a\", \"b\"": the names allowed, for messages
template <fields::NamedEnum E>
std::string enum_choices() {
  std::string text;
  for (const auto& [candidate, name] : enum_names(E{}))
    text += (text.empty() ? "\"" : ", \"") + std::string(name) + "\"";
  return text;
}

namespace fields {

// Throws InvalidInput "OWNER: PATH = VALUE is invalid; allowed: ..." for the first field out
// of range.
class Validator {
 public:
  Validator(std::string owner, std::string path)
      : owner_(std::move(owner)), path_(std::move(path)) {}

  template <class T>
  void operator()(std::string_view name, const T& value, const Allowed& allowed = {}) const {
    check(join(path_, name), value, allowed);
  }

  template <class T>
  void check(const std::string& path, const T& value, const Allowed& allowed = {}) const {
    if constexpr (Number<T>) {
      check_number<T>(path, double(value), allowed);
    } else if constexpr (IsOptional<T>::value) {
      if (value) check(path, *value, allowed);
    } else if constexpr (IsVector<T>::value) {
      for (std::size_t k = 0; k < value.size(); ++k) check(element(path, k), value[k], allowed);
    } else if constexpr (Described<T>) {
      T::visit_fields(value, Validator(owner_, path));
    }
    // bools, strings and named enums hold nothing out of range
  }

  // A value read as a double into a number field of type T.
  template <Number T>
  void check_number(const std::string& path, double value, const Allowed& allowed) const {
    if (admits(allowed, value, Integer<T>)) {
      if constexpr (Integer<T>) {
        // within the field's range but not the type's: say what the type holds
        const Allowed held = integer_range<T>(allowed);
        if (!admits(held, value, true))
          fail(invalid_value_message(label(path, allowed), value, describe(held, true)));
      }
      return;
    }
    fail(invalid_value_message(label(path, allowed), value, describe(allowed, Integer<T>)));
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw InvalidInput(owner_.empty() ? what : owner_ + ": " + what);
  }

 private:
  std::string owner_;
  std::string path_;
};

}  // namespace fields

// Throws InvalidInput naming `owner`, the first field out of range, its value and what is
// allowed: the one validation of every options and scene struct.
template <fields::Described T>
void validate(const T& value, std::string_view owner = {}) {
  T::visit_fields(value, fields::Validator(std::string(owner), ""));
}

}  // namespace mimpact
