#include "mimpact/granular/energy_ledger.hpp"

#include <cmath>
#include <vector>

#include "mimpact/common/error.hpp"

namespace mimpact::granular {

double EnergyLedger::imbalance() const {
  return kinetic_before + rotational_before + potential_before + work_of_forces -
         (kinetic_after + rotational_after + dissipated_total + potential_left);
}

EnergyLedger energy_ledger(const ContactModel& model, const ImpactOutcome& impact) {
  EnergyLedger ledger;
  ledger.kinetic_before = kinetic_energy(model, model.velocity);
  ledger.kinetic_after = kinetic_energy(model, impact.velocity_after);
  const Eigen::Index m = model.contact_count();
  const Eigen::VectorXd& stored_after = impact.result.stored_energy;
  const Eigen::VectorXd stored_before = impact.stored_energy_at_start.size() == m
                                            ? impact.stored_energy_at_start
                                            : Eigen::VectorXd::Zero(m);
  if (impact.result.work.size() != m || stored_after.size() != m)
    throw Error("the impact's method kept no energy ledger (nonlinear relations)");
  ledger.potential_before = stored_before.sum();
  ledger.work_of_forces = impact.work_of_forces;
  ledger.dissipated = impact.result.work + stored_before - stored_after;
  if (model.rotation) {
    ledger.rotational_before = rotational_energy(*model.rotation, model.rotation->angular_velocity);
    ledger.rotational_after = rotational_energy(*model.rotation, impact.angular_velocity_after);
    ledger.slip =
        impact.result.slip_work.size() == m ? impact.result.slip_work : Eigen::VectorXd::Zero(m);
    ledger.dissipated += ledger.slip;
  }
  ledger.formed = impact.formed;
  ledger.dissipated_total = ledger.dissipated.sum() + ledger.formed.dissipated;
  ledger.potential_left = stored_after.sum() + ledger.formed.potential_left;
  return ledger;
}

nlohmann::ordered_json ledger_json(const EnergyLedger& ledger) {
  const Eigen::VectorXd& d = ledger.dissipated;
  nlohmann::ordered_json json{{"kinetic_before", ledger.kinetic_before},
                              {"potential_before", ledger.potential_before},
                              {"work_of_forces", ledger.work_of_forces},
                              {"kinetic_after", ledger.kinetic_after},
                              {"dissipated", std::vector<double>(d.data(), d.data() + d.size())},
                              {"dissipated_total", ledger.dissipated_total},
                              {"potential_left", ledger.potential_left}};
  if (ledger.formed.count > 0)
    json["formed_contacts"] = {{"count", ledger.formed.count},
                               {"dissipated", ledger.formed.dissipated},
                               {"potential_left", ledger.formed.potential_left}};
  if (ledger.slip.size() > 0 || ledger.rotational_before > 0.0) {  // the bodies turn
    const Eigen::VectorXd& slip = ledger.slip;
    json["rotational_before"] = ledger.rotational_before;
    json["rotational_after"] = ledger.rotational_after;
    json["slip"] = std::vector<double>(slip.data(), slip.data() + slip.size());
    json["slip_total"] = slip.sum();
  }
  return json;
}

}  // namespace mimpact::granular
