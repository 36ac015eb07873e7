#pragma once

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "mimpact/granular/contact_model.hpp"
#include "mimpact/granular/impact_outcome.hpp"

namespace mimpact::granular {

// Where the kinetic energy of a scene's impacts went (J):
//   kinetic_before + rotational_before + potential_before + work_of_forces
//     = kinetic_after + rotational_after + dissipated_total + potential_left,
// to round-off for every method: each accounts the contacts' work by the trapezoidal rule over
// its own steps, which the velocities follow exactly (docs/model.md, sections 12 and 16).
struct EnergyLedger {
  double kinetic_before = 0.0, kinetic_after = 0.0;        // of the translations
  double rotational_before = 0.0, rotational_after = 0.0;  // of the rotations
  Eigen::VectorXd slip;           // per contact: the work its friction took (empty: no friction)
  double potential_before = 0.0;  // held by the contacts at the start (a precompression)
  double work_of_forces = 0.0;    // done by the bodies' own forces (the precompression)
  // per contact: its work (normal and slip) + its potential energy before - after
  Eigen::VectorXd dissipated;
  // the contacts the bodies formed as they moved, beyond the model's: in the two totals below
  FormedContacts formed;
  double dissipated_total = 0.0;
  double potential_left = 0.0;  // held by the contacts at the end (LZB: below its tolerance)
  // the two sides' difference (J), round-off
  double imbalance() const;
};

EnergyLedger energy_ledger(const ContactModel& model, const ImpactOutcome& impact);

// The energy ledger as summary.json has it ("energy").
nlohmann::ordered_json ledger_json(const EnergyLedger& ledger);

}  // namespace mimpact::granular
