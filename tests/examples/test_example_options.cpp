// The example programs' impact options from their command line: the "lzb" impact problem's
// own fields as one JSON object, with its messages for bad input.
#include <gtest/gtest.h>

#include "mimpact/common/error.hpp"
#include "mimpact/models/simulation_setup.hpp"

namespace mimpact::models {
namespace {

plugins::LzbImpactOptions defaults() {
  plugins::LzbImpactOptions options;
  options.relative_delta_p = 1e-3;
  return options;
}

std::string message_of(std::vector<const char*> argv) {
  try {
    impact_options_from_command_line(int(argv.size()), argv.data(), defaults());
  } catch (const InvalidInput& error) {
    return error.what();
  }
  return "no error";
}

TEST(ExampleOptions, NoArgumentKeepsTheDefaults) {
  const char* argv[] = {"cradle"};
  const auto options = impact_options_from_command_line(1, argv, defaults());
  EXPECT_EQ(options.chosen_integrator(), plugins::LzbIntegrator::impulse_step);
  EXPECT_EQ(options.relative_delta_p, 1e-3);
}

TEST(ExampleOptions, AnObjectChoosesTheIntegrator) {
  const char* argv[] = {"cradle", R"({"integrator": "adaptive", "tolerance": 1e-10})"};
  const auto options = impact_options_from_command_line(2, argv, defaults());
  EXPECT_EQ(options.integrator, plugins::LzbIntegrator::adaptive);
  EXPECT_EQ(options.tolerance, 1e-10);
  EXPECT_FALSE(options.relative_delta_p);  // the object replaces the defaults
}

TEST(ExampleOptions, BadInputIsNamed) {
  // malformed JSON, named with its line and column
  EXPECT_NE(message_of({"cradle", "{integrator"}).find("cradle impact options:1:2: malformed JSON"),
            std::string::npos);
  EXPECT_NE(message_of({"cradle", "{}", "{}"}).find("2 arguments"), std::string::npos);
  const std::string unknown = message_of({"cradle", R"({"tolerence": 1e-8})"});
  EXPECT_NE(unknown.find("\"tolerence\" (did you mean \"tolerance\"?)"), std::string::npos)
      << unknown;
  const std::string range =
      message_of({"cradle", R"({"integrator": "adaptive", "tolerance": -1})"});
  EXPECT_NE(range.find("tolerance = -1"), std::string::npos) << range;
  const std::string mixed =
      message_of({"cradle", R"({"integrator": "adaptive", "delta_p": 1e-3})"});
  EXPECT_NE(mixed.find("delta_p"), std::string::npos) << mixed;
}

}  // namespace
}  // namespace mimpact::models
