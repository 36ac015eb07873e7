#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "mimpact/numerics/contact_law.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::analysis {

// One impact seen through its generalized velocities: v(P) = v- + mobility P, mobility = M^-1 W.
struct ImpactProblemData {
  Eigen::SparseMatrix<double> H;
  Eigen::VectorXd u_minus;
  std::vector<numerics::ContactLaw> laws;
  Eigen::SparseMatrix<double> mobility;  // n_dof x contacts
  Eigen::VectorXd velocity_before;       // v-
};

// The comparison of the paper's appendix A.2 (eqs. 46-49) between runs at delta_p = h and h/2:
// eta_h(P) = ||v_h(P) - v_(h/2)(P)||_inf / ||v_(h/2)(P)||_inf along the principal impulse P
// (past the end of a run its velocities are the post-impact ones), and
// eta+_h = ||v+_h - v+_(h/2)||_inf / ||v+_(h/2)||_inf.
struct ConvergenceRow {
  double delta_p = 0.0;
  std::int64_t steps = 0;
  double wall_time = 0.0;  // s, of the run at delta_p
  double max_eta = 0.0;    // max over P of eta_h(P)
  double eta_plus = 0.0;   // eta+_h
  bool converged = false;  // max_eta <= epsilon and eta_plus <= epsilon_plus
};

struct ConvergenceStudy {
  std::vector<ConvergenceRow> rows;
  Eigen::VectorXd extrapolated_velocities;  // Richardson, 2 v+_(h/2) - v+_h, of the last pair
  Eigen::VectorXd finest_velocities;        // v+ of the finest run
  bool converged = false;
  // Why the study ended before max_halvings without converging ("" otherwise): the next run
  // would store more samples than ConvergenceOptions::max_sample_bytes.
  std::string stopped;
};

// What a study runs and when it stops.
struct ConvergenceOptions {
  double first_delta_p = 0.0;       // h of the first row (N s)
  double epsilon_plus = 0.01;       // bound on eta+_h (criterion 49)
  double epsilon = 0.01;            // bound on max eta_h (criterion 48)
  int max_halvings = 12;            // rows at most
  numerics::LzbOptions integrator;  // every run's options but delta_p and sampling
  // The comparison along the impact keeps every step of a run (P and v): a study stops before
  // a halving whose runs would hold more than this (bytes).
  double max_sample_bytes = 4e9;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("first_delta_p", self.first_delta_p, positive("N s"));
    field("epsilon_plus", self.epsilon_plus, positive());
    field("epsilon", self.epsilon, positive());
    field("max_halvings", self.max_halvings, at_least(1));
    field("integrator", self.integrator);
    field("max_sample_bytes", self.max_sample_bytes, positive("bytes"));
  }
};

// Runs delta_p = h, h/2, h/4, ... and fills a row per h from its run and the next; stops at
// the first h that meets both criteria, or after `max_halvings` rows. Stores O(steps x dof)
// samples of one run at a time.
ConvergenceStudy study_convergence(const ImpactProblemData& problem,
                                   const ConvergenceOptions& options);

// One row: the runs at h = options.first_delta_p and h/2.
ConvergenceRow compare_step_sizes(const ImpactProblemData& problem,
                                  const ConvergenceOptions& options);

}  // namespace mimpact::analysis
