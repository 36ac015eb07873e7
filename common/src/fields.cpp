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

std::string closest_name(std::string_view name, const std::vector<std::string_view>& candidates) {
  // Levenshtein distance, one row at a time
  auto distance = [](std::string_view a, std::string_view b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
      std::size_t diagonal = row[0];
      row[0] = i;
      for (std::size_t j = 1; j <= b.size(); ++j) {
        const std::size_t above = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
        diagonal = above;
      }
    }
    return row[b.size()];
  };
  if (name.size() > 100) return "";
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, name.size() / 3) + 1;
  for (std::string_view candidate : candidates) {
    const std::size_t d = distance(name, candidate);
    if (d < best_distance) {
      best_distance = d;
      best = candidate;
    }
  }
  return best;
}

bool admits(const Allowed& allowed, double value, bool integer) {
  if (!std::isfinite(value)) return false;
  if (allowed.lower_open ? !(value > allowed.lower) : !(value >= allowed.lower)) return false;
  if (allowed.upper_open ? !(value < allowed.upper) : !(value <= allowed.upper)) return false;
  return !integer || value == std::floor(value);
}

}  // namespace mimpact::fields
