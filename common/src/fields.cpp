#include "mimpact/common/fields.hpp"

namespace mimpact::fields {

namespace {

std::string bound(double value, bool open, bool lower) {
  return std::string(lower ? (open ? "> " : ">= ") : (open ? "< " : "<= ")) + to_text(value);
}

}  // namespace

std::string describe(const Allowed& allowed, bool integer) {
  std::string text(allowed.text);
  if (text.empty()) {
    const bool has_lower = std::isfinite(allowed.lower), has_upper = std::isfinite(allowed.upper);
    if (has_lower && has_upper) {
      text = std::string("in ") + (allowed.lower_open ? "(" : "[") + to_text(allowed.lower) + ", " +
             to_text(allowed.upper) + (allowed.upper_open ? ")" : "]");
    } else if (has_lower) {
      text = bound(allowed.lower, allowed.lower_open, true);
    } else if (has_upper) {
      text = bound(allowed.upper, allowed.upper_open, false);
    }
    if (integer) text = text.empty() ? "an integer" : "an integer " + text;
    if (text.empty()) text = "a finite number";
  }
  if (!allowed.note.empty()) text += " (" + std::string(allowed.note) + ")";
  return text;
}

bool admits(const Allowed& allowed, double value, bool integer) {
  if (!std::isfinite(value)) return false;
  if (allowed.lower_open ? !(value > allowed.lower) : !(value >= allowed.lower)) return false;
  if (allowed.upper_open ? !(value < allowed.upper) : !(value <= allowed.upper)) return false;
  return !integer || value == std::floor(value);
}

}  // namespace mimpact::fields
