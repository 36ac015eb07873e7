#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <optional>
#include <vector>

#include "mimpact/common/fields.hpp"

namespace mimpact::numerics {

// The options of the integrators that take steps of the principal impulse
// (ImpulseStepIntegrator: LzbImpulseIntegrator, LzbAsynchronousIntegrator).
struct LzbOptions {
  static constexpr Allowed kRelativeDeltaPRange =
      within(0.0, 1.0, "a share of each impact's natural impulse", true, true);

  // Delta P, the step of the principal impulse (N s). The scheme is first order in it.
  double delta_p = 1e-5;
  // Or, for each impact, delta_p = relative_delta_p * natural_impulse(H's diagonal, u-): this
  // share of the impulse that stops its fastest contact alone, so that impacts of very different
  // strengths (a ball's shrinking bounces) are resolved alike. delta_p stays where that impulse
  // underflows to 0.
  std::optional<double> relative_delta_p;
  // A contact takes part in the impact while E_j > tol_E_j or u_j < -tol_u_j, and the impact
  // ends when no contact does, with
  //   tol_u_j = termination_velocity_factor * H_jj * delta_p
  // (a fraction of the velocity change one principal step makes at contact j: what the
  // discrete impulse dynamics can resolve) and tol_E_j = tol_u_j^2 / (2 H_jj) (the energy
  // that, released at contact j, changes u_j by tol_u_j). Both vanish with delta_p, so the
  // result converges as delta_p -> 0 without tuning. The default 0.1 lets the wave front in
  // early enough (docs/validation.md).
  double termination_velocity_factor = 0.1;
  // Fixed thresholds in place of the scaled ones, as Siconos has them: kept to reproduce
  // published runs. They do not vanish with delta_p, so below some delta_p the result stops
  // converging (C3 of Nguyen & Brogliato's table 4 below 1e-6, where the scaled ones converge).
  struct FixedThresholds {
    double velocity = 0.0;  // m/s: tol_u_j
    double energy = 0.0;    // J: tol_E_j

    template <class Self, class Visit>
    static void visit_fields(Self& self, Visit&& field) {
      field("velocity", self.velocity, positive("m/s").needed());
      field("energy", self.energy, positive("J").needed());
    }
  };
  std::optional<FixedThresholds> fixed_thresholds;
  // The impact is abandoned (status step_limit) after this many steps.
  std::int64_t max_steps = 1'000'000'000;
  // The observer sees the state every this many steps (0: only at the start and the end).
  std::int64_t sample_every = 0;
  // Contacts the observer sees (empty: all of them), until set_sampled_contacts changes them.
  std::vector<Eigen::Index> sampled_contacts;
  // Impacts among at most this many contacts read a dense copy of H, faster than its
  // compressed columns; larger ones the sparse H, whose steps cost in proportion to the
  // contacts taking part.
  Eigen::Index dense_up_to = 16;

  // tol_u_j and tol_E_j of a contact whose Delassus diagonal is h_jj (1 / kg)
  double velocity_tolerance(double h_jj) const;
  double energy_tolerance(double h_jj) const;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("delta_p", self.delta_p, positive("N s"));
    field("relative_delta_p", self.relative_delta_p, kRelativeDeltaPRange);
    field("termination_velocity_factor", self.termination_velocity_factor, positive());
    field("fixed_thresholds", self.fixed_thresholds);
    field("max_steps", self.max_steps, at_least(1));
    field("sample_every", self.sample_every, at_least(0, "0: start and end only"));
    field("sampled_contacts", self.sampled_contacts, at_least(0, "contact indices"));
    field("dense_up_to", self.dense_up_to, within(0, 2147483648.0));
  }
};

}  // namespace mimpact::numerics
