#include "mimpact/kernel/registry.hpp"

namespace mimpact::kernel {

Registry<OneStepIntegrator>& integrators() {
  static Registry<OneStepIntegrator> registry("one-step integrator");
  return registry;
}

Registry<ImpactProblem>& impact_problems() {
  static Registry<ImpactProblem> registry("impact problem");
  return registry;
}

Registry<ContactForceProblem>& contact_force_problems() {
  static Registry<ContactForceProblem> registry("contact force problem");
  return registry;
}

}  // namespace mimpact::kernel
