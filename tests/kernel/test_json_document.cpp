// JSON text read with mimpact's limits (kernel/json_document.hpp) and the field reader's messages
// (kernel/parameters.hpp): every malformed, ambiguous or oversized input is refused in one line
// naming the file, line, column and field (issue 22, items 1, 3 and 5).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "../support/error_of.hpp"
#include "mimpact/kernel/json_document.hpp"
#include "mimpact/kernel/parameters.hpp"

namespace mimpact::kernel {
namespace {

using testing::error_of;

struct Striker {
  double velocity = 0.0;
  std::string side = "left";
  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("velocity", self.velocity, positive("m/s").needed());
    field("side", self.side);
  }
};

struct Scene {
  std::vector<Striker> strikers;
  std::optional<double> delta_p;
  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("strikers", self.strikers, any().needed());
    field("delta_p", self.delta_p, positive("N s"));
  }
};

// Parses and reads `text` as the file "scene.json"; the message of the error, or "".
std::string read_error(const std::string& text) {
  return error_of([&] {
    const JsonDocument document = parse_json_document(text, "scene.json");
    options_from<Scene>(document.value, {.name = "scene.json",
                                         .unknown = "key",
                                         .top = "the top level",
                                         .locations = &document.locations});
  });
}

TEST(JsonDocument, FieldErrorsNameTheLineAndColumnOfTheirKey) {
  const std::string text = "{\n  \"strikers\": [\n    {\"velocity\": -1}\n  ]\n}\n";
  EXPECT_EQ(read_error(text),
            "scene.json:3:6: strikers[0].velocity = -1 is invalid; allowed: > 0 (m/s)");
  // a value of the wrong type is echoed, with its type
  EXPECT_EQ(read_error("{\"strikers\": [{\"velocity\": \"fast\"}]}"),
            "scene.json:1:16: strikers[0].velocity = \"fast\" (a string) is invalid; allowed: a "
            "number, > 0 (m/s)");
}

TEST(JsonDocument, MalformedTextIsNamedByLineColumnAndField) {
  const std::string message = read_error("{\"strikers\": [\n {\"velocity\": 1 \"side\": 2}]}");
  EXPECT_EQ(message.rfind("scene.json:2:17: malformed JSON in strikers[0].velocity: ", 0), 0u)
      << message;
  EXPECT_EQ(read_error("").rfind("scene.json:1:1: malformed JSON: ", 0), 0u);
}

TEST(JsonDocument, NumbersBeyondDoublePrecisionAreNamed) {
  EXPECT_EQ(read_error("{\"strikers\": [{\"velocity\":\n 1e999}]}"),
            "scene.json:2:2: strikers[0].velocity = 1e999 is beyond double precision; allowed: "
            "a finite number of magnitude at most 1.8e308");
  // integers past 64 bits read as the nearest double, and are judged as numbers
  EXPECT_EQ(read_error("{\"strikers\": [{\"velocity\": 100000000000000000000000000000}]}"), "");
}

TEST(JsonDocument, KeysGivenTwiceAreRefused) {
  EXPECT_EQ(read_error("{\"strikers\": [],\n \"delta_p\": 1e-5, \"delta_p\": 1e-6}"),
            "scene.json:2:19: delta_p is given twice in its object; allowed: each key once");
  EXPECT_EQ(read_error("{\"strikers\": [{\"velocity\": 1, \"side\": \"a\", \"side\": \"b\"}]}"),
            "scene.json:1:44: strikers[0].side is given twice in its object; allowed: each key "
            "once");
  // the same key in two objects is no duplicate
  EXPECT_EQ(read_error("{\"strikers\": [{\"velocity\": 1}, {\"velocity\": 2}]}"), "");
}

TEST(JsonDocument, NestingDeeperThan64IsRefusedAtOnce) {
  auto nested = [](int depth) {
    return "{\"strikers\": [{\"velocity\": 1}], \"delta_p\": " + std::string(depth, '[') + "1" +
           std::string(depth, ']') + "}";
  };
  // 63 arrays in the top-level object: 64 levels, read (and refused as a number, not a crash)
  EXPECT_NE(read_error(nested(63)).find("delta_p = [[[[[[[["), std::string::npos);
  EXPECT_EQ(read_error(nested(64)),
            "scene.json:1:108: delta_p[0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0]"
            "[0][0][0][0][0][... nests arrays and objects deeper than 64 levels; allowed: at "
            "most 64");
  // a million levels: refused where the 65th opens, without reading the rest
  const auto start = std::chrono::steady_clock::now();
  EXPECT_NE(read_error(nested(1'000'000)).find("deeper than 64 levels"), std::string::npos);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 0.5);
}

TEST(JsonDocument, UnknownKeysAreNamedWithTheFieldTheyMisspell) {
  EXPECT_EQ(read_error("{\"striker\": [{\"velocity\": 1}]}"),
            "scene.json:1:2: unknown key \"striker\" in the top level (did you mean "
            "\"strikers\"?); allowed: strikers, delta_p");
  // nothing close: no guess
  EXPECT_EQ(read_error("{\"strikers\": [], \"mass\": 1}"),
            "scene.json:1:18: unknown key \"mass\" in the top level; allowed: strikers, delta_p");
}

TEST(JsonDocument, ValuesAreEchoedAtMost80Characters) {
  const std::string message =
      read_error("{\"strikers\": [{\"velocity\": \"" + std::string(1'000'000, 'x') + "\"}]}");
  EXPECT_LT(message.size(), 250u) << message;
  EXPECT_NE(message.find("... (1000000 characters) (a string) is invalid"), std::string::npos)
      << message;
  // a megabyte key is cut too
  EXPECT_LT(read_error("{\"" + std::string(1'000'000, 'k') + "\": 1, \"strikers\": []}").size(),
            400u);
}

TEST(JsonDocument, ExcerptsWriteNonFiniteNumbersAsSuch) {
  nlohmann::json values = {std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(), 1e-300};
  EXPECT_EQ(json_excerpt(values), "[nan, inf, -inf, 1e-300]");
  // and a field holding NaN (from a Python dict) is named with it, not as JSON's null
  const std::string message = error_of([&] {
    options_from<Scene>(nlohmann::json{{"strikers", {{{"velocity", values[0]}}}}},
                        {.name = "scene"});
  });
  EXPECT_EQ(message, "scene: strikers[0].velocity = nan is invalid; allowed: > 0 (m/s)");
}

TEST(JsonDocument, ByteOrderMarksAndCommentsAreRead) {
  EXPECT_EQ(read_error("\xEF\xBB\xBF// a comment\n{\"strikers\": [] /* none */}"), "");
  EXPECT_NE(read_error("{\"strikers\": [] /* open").find("malformed JSON"), std::string::npos);
}

}  // namespace
}  // namespace mimpact::kernel
