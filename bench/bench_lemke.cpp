// Lemke's method on random positive definite LCPs of size 10, 100 and 500.
#include <benchmark/benchmark.h>

#include <random>

#include "mimpact/numerics/lemke.hpp"

namespace {

void BM_LemkeRandomPositiveDefinite(benchmark::State& state) {
  const int n = int(state.range(0));
  std::mt19937 random(42);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd A(n, n);
  for (auto& x : A.reshaped()) x = normal(random);
  const Eigen::MatrixXd M = A * A.transpose() / n + Eigen::MatrixXd::Identity(n, n);
  Eigen::VectorXd q(n);
  for (auto& x : q) x = normal(random);
  mimpact::numerics::LemkeResult result;
  for (auto _ : state) {
    result = mimpact::numerics::solve_lemke(M, q);
    benchmark::DoNotOptimize(result.z.data());
  }
  if (!result.solved()) state.SkipWithError("not solved");
  state.counters["pivots"] = result.pivots;
  state.counters["complementarity_error"] = result.complementarity_error;
}
BENCHMARK(BM_LemkeRandomPositiveDefinite)
    ->Arg(10)
    ->Arg(100)
    ->Arg(500)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
