#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mimpact/numerics/contact_law.hpp"
#include "mimpact/numerics/delassus.hpp"
#include "mimpact/numerics/impact_observer.hpp"
#include "mimpact/numerics/impact_result.hpp"
#include "mimpact/numerics/tangential_rows.hpp"

// The seam of every way of integrating an LZB impact (the impulse steps, the asynchronous steps,
// the adaptive integration of the continuous limit, and the next ones): one interface, one law
// table, one check of the input and one assembly of the result (Drake's IntegratorBase).
namespace mimpact::numerics {

// What every integrator reads of contact j's law, computed once per impact (docs/model.md,
// section 3): one row of 64 bytes, read together in the step loops.
struct LawConstants {
  double coefficient = 0.0;        // F = coefficient * E^power: c(eta) K^(1/(1+eta))
  double power = 0.0;              // eta / (1 + eta)
  double one_plus_exponent = 0.0;  // 1 + eta
  double stiffness = 0.0;          // K (N/m^eta)
  double exponent = 0.0;           // eta
  double restitution = 0.0;        // e, 0 below ContactLaw::kNegligibleRestitution
  double inverse_e2 = 0.0;         // 1 / e^2 (0 for e = 0): the bi-stiffness expansion's rate
  bool mono_stiffness = false;
};

// The law constants of an impact's contacts, one row each, and their Coulomb coefficients
// apart (read only where an impact has friction).
class LawTable {
 public:
  void assign(std::span<const ContactLaw> laws);
  const LawConstants& operator[](std::size_t j) const { return rows_[j]; }
  const LawConstants* data() const { return rows_.data(); }
  std::size_t size() const { return rows_.size(); }
  double friction(std::size_t j) const { return friction_[j]; }
  bool frictional() const { return frictional_; }  // some contact's friction > 0

 private:
  std::vector<LawConstants> rows_;
  std::vector<double> friction_;
  bool frictional_ = false;
};

// An integrator of the LZB impact. The caller gives the Delassus operator H and u-, or the
// Delassus object, whose mobility M^-1 W lets an integrator follow the bodies rather than the
// contacts; the base checks them, fills the law table, runs the integrator and assembles the
// result: u+ = u- + H P, the residual energy, and the check that nothing overflowed.
class ImpactIntegrator {
 public:
  virtual ~ImpactIntegrator() = default;

  // The name a scene chooses it by: "impulse-step", "asynchronous", "adaptive".
  virtual std::string_view name() const = 0;

  // u_minus: pre-impact relative velocities (at least one < 0); laws: one per contact; H
  // symmetric with a positive diagonal. Throws InvalidInput naming a bad entry, and Error when
  // the impact's velocities, forces or duration overflow double precision.
  ImpactResult integrate(const Eigen::SparseMatrix<double>& H, const Eigen::VectorXd& u_minus,
                         std::span<const ContactLaw> laws, ImpactObserver* observer = nullptr);
  ImpactResult integrate(const Eigen::MatrixXd& H, const Eigen::VectorXd& u_minus,
                         std::span<const ContactLaw> laws, ImpactObserver* observer = nullptr);
  ImpactResult integrate(const Delassus& delassus, const Eigen::VectorXd& u_minus,
                         std::span<const ContactLaw> laws, ImpactObserver* observer = nullptr);
  // With Coulomb friction: the tangential rows beside H; each contact's coefficient is its
  // law's `friction`. The result adds P_t, s+ and the slip work (ImpactResult). Throws
  // InvalidInput naming the entry for a bad block, and for a friction > 0 when this integrator
  // does not integrate friction.
  ImpactResult integrate(const Eigen::SparseMatrix<double>& H, const Eigen::VectorXd& u_minus,
                         std::span<const ContactLaw> laws, const TangentialRows& tangential,
                         ImpactObserver* observer = nullptr);
  // Whether run() integrates the tangential impulses of contacts with friction > 0.
  virtual bool integrates_friction() const { return false; }

  // The contacts the observer sees in the next impacts (empty: all of them).
  void set_sampled_contacts(std::vector<Eigen::Index> contacts) {
    sampled_contacts_ = std::move(contacts);
  }
  // The approach speed below which contact j counts as separated at the end of an impact
  // (m/s): what the integrator resolves, for H's diagonal and u-.
  virtual Eigen::VectorXd velocity_resolution(const Eigen::VectorXd& diagonal,
                                              const Eigen::VectorXd& u_minus) const = 0;

  // One impact, checked: H compressed, its diagonal, u-, the law table; the mobility when the
  // caller gave it; the tangential rows and H_tn^T (compressed) when it gave them.
  struct Input {
    const Eigen::SparseMatrix<double>& H;
    const Eigen::VectorXd& diagonal;
    const Eigen::VectorXd& u_minus;
    const LawTable& laws;
    const Eigen::SparseMatrix<double>* mobility = nullptr;
    const TangentialRows* tangential = nullptr;
    const Eigen::SparseMatrix<double>* tangent_to_normal = nullptr;  // H_tn^T: contacts x rows
  };

 protected:
  // sampled_contacts: those the observer sees (empty: all of them)
  explicit ImpactIntegrator(std::vector<Eigen::Index> sampled_contacts)
      : sampled_contacts_(std::move(sampled_contacts)) {}
  ImpactIntegrator(const ImpactIntegrator&) = default;
  ImpactIntegrator(ImpactIntegrator&&) noexcept = default;
  ImpactIntegrator& operator=(const ImpactIntegrator&) = default;
  ImpactIntegrator& operator=(ImpactIntegrator&&) noexcept = default;

  // Fills the result's per-contact fields (impulse, max_force, time_of_max_force, work,
  // stored_energy) and counts (steps, contact_steps, duration, status, message).
  virtual void run(const Input& input, ImpactObserver* observer, ImpactResult& result) = 0;
  // What the observer is sent through: the sampled contacts' values, gathered. Reset for each
  // impact before run().
  ImpactSampler& sampler() { return sampler_; }

 private:
  // The caller's impact: H, u-, the laws, and the mobility and tangential rows it gave.
  struct Given {
    const Eigen::SparseMatrix<double>& H;
    const Eigen::VectorXd& u_minus;
    std::span<const ContactLaw> laws;
    const Eigen::SparseMatrix<double>* mobility = nullptr;
    const TangentialRows* tangential = nullptr;
  };
  ImpactResult integrate_checked(const Given& given, ImpactObserver* observer);
  void assemble(const Given& given, const Eigen::SparseMatrix<double>* tangent_to_normal,
                ImpactResult& result) const;

  std::vector<Eigen::Index> sampled_contacts_;
  ImpactSampler sampler_;
  LawTable laws_;
};

}  // namespace mimpact::numerics
