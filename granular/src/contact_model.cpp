#include "mimpact/granular/contact_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mimpact/common/error.hpp"
#include "mimpact/numerics/impulse_step_integrator.hpp"

namespace mimpact::granular {

double kinetic_energy(const ContactModel& model, const Eigen::VectorXd& velocity) {
  return 0.5 * model.mass.dot(velocity.cwiseAbs2());
}

void split_velocities(const ContactModel& model, const Eigen::VectorXd& generalized,
                      Eigen::VectorXd& velocity, Eigen::VectorXd& angular_velocity) {
  if (!model.rotation) {
    velocity = generalized;
    angular_velocity.resize(0);
    return;
  }
  const int d = model.dimension, r = model.rotation->components;
  velocity.resize(model.mass.size());
  angular_velocity.resize(r * model.body_count());
  for (Eigen::Index b = 0; b < model.body_count(); ++b) {
    velocity.segment(d * b, d) = generalized.segment((d + r) * b, d);
    angular_velocity.segment(r * b, r) = generalized.segment((d + r) * b + d, r);
  }
}

kernel::SimulationOptions simulation_options(const ContactModel& model) {
  kernel::SimulationOptions options;
  options.penetration_tolerance = 2.0 * model.touching_tolerance + model.largest_static_overlap;
  return options;
}

double lone_overlap(const ContactModel& model, Eigen::Index j) {
  const double u = model.u_minus(j);
  const numerics::ContactLaw& law = model.laws[std::size_t(j)];
  const double reduced_mass = 1.0 / model.H.coeff(j, j);
  // the energy of the approach, m u^2 / 2, all stored: K delta^(1+eta) / (1 + eta)
  return std::pow((1.0 + law.exponent) * reduced_mass * u * u / (2.0 * law.stiffness),
                  1.0 / (1.0 + law.exponent));
}

void check_impact_scales(const ContactModel& model,
                         const std::function<std::string(Eigen::Index)>& contact_name) {
  for (Eigen::Index j = 0; j < model.contact_count(); ++j) {
    const double u = model.u_minus(j);
    if (!(u < 0.0)) continue;
    const double energy = 0.5 * u * u / model.H.coeff(j, j);
    if (!(energy >= 1e-250 && energy <= 1e250))
      throw InvalidInput(
          "the contact of " + contact_name(j) +
          " approaches with the energy m u^2 / 2 = " + to_text(energy) + " J (u = " + to_text(u) +
          " m/s, m = " + to_text(1.0 / model.H.coeff(j, j)) +
          " kg); allowed: between 1e-250 and 1e250 J, where double precision resolves the "
          "impact (check the strikers' velocities and the radii and densities)");
  }
}

std::string faster_strikers_advice(bool moving) {
  return std::string(
             "allowed: faster strikers (strikers[].velocity: the overlaps grow with the "
             "speed), ") +
         (moving ? "the frozen geometry (compliant.geometry \"frozen\") " : "") +
         "or the LZB impact (\"method\": \"lzb\"), which needs no positions";
}

void check_overlap_resolved(double overlap, double largest_coordinate, const std::string& advice) {
  constexpr double kResolvedOverlap = 1e3;
  const double rounding = largest_coordinate * std::numeric_limits<double>::epsilon();
  if (!(overlap > kResolvedOverlap * rounding))
    throw InvalidInput("the impact's overlaps, about " + to_text(overlap) + " m, are within " +
                       to_text(kResolvedOverlap) +
                       " rounding errors of the bodies' coordinates (up to " +
                       to_text(largest_coordinate) +
                       " m): double precision cannot resolve them where the bodies are; " + advice);
}

void check_striker_gap(double gap, double reach, const std::string& field) {
  if (!(gap <= kFarthestGap * reach))
    throw InvalidInput(invalid_value_message(
        field, gap,
        "at most " + to_text(kFarthestGap * reach) +
            " m, 1e6 times the sum of the striker's and "
            "its target's radii: farther, the rounding of its flight nears the contacts' touching "
            "tolerance (1e-9 of the radii)"));
}

double impact_overlap(const ContactModel& model) {
  double smallest = INFINITY;
  for (Eigen::Index j = 0; j < model.contact_count(); ++j)
    if (model.u_minus(j) < 0.0) smallest = std::min(smallest, lone_overlap(model, j));
  return smallest;
}

namespace {

// m |v| of each moving body (its speed by stableNorm: |v| = 1e-170 does not square to 0)
template <class Pick>
double momentum(const ContactModel& model, double start, Pick pick) {
  double chosen = start;
  const int d = model.dimension;
  for (Eigen::Index b = 0; b < model.body_count(); ++b) {
    const double speed = model.velocity.segment(b * d, d).stableNorm();
    if (speed != 0.0) chosen = pick(chosen, model.mass(b * d) * speed);
  }
  return chosen;
}

}  // namespace

double smallest_momentum(const ContactModel& model) {
  return momentum(model, INFINITY, [](double a, double b) { return std::min(a, b); });
}

double largest_momentum(const ContactModel& model) {
  return momentum(model, 0.0, [](double a, double b) { return std::max(a, b); });
}

double natural_impulse(const ContactModel& model) {
  return numerics::natural_impulse(Eigen::VectorXd(model.H.diagonal()), model.u_minus);
}

void check_delta_p(const ContactModel& model, double delta_p, std::int64_t max_steps,
                   const std::string& field) {
  const double impulse = smallest_momentum(model);
  if (!(delta_p > 0.0 && delta_p < impulse))
    throw InvalidInput(invalid_value_message(field, delta_p,
                                             "0 < delta_p < the striker's momentum m V = " +
                                                 to_text(impulse) + " N s (best <= 1e-3 m V)"));
  const double largest = largest_momentum(model);
  if (!(largest / delta_p <= double(max_steps)))
    throw InvalidInput(invalid_value_message(
        field, delta_p,
        ">= P / max_steps = " + to_text(largest / double(max_steps)) + " N s, P = " +
            to_text(largest) + " N s the largest momentum: the impact would take at least P / " +
            "delta_p = " + rounded_text(largest / delta_p) +
            " impulse steps, more than impact.max_steps = " + std::to_string(max_steps) +
            " (raise it to allow more)"));
}

}  // namespace mimpact::granular
