#include "mimpact/numerics/contact_law.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "mimpact/common/error.hpp"

namespace mimpact::numerics {
namespace {

TEST(ContactLaw, ForceFromEnergyIsKDeltaToTheEta) {
  // E = K delta^(1+eta) / (1+eta) must give back F = K delta^eta
  for (double eta : {1.0, 1.5, 2.5}) {
    ContactLaw law{.stiffness = 3.7e9, .exponent = eta};
    for (double delta : {1e-9, 1e-6, 1e-4}) {
      const double energy = law.stiffness * std::pow(delta, 1.0 + eta) / (1.0 + eta);
      EXPECT_NEAR(law.force_from_energy(energy), law.stiffness * std::pow(delta, eta),
                  1e-12 * law.stiffness * std::pow(delta, eta));
    }
  }
}

TEST(ContactLaw, ValidationNamesTheField) {
  auto message = [](ContactLaw law) {
    try {
      validate(law, "contact 7");
    } catch (const InvalidInput& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  EXPECT_NE(message({.stiffness = 0.0}).find("stiffness K = 0"), std::string::npos);
  EXPECT_NE(message({.stiffness = -2.0}).find("contact 7"), std::string::npos);
  EXPECT_NE(message({.stiffness = 1.0, .exponent = 0.0}).find("exponent eta = 0"),
            std::string::npos);
  EXPECT_NE(message({.stiffness = 1.0, .restitution = 1.2}).find("restitution e = 1.2"),
            std::string::npos);
  EXPECT_NE(message({.stiffness = 1.0, .restitution = -0.1}).find("0 <= e <= 1"),
            std::string::npos);
  EXPECT_EQ(message({.stiffness = 1.0, .restitution = 0.0}), "");
  EXPECT_EQ(message({.stiffness = NAN}).find("stiffness K = nan"), 11u);
}

TEST(ContactLaw, ModelNamesRoundTrip) {
  for (ComplianceModel model : {ComplianceModel::bi_stiffness, ComplianceModel::mono_stiffness})
    EXPECT_EQ(enum_from_name<ComplianceModel>(enum_name(model)), model);
  EXPECT_FALSE(enum_from_name<ComplianceModel>("tri-stiffness"));
}

}  // namespace
}  // namespace mimpact::numerics
