#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "mimpact/numerics/tangential_rows.hpp"

namespace mimpact::numerics {

// The state of an impact at one impulse step, for the contacts being sampled. The spans
// point into the integrator's buffers: copy what you keep.
struct ImpactSample {
  std::int64_t step = 0;  // impulse steps taken so far
  double time = 0.0;      // s since the impact began
  // the independent variable P: the primary contacts' impulse steps summed (N s); each is
  // delta_p but the last of a primary's phase, which ends where the phase does
  double principal_impulse = 0.0;
  std::span<const Eigen::Index> contacts;  // which contacts the arrays describe
  std::span<const double> velocity;        // relative normal velocity u (m/s, < 0 approaching)
  std::span<const double> energy;          // potential energy E (J)
  std::span<const double> force;           // contact force F in the last step (N)
  std::span<const double> impulse;         // cumulated impulse P (N s)
  // with friction: the cumulated tangential impulse P_t (N s) of the sampled contacts' tangential
  // rows (TangentialRows), contact after contact in the order of `contacts`; else empty
  std::span<const double> tangential_impulse;
};

// Where an integrator is, whatever it samples: what a progress meter shows and its clock reads.
struct ImpactProgress {
  std::int64_t step = 0;
  double time = 0.0;                                                    // s, from the first contact
  double principal_impulse = std::numeric_limits<double>::quiet_NaN();  // N s, where it is kept
};

// observe: called at the first step, every `sample_every` steps and at the end of an impact.
// progressed: every kProgressSteps steps of the impulse steps, every step of the adaptive
// integrator (whose steps may advance no sample time), whatever is sampled; nothing by default.
class ImpactObserver {
 public:
  static constexpr std::int64_t kProgressSteps = 65'536;

  virtual ~ImpactObserver() = default;
  virtual void observe(const ImpactSample& sample) = 0;
  virtual void progressed(const ImpactProgress& /*where*/) {}
};

// When a loop of steps next tells its observer something: a sample every `sample_every` steps
// (0: none), where it is every ImpactObserver::kProgressSteps; never without an observer. One
// comparison a step, as the impulse steps' loops can afford.
class ObserverSchedule {
 public:
  ObserverSchedule(const ImpactObserver* observer, std::int64_t sample_every);
  bool due(std::int64_t step) const { return step == next_; }
  // At a due step: whether it is a sample's, whether a progress report's; sets the next.
  struct Due {
    bool sample = false, progress = false;
  };
  Due take(std::int64_t step);

 private:
  std::int64_t next_of(std::int64_t step) const;

  std::int64_t sample_every_;
  std::int64_t next_;
};

// What an impact integrator hands its observer: the contacts sampled and their values at the
// current sample, in buffers reused from one sample to the next.
class ImpactSampler {
 public:
  // Samples `contacts`, or all `contact_count` contacts when it is empty, and with `rows` their
  // tangential rows too.
  void reset(std::span<const Eigen::Index> contacts, std::size_t contact_count,
             const TangentialRows* rows = nullptr);
  // Calls value_of(j, velocity, energy, force, impulse) to fill each sampled contact j's
  // values, then passes the sample to the observer.
  template <class ValueOf>
  void observe(ImpactObserver& observer, std::int64_t step, double time, double principal_impulse,
               ValueOf&& value_of) {
    for (std::size_t k = 0; k < contacts_.size(); ++k)
      value_of(contacts_[k], velocity_[k], energy_[k], force_[k], impulse_[k]);
    send(observer, step, time, principal_impulse);
  }
  // The same, with each sampled tangential row r's P_t from tangential_of(r).
  template <class ValueOf, class TangentialOf>
  void observe(ImpactObserver& observer, std::int64_t step, double time, double principal_impulse,
               ValueOf&& value_of, TangentialOf&& tangential_of) {
    for (std::size_t i = 0; i < tangential_rows_.size(); ++i)
      tangential_[i] = tangential_of(tangential_rows_[i]);
    observe(observer, step, time, principal_impulse, value_of);
  }

 private:
  void send(ImpactObserver& observer, std::int64_t step, double time, double principal_impulse);

  std::vector<Eigen::Index> contacts_;
  std::vector<double> velocity_, energy_, force_, impulse_;
  std::vector<Eigen::Index> tangential_rows_;  // of the sampled contacts, in their order
  std::vector<double> tangential_;
};

// Keeps every sample: one row per sample, one column per sampled contact.
class ImpactHistory : public ImpactObserver {
 public:
  void observe(const ImpactSample& sample) override;

  std::vector<Eigen::Index> contacts;
  std::vector<std::int64_t> step;
  std::vector<double> time;
  std::vector<double> principal_impulse;
  std::vector<std::vector<double>> velocity, energy, force, impulse, tangential_impulse;
};

}  // namespace mimpact::numerics
