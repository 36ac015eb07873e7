#include "mimpact/analysis/lzb_convergence.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "mimpact/common/error.hpp"

namespace mimpact::analysis {

namespace {

// A run's generalized velocities v(P) at every step, stored flat (P, then n values a sample).
struct Run {
  numerics::ImpactResult result;
  double wall_time = 0.0;
  Eigen::Index dof = 0;
  std::vector<double> principal, velocities;
  Eigen::VectorXd velocity_after;

  // v at P, linear between samples; the post-impact velocity past the end
  void velocity_at(double p, std::size_t& cursor, Eigen::VectorXd& out) const {
    const std::size_t count = principal.size();
    if (count == 0 || p >= principal.back()) {
      out = velocity_after;
      return;
    }
    while (cursor + 1 < count && principal[cursor + 1] < p) ++cursor;
    const double p0 = principal[cursor], p1 = principal[cursor + 1];
    const double w = p1 > p0 ? std::clamp((p - p0) / (p1 - p0), 0.0, 1.0) : 0.0;
    const Eigen::Map<const Eigen::VectorXd> a(&velocities[cursor * std::size_t(dof)], dof);
    const Eigen::Map<const Eigen::VectorXd> b(&velocities[(cursor + 1) * std::size_t(dof)], dof);
    out = (1.0 - w) * a + w * b;
  }
};

double relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const double scale = b.cwiseAbs().maxCoeff();
  return scale > 0.0 ? (a - b).cwiseAbs().maxCoeff() / scale : (a - b).cwiseAbs().maxCoeff();
}

// Stores the samples (when `keep`) and compares each with the coarser run at the same P.
class Sampler : public numerics::ImpactObserver {
 public:
  Sampler(const ImpactProblemData& problem, Run& run, const Run* coarser)
      : problem_(problem), run_(run), coarser_(coarser) {}
  void observe(const numerics::ImpactSample& sample) override {
    impulse_ = Eigen::Map<const Eigen::VectorXd>(sample.impulse.data(),
                                                 Eigen::Index(sample.impulse.size()));
    velocity_ = problem_.velocity_before + problem_.mobility * impulse_;
    run_.principal.push_back(sample.principal_impulse);
    run_.velocities.insert(run_.velocities.end(), velocity_.data(),
                           velocity_.data() + velocity_.size());
    if (coarser_) {
      coarser_->velocity_at(sample.principal_impulse, cursor_, other_);
      max_eta = std::max(max_eta, relative(other_, velocity_));
    }
  }
  double max_eta = 0.0;  // eta_h(P) at its largest so far

 private:
  const ImpactProblemData& problem_;
  Run& run_;
  const Run* coarser_;
  Eigen::VectorXd impulse_, velocity_, other_;
  std::size_t cursor_ = 0;
};

// Runs at delta_p, compared along P with `coarser` when given.
Run run(const ImpactProblemData& problem, numerics::LzbOptions options, double delta_p,
        const Run* coarser, double& max_eta) {
  options.delta_p = delta_p;
  options.relative_delta_p.reset();  // each row's step is the study's
  options.sample_every = 1;
  options.sampled_contacts.clear();
  numerics::LzbImpulseIntegrator integrator(options);
  Run measured;
  measured.dof = problem.velocity_before.size();
  Sampler sampler(problem, measured, coarser);
  const auto start = std::chrono::steady_clock::now();
  measured.result = integrator.integrate(problem.H, problem.u_minus, problem.laws, &sampler);
  measured.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (measured.result.status != numerics::ImpactStatus::terminated)
    throw Error("convergence study: " + measured.result.message);
  measured.velocity_after = problem.velocity_before + problem.mobility * measured.result.impulse;
  max_eta = sampler.max_eta;
  return measured;
}

ConvergenceRow row_of(const Run& coarse, const Run& fine, double max_eta, double h,
                      const ConvergenceOptions& options) {
  ConvergenceRow row;
  row.delta_p = h;
  row.steps = coarse.result.steps;
  row.wall_time = coarse.wall_time;
  row.max_eta = max_eta;
  row.eta_plus = relative(coarse.velocity_after, fine.velocity_after);
  row.converged = row.max_eta <= options.epsilon && row.eta_plus <= options.epsilon_plus;
  return row;
}

}  // namespace

ConvergenceRow compare_step_sizes(const ImpactProblemData& problem,
                                  const ConvergenceOptions& options) {
  validate(options, "convergence study");
  const double h = options.first_delta_p;
  double unused = 0.0, max_eta = 0.0;
  const Run coarse = run(problem, options.integrator, h, nullptr, unused);
  const Run fine = run(problem, options.integrator, h / 2, &coarse, max_eta);
  return row_of(coarse, fine, max_eta, h, options);
}

ConvergenceStudy study_convergence(const ImpactProblemData& problem,
                                   const ConvergenceOptions& options) {
  validate(options, "convergence study");
  ConvergenceStudy study;
  double h = options.first_delta_p, unused = 0.0;
  Run coarse = run(problem, options.integrator, h, nullptr, unused);
  for (int k = 0; k < options.max_halvings; ++k, h /= 2) {
    // the run at h/2 takes about twice the steps of the run at h, and both are held at once, in
    // vectors that grow by doubling
    const double bytes = 6.0 * double(coarse.principal.size()) * double(coarse.dof + 1) * 8.0;
    if (bytes > options.max_sample_bytes) {
      study.stopped = "the run at delta_p = " + to_text(h / 2) + " N s would hold about " +
                      to_text(std::round(bytes / 1e8) / 10.0) + " GB of samples, above the " +
                      to_text(std::round(options.max_sample_bytes / 1e8) / 10.0) +
                      " GB allowed; loosen the bounds, allow more memory or use the adaptive "
                      "integrator (\"integrator\": \"adaptive\")";
      break;
    }
    double max_eta = 0.0;
    Run fine = run(problem, options.integrator, h / 2, &coarse, max_eta);
    study.rows.push_back(row_of(coarse, fine, max_eta, h, options));
    study.extrapolated_velocities = 2.0 * fine.velocity_after - coarse.velocity_after;
    study.finest_velocities = fine.velocity_after;
    if (study.rows.back().converged) {
      study.converged = true;
      break;
    }
    coarse = std::move(fine);
  }
  return study;
}

}  // namespace mimpact::analysis
