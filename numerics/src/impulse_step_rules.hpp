#pragma once

// What the LZB integrators of steps share (lzb_impulse_integrator.cpp,
// lzb_asynchronous_integrator.cpp): column access to H, the power x^p, and the synchronous
// steps' two exact sub-step rules of docs/model.md, section 6.

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>

namespace mimpact::numerics::detail {

// Column access to H, so the step loops are written once for sparse and dense storage.
// Compressed sparse columns read directly: a step touches only the columns of the contacts
// it updates.
struct SparseDelassus {
  explicit SparseDelassus(const Eigen::SparseMatrix<double>& compressed)
      : start(compressed.outerIndexPtr()),
        row(compressed.innerIndexPtr()),
        value(compressed.valuePtr()),
        rows(compressed.rows()) {}
  template <class Visit>
  void for_each_in_column(Eigen::Index j, Visit&& visit) const {
    for (int k = start[j]; k < start[j + 1]; ++k) visit(Eigen::Index(row[k]), value[k]);
  }
  const int* start;
  const int* row;
  const double* value;
  Eigen::Index rows;
};

struct DenseDelassus {
  const Eigen::MatrixXd& H;
  template <class Visit>
  void for_each_in_column(Eigen::Index j, Visit&& visit) const {
    const double* column = H.col(j).data();
    for (Eigen::Index i = 0; i < H.rows(); ++i) visit(i, column[i]);
  }
};

// Calls run(columns) with H's columns: a dense copy (in `dense`, a buffer reused from one impact
// to the next) for impacts among at most `dense_up_to` contacts, whose columns are then read
// without indices; the compressed sparse columns otherwise.
template <class Run>
void with_columns(const Eigen::SparseMatrix<double>& H, Eigen::Index dense_up_to,
                  Eigen::MatrixXd& dense, Run&& run) {
  if (H.rows() <= dense_up_to) {
    dense = H;
    run(DenseDelassus{dense});
  } else {
    run(SparseDelassus(H));
  }
}

// x^p for x > 0, through exp2 and log2: a few ulp from std::pow and a quarter cheaper,
// which matters because the step loops evaluate one power per contact updated.
inline double power_of(double x, double p) { return std::exp2(p * std::log2(x)); }

// The time a contact takes to absorb an impulse step delta_p: the integral of dP / F(E(P))
// with F = c E^a and E linear in P from e0 to e1 (e1 not yet clamped at 0), `force` being
// F(e0). The paper's left-point rule dt = delta_p / F(e0) misses a fixed share of the
// integrable singularity where a contact starts or ends (F -> 0), so its times converge only
// as delta_p^0.4; this rule is exact for the power law there and equal to the paper's rule in
// the smooth interior.
double step_duration(double delta_p, double e0, double e1, double force, double coefficient,
                     double power);

// Below this share of a step, the end of a compression is not worth a step of its own: the
// error of treating the step as expansion is of order share^2.
constexpr double kSmallestCut = 1e-6;

// The share s in [0, 1] of the step at which a contact's phase ends, so that the step can
// stop exactly there: u crossing 0 (compression ends), or E reaching the level where it is
// released (0, or (1 - e^2) W_c for mono-stiffness). Within a step u is linear in s,
// u0 + du s, and the work trapezoidal, so E(s) = E0 - f dp (u0 s + du s^2/2) in expansion,
// with f = 1/e^2 for bi-stiffness and 1 for mono-stiffness.
struct PhaseStep {
  double u = 0.0;               // u0: the contact's velocity at the step's start (m/s)
  double du = 0.0;              // its change over the whole step (m/s)
  double energy = 0.0;          // E0 (J)
  double delta_p = 0.0;         // dp, the contact's impulse over the step (N s)
  double expansion_rate = 1.0;  // f
  double release_level = 0.0;   // J
  bool drops_at_turn = false;   // e = 0: released where the step's work is zero
};
// Inline: it is called at every step, and a call through memory for its seven numbers cost the
// impulse steps about 4 % (bench/bench_lzb.cpp, BM_ChainSteps).
inline double phase_end(const PhaseStep& step) {
  const double u0 = step.u, du = step.du, e0 = step.energy, dp = step.delta_p;
  const double f = step.expansion_rate, level = step.release_level;
  const bool released_at_once = step.drops_at_turn;
  if (u0 < 0.0 && u0 + du > 0.0) {
    const double crossing = -u0 / du;
    if (crossing >= kSmallestCut) return crossing;
  } else if (u0 + 0.5 * du < 0.0) {
    return 1.0;  // compression all along
  }
  // nothing to give back (e = 0, or E already at its level): release where the step's work
  // is zero, at once when u0 >= 0
  if (released_at_once || level >= e0) return std::clamp(-2.0 * u0 / du, 0.0, 1.0);
  const double a = 0.5 * f * dp * du, b = f * dp * u0, c = level - e0;
  if (a + b + c <= 0.0) return 1.0;  // E stays above its release level
  const double discriminant = b * b - 4.0 * a * c;
  const double denominator = -b - std::sqrt(std::max(discriminant, 0.0));
  return denominator < 0.0 ? std::clamp(2.0 * c / denominator, 0.0, 1.0) : 1.0;
}

}  // namespace mimpact::numerics::detail
