#pragma once

#include <Eigen/Dense>
#include <array>
#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/tools/toms748_solve.hpp>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace mimpact::numerics::internal {

// A Hertz force K delta^(3/2) between two spheres switches on where they touch (or off where
// they part) within a step, and there its second derivative is unbounded: a Runge-Kutta step's
// weights, exact for cubics, integrate it with an error of order h^2.5 in the velocity, where
// a smooth force errs as h^5. A large group of a packing has a touch or a parting in almost
// every step (docs/model.md, section 17).
//
// This integrates that one force again, along the separation of the two spheres over the step
// modelled as the cubic Hermite of its values and rates at the step's ends (error O(h^4)),
// where the spheres overlap (the overlap's ends found by TOMS 748, a span integrated by
// Gauss-Legendre from its touching end, or each half from its own, after a change of variable
// that makes the touch's (s - s_touch)^(3/2) smooth), and gives what the step's weights missed:
//   integral over the step of F n dt  -  h sum_i b_i F(t0 + c_i h) n(t0 + c_i h),
// both along the same model, so that the model's own error largely cancels and the difference
// vanishes where the force is smooth. Added to the two bodies' velocities, equal and opposite
// (a group's momentum stays exact), it takes the velocity's error of a step across a touch from
// order h^2.5 to h^5 (tests/numerics/test_onset_quadrature.cpp: 45 times smaller at an eighth
// of the contact's duration, 1 460 times at a sixty-fourth).
struct OnsetQuadrature {
  // N s / h: what the weights missed of the force on the second body (along the separation
  // from the first), and of the force's magnitude (the contact's impulse)
  Eigen::Vector3d impulse = Eigen::Vector3d::Zero();
  double magnitude = 0.0;
};

// The separation (m) of the second sphere's centre from the first's at the step's start, r0,
// and end, r1, and its rates times the step, u0 = h r0', u1 = h r1' (m); `reach` (m) the sum of
// the radii, `stiffness` K (N / m^(3/2)); the step's velocity weights b at its nodes c.
template <std::size_t Stages>
OnsetQuadrature hertz_onset_quadrature(const Eigen::Vector3d& r0, const Eigen::Vector3d& u0,
                                       const Eigen::Vector3d& r1, const Eigen::Vector3d& u1,
                                       double reach, double stiffness,
                                       const std::array<double, Stages>& nodes,
                                       const std::array<double, Stages>& weights) {
  auto separation = [&](double s) -> Eigen::Vector3d {
    const double s2 = s * s, s3 = s2 * s;
    return (2.0 * s3 - 3.0 * s2 + 1.0) * r0 + (s3 - 2.0 * s2 + s) * u0 +
           (3.0 * s2 - 2.0 * s3) * r1 + (s3 - s2) * u1;
  };
  auto overlap = [&](double s) { return reach - separation(s).norm(); };
  struct Force {
    Eigen::Vector3d vector = Eigen::Vector3d::Zero();
    double magnitude = 0.0;
  };
  auto force = [&](double s) {
    const Eigen::Vector3d r = separation(s);
    const double distance = r.norm(), delta = reach - distance;
    Force f;
    if (delta <= 0.0) return f;
    f.magnitude = stiffness * delta * std::sqrt(delta);
    f.vector = (f.magnitude / distance) * r;
    return f;
  };
  OnsetQuadrature out;
  // a span where the spheres overlap, integrated in u from each end where they touch or part,
  // with s = end +- length u^2: the force's (s - end)^(3/2) there becomes a smooth u^3, and
  // Gauss-Legendre takes it to round-off; one end such (the other the step's), the whole span
  // from it (8 forces), both, each half from its own (2 x 8)
  using Gauss = boost::math::quadrature::gauss<double, 8>;
  auto integrate_from = [&](double end, double length) {  // length < 0: the span ends at `end`
    const auto& x = Gauss::abscissa();
    const auto& w = Gauss::weights();
    for (std::size_t k = 0; k < x.size(); ++k)
      for (const double sign : {-1.0, 1.0}) {
        // u on [0, 1] (Gauss weight w / 2), ds = 2 |length| u du
        const double u = 0.5 * (1.0 + sign * x[k]);
        const Force f = force(end + length * u * u);
        out.impulse += w[k] * std::abs(length) * u * f.vector;
        out.magnitude += w[k] * std::abs(length) * u * f.magnitude;
      }
  };
  auto integrate_span = [&](double first, double last, bool first_touches, bool last_touches) {
    if (first_touches && last_touches) {
      const double half = 0.5 * (last - first);
      integrate_from(first, half);
      integrate_from(last, -half);
    } else if (last_touches) {
      integrate_from(last, first - last);
    } else {
      integrate_from(first, last - first);
    }
  };
  // the overlap's sign changes, sampled finely enough for the few a step's cubic may have
  constexpr int kSamples = 8;
  double before = 0.0, overlap_before = overlap(0.0);
  double span_start = overlap_before > 0.0 ? 0.0 : -1.0;
  for (int m = 1; m <= kSamples; ++m) {
    const double s = double(m) / kSamples, overlap_here = overlap(s);
    if ((overlap_before > 0.0) != (overlap_here > 0.0)) {
      std::uintmax_t iterations = 100;
      const auto [lo, hi] = boost::math::tools::toms748_solve(
          overlap, before, s, overlap_before, overlap_here,
          boost::math::tools::eps_tolerance<double>(48), iterations);
      const double root = 0.5 * (lo + hi);
      if (overlap_here > 0.0) {
        span_start = root;
      } else {
        integrate_span(span_start, root, span_start > 0.0, true);
        span_start = -1.0;
      }
    }
    before = s;
    overlap_before = overlap_here;
  }
  if (span_start >= 0.0) integrate_span(span_start, 1.0, span_start > 0.0, false);
  for (std::size_t i = 0; i < Stages; ++i) {
    const Force f = force(nodes[i]);
    out.impulse -= weights[i] * f.vector;
    out.magnitude -= weights[i] * f.magnitude;
  }
  return out;
}

}  // namespace mimpact::numerics::internal
