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
  EXPECT_EQ(options.integrator, plugins::LzbIntegrator::impulse_step);
  EXPECT_EQ(options.relative_delta_p, 1e-3);
}

TEST(ExampleOptions, AnObjectChoosesTheIntegrator) {
  const char* argv[] = {"cradle", R"({"integrator": "adaptive", "tolerance": 1e-10})"};
  const auto options = impact_options_from_command_line(2, argv, defaults());
  EXPECT_EQ(options.integrator, plugins::LzbIntegrator::adaptive);
  EXPECT_EQ(options.adaptive.tolerance, 1e-10);
  EXPECT_EQ(options.relative_delta_p, 0.0);  // the object replaces the defaults
}

TEST(ExampleOptions, BadInputIsNamed) {
  EXPECT_NE(message_of({"cradle", "{integrator"}).find("is not JSON"), std::string::npos);
  EXPECT_NE(message_of({"cradle", "{}", "{}"}).find("2 arguments"), std::string::npos);
  const std::string unknown = message_of({"cradle", R"({"tolerence": 1e-8})"});
  EXPECT_NE(unknown.find("tolerence"), std::string::npos) << unknown;
  const std::string range =
      message_of({"cradle", R"({"integrator": "adaptive", "tolerance": -1})"});
  EXPECT_NE(range.find("tolerance = -1"), std::string::npos) << range;
  const std::string mixed =
      message_of({"cradle", R"({"integrator": "adaptive", "delta_p": 1e-3})"});
  EXPECT_NE(mixed.find("delta_p"), std::string::npos) << mixed;
}

}  // namespace
}  // namespace mimpact::models
