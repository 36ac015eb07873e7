#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/tools/toms748_solve.hpp>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>

#include "mimpact/numerics/contact_law.hpp"

namespace mimpact::numerics {

// A Hertz force K delta^(3/2) between two spheres switches on where they touch (or off where
// they part) within a step, and there its second derivative is unbounded: a Runge-Kutta step's
// weights, exact for cubics, integrate it with an error of order h^2.5 in the velocity, where
// a smooth force errs as h^5. A large group of a packing has a touch or a parting in almost
// every step (docs/design/moving_geometry.md).
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
// order h^2.5 to h^5 (tests/numerics/test_onset_quadrature.cpp).
struct OnsetQuadrature {
  // N s / h: what the weights missed of the force on the second body (along the separation
  // from the first), and of the force's magnitude (the contact's impulse)
  Eigen::Vector3d impulse = Eigen::Vector3d::Zero();
  double magnitude = 0.0;
  // A bi-stiffness contact's (e < 1) history within the step, in order: where (a share of the
  // step) its overlap turned above the largest it had, which becomes its history (m), or where
  // it opened (its overlap fell to `opening`), where its history becomes 0.
  struct HistoryChange {
    double s = 0.0, history = 0.0;
  };
  std::array<HistoryChange, 4> changes{};
  std::size_t change_count = 0;
  // N s / h: what the position weights missed of the force's moment about the step's end,
  // integral over the step of F n (1 - s) ds - sum_i b_i F_i n_i (the positions err by h^2
  // this over the mass; amended where the force jumps, as an e = 0 contact's at its turn)
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
};

// The separation (m) of two bodies over a step in s = (t - t0) / h, the Hermite interpolant of its
// values r, rates times the step u = h r' and, if `quintic`, accelerations times its square
// a = h^2 r'' at the step's ends (cubic: error O(h^4); quintic: O(h^6), as the Nystrom step's
// own dense output).
struct StepSeparation {
  Eigen::Vector3d r0 = Eigen::Vector3d::Zero(), u0 = Eigen::Vector3d::Zero(),
                  a0 = Eigen::Vector3d::Zero();
  Eigen::Vector3d r1 = Eigen::Vector3d::Zero(), u1 = Eigen::Vector3d::Zero(),
                  a1 = Eigen::Vector3d::Zero();
  bool quintic = false;

  Eigen::Vector3d at(double s) const {
    const double s2 = s * s, s3 = s2 * s;
    if (!quintic)
      return (2.0 * s3 - 3.0 * s2 + 1.0) * r0 + (s3 - 2.0 * s2 + s) * u0 +
             (3.0 * s2 - 2.0 * s3) * r1 + (s3 - s2) * u1;
    const double s4 = s3 * s, s5 = s4 * s;
    return (1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5) * r0 +
           (s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5) * u0 +
           (0.5 * s2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5) * a0 +
           (10.0 * s3 - 15.0 * s4 + 6.0 * s5) * r1 + (-4.0 * s3 + 7.0 * s4 - 3.0 * s5) * u1 +
           (0.5 * s3 - s4 + 0.5 * s5) * a1;
  }
  // d/ds of at(s)
  Eigen::Vector3d rate(double s) const {
    const double s2 = s * s, s3 = s2 * s;
    if (!quintic)
      return (6.0 * s2 - 6.0 * s) * r0 + (3.0 * s2 - 4.0 * s + 1.0) * u0 +
             (6.0 * s - 6.0 * s2) * r1 + (3.0 * s2 - 2.0 * s) * u1;
    const double s4 = s3 * s;
    return (-30.0 * s2 + 60.0 * s3 - 30.0 * s4) * (r0 - r1) +
           (1.0 - 18.0 * s2 + 32.0 * s3 - 15.0 * s4) * u0 +
           (s - 4.5 * s2 + 6.0 * s3 - 2.5 * s4) * a0 + (-12.0 * s2 + 28.0 * s3 - 15.0 * s4) * u1 +
           (1.5 * s2 - 4.0 * s3 + 2.5 * s4) * a1;
  }
};

// The same for the force of any contact law along a model of the separation, with its history: the
// compliant law (contact_law.hpp: K delta^eta on loading, for e < 1 the stiffer curve from its
// largest overlap on unloading) that the step's right-hand side took at its nodes with the
// history `max_compression` (m) it began with, against the law as it is over the step, whose
// history changes where the overlap turns above it and where it opens (falls to `opening`, m)
// (docs/design/moving_geometry.md). Besides a touch and a parting, the force's corners lie where
// the overlap crosses the history (loading meets unloading) and the unloading curve's zero; the
// model is integrated between all of them, each span from its corners by the change of
// variable above, and the history's changes are returned.
struct ContactOverStep {
  double reach = 0.0;  // m: the sum of the radii, or the bead's radius against a wall
  ContactLaw law;
  double max_compression = 0.0;  // m: its history at the step's start
  double opening = 0.0;          // m: the overlap below which it forgets its history
};

// The step's own quadrature: its nodes c and the weights b of its velocities and b-bar of its
// positions (zero where only the velocities are amended).
template <std::size_t Stages>
struct StepQuadrature {
  const std::array<double, Stages>& nodes;
  const std::array<double, Stages>& weights;
  const std::array<double, Stages>& position_weights;
};

namespace detail {

// contact_step_quadrature's stages: the force along the model, the spans of one history between
// its corners, the history's changes, and what the step's own weights took.
class ContactStepQuadrature {
 public:
  ContactStepQuadrature(const StepSeparation& model, const ContactOverStep& contact)
      : model_(model),
        contact_(contact),
        hysteretic_(contact.law.restitution < 1.0),
        hertz_(!hysteretic_ && contact.law.exponent == 1.5) {}

  // The force along the model and its history's changes, from the step's start to its end.
  void integrate_over_step() {
    double from = 0.0, history = contact_.max_compression;
    bool turned = false;  // the last change
    while (hysteretic_ && out_.change_count < out_.changes.size()) {
      const double turn =
          first_crossing([&](double s) { return closing(s); }, from, turned,
                         [&](double at) { return overlap(at) > std::max(history, 0.0); });
      const double open =
          history > 0.0 ? first_crossing([&](double s) { return contact_.opening - overlap(s); },
                                         from, false, [](double) { return true; })
                        : 2.0;
      const double next = std::min(turn, open);
      if (next > 1.0) break;
      integrate_part(from, next, history);
      turned = next == turn;
      history = turned ? overlap(turn) : 0.0;
      out_.changes[out_.change_count++] = {.s = next, .history = history};
      from = next;
    }
    integrate_part(from, 1.0, history);
  }

  // Less what the right-hand side took at the step's nodes.
  template <std::size_t Stages>
  OnsetQuadrature less_the_step(const StepQuadrature<Stages>& step) {
    for (std::size_t i = 0; i < Stages; ++i) {
      const Force f = force(step.nodes[i], contact_.max_compression);
      out_.impulse -= step.weights[i] * f.vector;
      out_.magnitude -= step.weights[i] * f.magnitude;
      out_.moment -= step.position_weights[i] * f.vector;
    }
    return out_;
  }

 private:
  static constexpr int kSamples = 8;  // fine enough for the few corners a step's cubic may have
  using Gauss = boost::math::quadrature::gauss<double, 8>;
  struct Force {
    Eigen::Vector3d vector = Eigen::Vector3d::Zero();
    double magnitude = 0.0;
  };

  double overlap(double s) const { return contact_.reach - model_.at(s).norm(); }
  // r . r': from closing to opening where it crosses 0
  double closing(double s) const { return model_.at(s).dot(model_.rate(s)); }

  Force force(double s, double history) const {
    const Eigen::Vector3d r = model_.at(s);
    const double distance = r.norm(), delta = contact_.reach - distance;
    Force f;
    if (delta <= 0.0) return f;
    // (an elastic Hertz force written as the right-hand side writes it, to its last bit)
    f.magnitude = hertz_ ? hertz_force(contact_.law.stiffness, delta)
                         : hysteresis_force(contact_.law, delta, history);
    f.vector = (f.magnitude / distance) * r;
    return f;
  }

  template <class F>
  static double root(F&& f, double a, double b, double fa, double fb) {
    if (fb == 0.0) return b;
    std::uintmax_t iterations = 100;
    const auto [lo, hi] = boost::math::tools::toms748_solve(
        f, a, b, fa, fb, boost::math::tools::eps_tolerance<double>(48), iterations);
    return 0.5 * (lo + hi);
  }

  // One span of one history, by Gauss-Legendre in u with s = end + length u^2 (length < 0: the
  // span ends at `end`), smooth across a touch at `end`.
  void integrate_from(double end, double length, double history) {
    const auto& x = Gauss::abscissa();
    const auto& w = Gauss::weights();
    for (std::size_t k = 0; k < x.size(); ++k)
      for (const double sign : {-1.0, 1.0}) {
        // u on [0, 1] (Gauss weight w / 2), ds = 2 |length| u du
        const double u = 0.5 * (1.0 + sign * x[k]);
        const double s = end + length * u * u;
        const Force f = force(s, history);
        out_.impulse += w[k] * std::abs(length) * u * f.vector;
        out_.moment += (w[k] * std::abs(length) * u * (1.0 - s)) * f.vector;
        out_.magnitude += w[k] * std::abs(length) * u * f.magnitude;
      }
  }

  // The spans of one history, from its corners (where the overlap crosses the force's zero or
  // loading's start).
  void integrate_part(double from, double to, double history) {
    const double e = contact_.law.restitution;
    std::array<double, 2> thresholds{0.0, -1.0};  // the force's zero, and loading's start
    if (hysteretic_ && history > 0.0) thresholds = {history * (1.0 - e * e), history};
    std::array<double, 2 + 2 * kSamples> corner{};  // ascending: the part's ends, then roots
    std::array<bool, 2 + 2 * kSamples> touches{};
    std::size_t count = 0;
    corner[count++] = from;
    double before = from, overlap_before = overlap(from);
    for (int m = 1; m <= kSamples; ++m) {
      const double s = from + (to - from) * double(m) / kSamples, overlap_here = overlap(s);
      std::array<double, 2> found{};
      std::size_t here = 0;
      for (const double threshold : thresholds) {
        if (threshold < 0.0 || (overlap_before > threshold) == (overlap_here > threshold)) continue;
        found[here++] = root([&](double t) { return overlap(t) - threshold; }, before, s,
                             overlap_before - threshold, overlap_here - threshold);
      }
      if (here == 2 && found[1] < found[0]) std::swap(found[0], found[1]);
      for (std::size_t k = 0; k < here; ++k) {
        touches[count] = true;
        corner[count++] = found[k];
      }
      before = s;
      overlap_before = overlap_here;
    }
    corner[count++] = to;
    for (std::size_t k = 0; k + 1 < count; ++k) {
      const double first = corner[k], last = corner[k + 1];
      if (!(last > first) || force(0.5 * (first + last), history).magnitude == 0.0) continue;
      if (touches[k] && touches[k + 1]) {
        const double half = 0.5 * (last - first);
        integrate_from(first, half, history);
        integrate_from(last, -half, history);
      } else if (touches[k + 1]) {
        integrate_from(last, first - last, history);
      } else {
        integrate_from(first, last - first, history);
      }
    }
  }

  // Where f first crosses from < 0 to >= 0 after `from` at a point `accept` takes, 2 if nowhere;
  // `crossed`: f's own crossing is at `from`, the last change: the next needs f < 0 again.
  template <class F, class Accept>
  double first_crossing(F&& f, double from, bool crossed, Accept&& accept) const {
    double before = from, value_before = crossed ? 0.0 : f(from);
    for (int m = 1; m <= kSamples; ++m) {
      const double s = from + (1.0 - from) * double(m) / kSamples, value_here = f(s);
      if (value_before < 0.0 && value_here >= 0.0) {
        const double at = root(f, before, s, value_before, value_here);
        if (accept(at)) return at;
      }
      before = s;
      value_before = value_here;
    }
    return 2.0;  // none
  }

  const StepSeparation& model_;
  const ContactOverStep& contact_;
  bool hysteretic_, hertz_;
  OnsetQuadrature out_;
};

}  // namespace detail

template <std::size_t Stages>
OnsetQuadrature contact_step_quadrature(const StepSeparation& model, const ContactOverStep& contact,
                                        const StepQuadrature<Stages>& step) {
  detail::ContactStepQuadrature quadrature(model, contact);
  quadrature.integrate_over_step();
  return quadrature.less_the_step(step);
}

// The same for an elastic Hertz contact along the cubic Hermite of its separation (m) from the
// second sphere's centre to the first's, r0 at the step's start and r1 at its end, with its rates
// times the step, u0 = h r0', u1 = h r1' (m); `reach` (m) the sum of the radii, `stiffness` K
// (N / m^(3/2)); the step's velocity weights b at its nodes c.
template <std::size_t Stages>
OnsetQuadrature hertz_onset_quadrature(const StepSeparation& separation, double reach,
                                       double stiffness, const std::array<double, Stages>& nodes,
                                       const std::array<double, Stages>& weights) {
  static constexpr std::array<double, Stages> kNoPositions{};
  const ContactLaw hertz{.stiffness = stiffness, .exponent = 1.5, .restitution = 1.0};
  return contact_step_quadrature(separation, {.reach = reach, .law = hertz},
                                 StepQuadrature<Stages>{nodes, weights, kNoPositions});
}

}  // namespace mimpact::numerics
