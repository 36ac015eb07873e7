#pragma once

#include "mimpact/kernel/non_smooth_law.hpp"
#include "mimpact/numerics/contact_law.hpp"

namespace mimpact::plugins {

// The LZB impact law of a contact: compliance F = K delta^eta, energetic restitution e,
// mono- or bi-stiffness (docs/model.md, section 3). Throws InvalidInput when a value is out of
// range.
class LzbLaw : public kernel::NonSmoothLaw {
 public:
  explicit LzbLaw(numerics::ContactLaw law) : law_(law) { validate(law_, "LZB law"); }
  std::string_view kind() const override { return "lzb"; }
  const numerics::ContactLaw& contact_law() const { return law_; }

 private:
  numerics::ContactLaw law_;
};

}  // namespace mimpact::plugins
