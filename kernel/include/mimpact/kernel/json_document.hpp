#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

// JSON text read with the limits every input of mimpact keeps (scene files, parameters, Python
// dicts): nesting at most kMaxJsonDepth deep, each key once in its object, numbers within double
// precision; and where each value was written, so that a message names the file, the line, the
// column and the field: "scene.json:3:17: strikers[0].velocity = 1e999 is ...".
namespace mimpact::kernel {

// Arrays and objects nested deeper than this are refused: no scene needs more than 5 levels, and
// values a million levels deep overflowed the stack of every recursive copy, dump and destructor.
inline constexpr int kMaxJsonDepth = 64;

// Where the keys of a document are written: line and column of each field's path.
class JsonLocations {
 public:
  JsonLocations() = default;
  explicit JsonLocations(std::string_view text);

  void add(std::string path, std::size_t offset) { offsets_.emplace(std::move(path), offset); }
  // "LINE:COLUMN" of `path` ("strikers[0].velocity"), or of the nearest enclosing field written
  // in the text; "" when none is.
  std::string of(std::string_view path) const;
  // "LINE:COLUMN" of a byte offset into the text (both counted from 1).
  std::string at_offset(std::size_t offset) const;

 private:
  std::unordered_map<std::string, std::size_t> offsets_;  // path -> offset of its key
  std::vector<std::size_t> line_starts_;                  // offset where each line starts
};

struct JsonDocument {
  nlohmann::json value;
  JsonLocations locations;
};

// Parses JSON text (comments allowed, a UTF-8 byte-order mark skipped). Throws InvalidInput
// "SOURCE:LINE:COLUMN: ..." naming the field for malformed text, a number beyond double
// precision, a key given twice in one object, and nesting deeper than kMaxJsonDepth.
JsonDocument parse_json_document(std::string_view text, const std::string& source);

// The value as JSON text cut to about `limit` characters ("..." and the full size after a
// cut), with non-finite numbers written nan, inf and -inf rather than JSON's null: what a
// message shows of a value.
std::string json_excerpt(const nlohmann::json& value, std::size_t limit = 80);
std::string json_excerpt(const nlohmann::ordered_json& value, std::size_t limit = 80);

// "strikers[0].velocity" from "strikers", 0, "velocity"; cut to `limit` characters with "...".
std::string shortened_path(const std::string& path, std::size_t limit = 80);

}  // namespace mimpact::kernel
