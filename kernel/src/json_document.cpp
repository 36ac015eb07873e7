#include "mimpact/kernel/json_document.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <optional>
#include <unordered_set>

#include "mimpact/common/error.hpp"

namespace mimpact::kernel {

using nlohmann::json;

namespace {

// A pointer into the text that reports how far the parser has read it: nlohmann's SAX events
// carry no position, so the key events take theirs from here.
class ReadingPosition {
 public:
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  ReadingPosition(const char* at, const char** furthest) : at_(at), furthest_(furthest) {}
  reference operator*() const { return *at_; }
  ReadingPosition& operator++() {
    *furthest_ = ++at_;
    return *this;
  }
  ReadingPosition operator++(int) {
    ReadingPosition before = *this;
    ++*this;
    return before;
  }
  bool operator==(const ReadingPosition& other) const { return at_ == other.at_; }

 private:
  const char* at_;
  const char** furthest_;
};

// Builds the document from nlohmann's SAX events, keeping the path of the value being read,
// the keys of each open object and where each key is written.
class DocumentBuilder {
 public:
  DocumentBuilder(std::string_view text, const std::string& source, const char** furthest)
      : text_(text), source_(source), furthest_(furthest), document_{json(), JsonLocations(text)} {}

  JsonDocument take() { return std::move(document_); }

  bool null() { return put(nullptr); }
  bool boolean(bool value) { return put(value); }
  bool number_integer(json::number_integer_t value) { return put(value); }
  bool number_unsigned(json::number_unsigned_t value) { return put(value); }
  bool number_float(json::number_float_t value, const std::string&) { return put(value); }
  bool string(std::string& value) { return put(std::move(value)); }
  bool binary(json::binary_t&) { return put(nullptr); }  // not produced by JSON text
  bool start_object(std::size_t) { return open(json::object()); }
  bool start_array(std::size_t) { return open(json::array()); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool key(std::string& name) {
    Frame& top = open_.back();
    top.key = name;
    top.has_key = true;
    // the key starts its length and two quotes before where the reading stopped
    const std::size_t start = here() - std::min(here(), name.size() + 2);
    if (!top.keys.insert(name).second)
      fail(start, shortened_path(path()) + " is given twice in its object; allowed: each key once");
    document_.locations.add(path(), start);
    return true;
  }

  bool parse_error(std::size_t position, const std::string& last_token,
                   const nlohmann::detail::exception& ex) {
    const std::string what = ex.what();
    if (ex.id == 406) {  // number overflow, of a finite-looking text such as 1e999
      const std::size_t start = number_start(position);
      fail(start,
           field_name() + " = " +
               std::string(text_.substr(start, std::min<std::size_t>(position - start, 40))) +
               " is beyond double precision; allowed: a finite number of magnitude at "
               "most 1.8e308");
    }
    // "[json.exception.parse_error.101] parse error at line 2, column 25: syntax error while
    // parsing object - unexpected string literal; expected '}'": the part after the position
    const std::size_t colon = what.find(": ", what.find("column"));
    std::string detail = colon == std::string::npos ? what : what.substr(colon + 2);
    if (detail.size() > 160) detail = detail.substr(0, 157) + "...";
    // `position` characters were read: point at the last, or at the start of an unexpected
    // string literal
    const bool string = !last_token.empty() && last_token.front() == '"';
    const std::size_t token = std::min<std::size_t>(position, string ? last_token.size() : 1);
    fail(
        position - token,
        "malformed JSON" + (open_.empty() ? std::string() : " in " + field_name()) + ": " + detail);
  }

 private:
  struct Frame {
    json* value;
    std::string key;  // objects: the key being read
    bool has_key = false;
    std::size_t index = 0;  // arrays: how many elements are stored
    std::unordered_set<std::string> keys;
  };

  // Stores a value where the parser is, and returns it.
  template <class Value>
  json* store(Value&& value) {
    if (open_.empty()) {
      document_.value = std::forward<Value>(value);
      return &document_.value;
    }
    Frame& top = open_.back();
    if (top.value->is_array()) {
      ++top.index;
      top.value->push_back(std::forward<Value>(value));
      return &top.value->back();
    }
    json& slot = (*top.value)[top.key];
    slot = std::forward<Value>(value);
    return &slot;
  }
  template <class Value>
  bool put(Value&& value) {
    store(std::forward<Value>(value));
    return true;
  }
  bool open(json container) {
    if (int(open_.size()) >= kMaxJsonDepth)
      fail(here(), field_name() + " nests arrays and objects deeper than " +
                       std::to_string(kMaxJsonDepth) + " levels; allowed: at most " +
                       std::to_string(kMaxJsonDepth));
    json* stored = store(std::move(container));
    open_.push_back(Frame{stored, {}, false, 0, {}});
    return true;
  }
  bool close() {
    open_.pop_back();
    return true;
  }

  // "strikers[0].velocity": the path of the value being read. An array's open element is its
  // last one stored, or, in the innermost array, the next one.
  std::string path() const {
    std::string text;
    for (const Frame& frame : open_) {
      if (frame.value->is_array()) {
        const bool innermost = &frame == &open_.back();
        const std::size_t index = innermost || frame.index == 0 ? frame.index : frame.index - 1;
        text += '[';
        text += std::to_string(index);
        text += ']';
      } else if (frame.has_key) {
        if (!text.empty()) text += '.';
        text += frame.key;
      }
    }
    return text;
  }
  std::string field_name() const {
    const std::string name = path();
    return name.empty() ? "the top level" : shortened_path(name);
  }
  std::size_t here() const { return std::size_t(*furthest_ - text_.data()); }

  // where the number token that ends at `position` starts
  std::size_t number_start(std::size_t position) const {
    std::size_t start = std::min(position, text_.size());
    while (start > 0 &&
           std::string_view("0123456789+-.eE").find(text_[start - 1]) != std::string_view::npos)
      --start;
    return start;
  }

  [[noreturn]] void fail(std::size_t offset, const std::string& what) const {
    throw InvalidInput(source_ + ":" + document_.locations.at_offset(offset) + ": " + what);
  }

  std::string_view text_;
  const std::string& source_;
  const char** furthest_;
  JsonDocument document_;
  std::vector<Frame> open_;
};

template <class Json>
void excerpt_into(const Json& value, std::string& out, std::size_t limit) {
  if (out.size() > limit) return;
  switch (value.type()) {
    case Json::value_t::number_float: {
      const double number = value.template get<double>();
      out += std::isfinite(number) ? to_text(number)
             : std::isnan(number)  ? "nan"
             : number > 0          ? "inf"
                                   : "-inf";
      return;
    }
    case Json::value_t::array: {
      out += "[";
      bool first = true;
      for (const Json& item : value) {
        if (out.size() > limit) break;
        out += first ? "" : ", ";
        first = false;
        excerpt_into(item, out, limit);
      }
      out += "]";
      return;
    }
    case Json::value_t::object: {
      out += "{";
      bool first = true;
      for (const auto& [key, item] : value.items()) {
        if (out.size() > limit) break;
        out += (first ? "" : ", ") + Json(key).dump() + ": ";
        first = false;
        excerpt_into(item, out, limit);
      }
      out += "}";
      return;
    }
    case Json::value_t::string: {
      const std::string& text = value.template get_ref<const std::string&>();
      if (text.size() <= limit) {
        out += value.dump(-1, ' ', false, Json::error_handler_t::replace);
        return;
      }
      out += Json(text.substr(0, limit)).dump(-1, ' ', false, Json::error_handler_t::replace);
      return;
    }
    default:
      out += value.dump();
  }
}

template <class Json>
std::string excerpt(const Json& value, std::size_t limit) {
  std::string out;
  excerpt_into(value, out, limit);
  if (out.size() <= limit) return out;
  const std::size_t size =
      value.is_string() ? value.template get_ref<const std::string&>().size() : value.size();
  return out.substr(0, limit) + "... (" + std::to_string(size) +
         (value.is_string() ? " characters)" : " entries)");
}

}  // namespace

JsonLocations::JsonLocations(std::string_view text) {
  line_starts_.push_back(0);
  for (std::size_t k = 0; k < text.size(); ++k)
    if (text[k] == '\n') line_starts_.push_back(k + 1);
}

std::string JsonLocations::at_offset(std::size_t offset) const {
  if (line_starts_.empty()) return "";
  const auto next = std::upper_bound(line_starts_.begin(), line_starts_.end(), offset);
  const std::size_t line = std::size_t(next - line_starts_.begin());
  return std::to_string(line) + ":" + std::to_string(offset - *(next - 1) + 1);
}

std::string JsonLocations::of(std::string_view path) const {
  std::string at(path);
  while (!at.empty()) {
    if (const auto found = offsets_.find(at); found != offsets_.end())
      return at_offset(found->second);
    const std::size_t cut = at.find_last_of(".[");
    at.resize(cut == std::string::npos ? 0 : cut);
  }
  return "";
}

JsonDocument parse_json_document(std::string_view text, const std::string& source) {
  const char* furthest = text.data();
  DocumentBuilder builder(text, source, &furthest);
  json::sax_parse(ReadingPosition(text.data(), &furthest),
                  ReadingPosition(text.data() + text.size(), &furthest), &builder,
                  json::input_format_t::json, /*strict=*/true, /*ignore_comments=*/true);
  return builder.take();
}

std::string json_excerpt(const nlohmann::json& value, std::size_t limit) {
  return excerpt(value, limit);
}
std::string json_excerpt(const nlohmann::ordered_json& value, std::size_t limit) {
  return excerpt(value, limit);
}

std::string shortened_path(const std::string& path, std::size_t limit) {
  return path.size() <= limit ? path : path.substr(0, limit) + "...";
}

}  // namespace mimpact::kernel
