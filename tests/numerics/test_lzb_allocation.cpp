// The step loop of the LZB integrator allocates nothing: a run with eight times more steps
// makes exactly as many heap allocations. Counted by replacing the global operator new.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "../support/uniform_chain.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace {
std::atomic<long> allocations{0};
}

void* operator new(std::size_t size) {
  ++allocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
// GCC 12 takes the replaced operator delete for the library's and warns that free() does not
// match new; here new is malloc, so free is its match.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace mimpact::numerics {
namespace {

// An observer that keeps a running maximum: it allocates nothing itself.
class PeakObserver : public ImpactObserver {
 public:
  void observe(const ImpactSample& sample) override {
    for (double f : sample.force) peak = std::max(peak, f);
  }
  double peak = 0.0;
};

long allocations_of_impact(double delta_p, bool observe) {
  const int contacts = 30;
  const Eigen::SparseMatrix<double> H = testing::uniform_chain_delassus(contacts, 0.03);
  Eigen::VectorXd u_minus = Eigen::VectorXd::Zero(contacts);
  u_minus(0) = -1.0;
  const std::vector<ContactLaw> laws(contacts, {.stiffness = 1e10, .restitution = 0.9});
  LzbImpulseIntegrator integrator({.delta_p = delta_p, .sample_every = observe ? 10 : 0});
  PeakObserver observer;
  const long before = allocations.load();
  const ImpactResult result = integrator.integrate(H, u_minus, laws, observe ? &observer : nullptr);
  const long count = allocations.load() - before;
  EXPECT_EQ(result.status, ImpactStatus::terminated);
  EXPECT_GT(result.steps, 1000);
  return count;
}

TEST(LzbAllocation, StepLoopAllocatesNothing) {
  EXPECT_EQ(allocations_of_impact(8e-5, false), allocations_of_impact(1e-5, false));
  EXPECT_EQ(allocations_of_impact(8e-5, true), allocations_of_impact(1e-5, true));
}

}  // namespace
}  // namespace mimpact::numerics
