#include "mimpact/granular/impact_recorder.hpp"

#include <algorithm>
#include <cstdio>
#include <numeric>

namespace mimpact::granular {

namespace {

// "time,<label 0>,<label 1>,..." then one row per sample, 17 significant digits
std::string csv(const std::vector<double>& time, const std::vector<std::vector<double>>& rows,
                const std::vector<std::string>& labels) {
  std::string text = "time";
  for (const std::string& label : labels) text += "," + label;
  text += "\n";
  char number[32];
  for (std::size_t r = 0; r < time.size(); ++r) {
    std::snprintf(number, sizeof number, "%.17g", time[r]);
    text += number;
    for (double value : rows[r]) {
      std::snprintf(number, sizeof number, ",%.17g", value);
      text += number;
    }
    text += "\n";
  }
  return text;
}

}  // namespace

std::string TimeSeries::forces_csv() const {
  std::vector<std::string> labels;
  for (int contact : contacts) labels.push_back("F_" + std::to_string(contact));
  return csv(time, force, labels);
}

std::string vector_csv(const std::vector<double>& time,
                       const std::vector<std::vector<double>>& rows, const std::vector<int>& bodies,
                       int dimension, const std::string& symbol) {
  static const char* const kAxes[] = {"x", "y", "z"};
  std::vector<std::string> labels;
  for (int body : bodies)
    for (int k = 0; k < dimension; ++k)
      labels.push_back((dimension == 1 ? (symbol.empty() ? "x" : symbol) : symbol + kAxes[k]) +
                       "_" + std::to_string(body));
  return csv(time, rows, labels);
}

std::string TimeSeries::velocities_csv() const {
  return vector_csv(time, velocity, bodies, dimension, "v");
}

namespace {

// What a sample keeps (bytes): its own record, the impulses it samples, and the series and CSV
// rows it becomes (a number is 8 bytes held, 25 written)
constexpr double kSampleOverhead = 150.0;
constexpr double kBytesPerColumn = 60.0;

}  // namespace

std::string sampling_fields(const RecordSpec& record, bool by_time, int frame_every) {
  return (by_time ? "record.interval = " + to_text(record.interval) + " s"
                  : "record.every = " + std::to_string(record.every)) +
         (frame_every > 0 ? ", record.frames = " + std::to_string(frame_every) : "");
}

namespace {}  // namespace

ImpactRecorder::ImpactRecorder(const ContactModel& model, RecordSpec record, int frame_every,
                               const RunLimits& limits)
    : model_(model),
      record_(std::move(record)),
      frame_every_(frame_every),
      budget_(0.0, 0.0, limits, "") {
  for (int body : record_.bodies)
    for (int k = 0; k < model_.dimension; ++k)
      recorded_coordinates_.push_back(Eigen::Index(body) * model_.dimension + k);
  std::vector<Eigen::Index> needed(record_.contacts.begin(), record_.contacts.end());
  if (frame_every_ > 0) {
    needed.resize(std::size_t(model_.contact_count()));
    std::iota(needed.begin(), needed.end(), Eigen::Index(0));
  } else {
    // the contacts touching a body are the nonzeros of its coordinates' rows of W
    for (Eigen::Index c = 0; c < model_.W.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(model_.W, c); it; ++it)
        if (std::find(recorded_coordinates_.begin(), recorded_coordinates_.end(), it.row()) !=
            recorded_coordinates_.end())
          needed.push_back(c);
  }
  std::sort(needed.begin(), needed.end());
  needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
  sampled_ = needed;
  if (model_.rotation)
    for (Eigen::Index c : sampled_)
      for (Eigen::Index r = model_.rotation->tangential.first_row[std::size_t(c)];
           r < model_.rotation->tangential.first_row[std::size_t(c) + 1]; ++r)
        sampled_rows_.push_back(r);
  const double columns = double(record_.contacts.size() + recorded_coordinates_.size() + 1);
  const double all = double(model_.contact_count() + model_.mass.size());
  budget_ = RecordingBudget(kSampleOverhead + 8.0 * double(sampled_.size() + sampled_rows_.size()) +
                                kBytesPerColumn * columns,
                            kBytesPerColumn * all, limits, "");
}

void ImpactRecorder::configure(plugins::LzbImpactOptions& options) {
  options.impulse_steps.sample_every = record_.every;
  options.impulse_steps.sampled_contacts = sampled_;
  options.adaptive.sample_interval = record_.interval;
  const bool adaptive = options.chosen_integrator() == plugins::LzbIntegrator::adaptive;
  double samples;
  if (adaptive) {
    samples = impact_duration_bound(model_) / record_.interval;
  } else {
    const double delta_p = options.delta_p
                               ? *options.delta_p
                               : options.relative_delta_p.value_or(1.0) * natural_impulse(model_);
    samples = largest_momentum(model_) / delta_p / double(record_.every);
  }
  budget_.name(sampling_fields(record_, adaptive, frame_every_));
  budget_.check_estimate(samples, frame_every_ > 0 ? samples / double(frame_every_) : 0.0);
}

void ImpactRecorder::observe(const numerics::ImpactSample& sample) {
  if (sample.step == 0) ++impacts_seen_;
  // the sample names its contacts, in increasing order; one outside this impact carries nothing
  auto value_of = [&](std::span<const double> values, Eigen::Index contact) {
    const auto at = std::lower_bound(sample.contacts.begin(), sample.contacts.end(), contact);
    return at != sample.contacts.end() && *at == contact
               ? values[std::size_t(at - sample.contacts.begin())]
               : 0.0;
  };
  Sample kept{impacts_seen_ - 1, sample.time, {}, {}};
  kept.frame = frame_every_ > 0 && samples_.size() % std::size_t(frame_every_) == 0;
  budget_.add(kept.frame);
  for (Eigen::Index contact : sampled_) kept.impulse.push_back(value_of(sample.impulse, contact));
  if (kept.frame)
    for (Eigen::Index contact : sampled_) kept.force.push_back(value_of(sample.force, contact));
  else
    for (int contact : record_.contacts) kept.force.push_back(value_of(sample.force, contact));
  if (!sampled_rows_.empty()) keep_tangential(sample, kept);
  samples_.push_back(std::move(kept));
}

void ImpactRecorder::keep_tangential(const numerics::ImpactSample& sample, Sample& kept) const {
  const numerics::TangentialRows& rows = model_.rotation->tangential;
  kept.tangential.assign(sampled_rows_.size(), 0.0);
  if (sample.tangential_impulse.empty()) return;  // a frictionless impact of this run
  // the sample's rows follow its contacts; sampled_rows_ follows sampled_, both increasing
  std::size_t from = 0, kept_row = 0, k = 0;
  for (Eigen::Index contact : sample.contacts) {
    const int count = rows.rows_of(contact);
    while (k < sampled_.size() && sampled_[k] < contact)
      kept_row += std::size_t(rows.rows_of(sampled_[k++]));
    if (k < sampled_.size() && sampled_[k] == contact)
      for (int r = 0; r < count; ++r)
        kept.tangential[kept_row + std::size_t(r)] =
            sample.tangential_impulse[from + std::size_t(r)];
    from += std::size_t(count);
  }
}

Eigen::VectorXd ImpactRecorder::tangential_impulse(const Sample& sample) const {
  Eigen::VectorXd impulse = Eigen::VectorXd::Zero(model_.rotation->tangential.rows());
  for (std::size_t i = 0; i < sampled_rows_.size(); ++i)
    impulse(sampled_rows_[i]) = sample.tangential[i];
  return impulse;
}

std::vector<double> ImpactRecorder::velocities(const ImpactOutcome& impact, const Sample& sample,
                                               const std::vector<Eigen::Index>& coordinates) const {
  std::vector<double> velocity;
  for (Eigen::Index coordinate : coordinates) {
    double v = impact.velocities_before[sample.impact](coordinate);
    for (std::size_t k = 0; k < sampled_.size(); ++k)
      v += model_.W.coeff(coordinate, sampled_[k]) * sample.impulse[k] / model_.mass(coordinate);
    for (std::size_t i = 0; i < sampled_rows_.size(); ++i)  // with friction: + M^-1 W_t P_t
      v += model_.rotation->W_t.coeff(coordinate, sampled_rows_[i]) * sample.tangential[i] /
           model_.mass(coordinate);
    velocity.push_back(v);
  }
  return velocity;
}

TimeSeries ImpactRecorder::series(const ImpactOutcome& impact) const {
  TimeSeries series;
  series.contacts = record_.contacts;
  series.bodies = record_.bodies;
  series.dimension = model_.dimension;
  for (const Sample& sample : samples_) {
    series.time.push_back(impact.impact_times[sample.impact] - impact.impact_time + sample.time);
    if (sample.frame) {  // a frame holds every contact's force: keep the recorded ones
      std::vector<double> force;
      for (int contact : record_.contacts) force.push_back(sample.force[std::size_t(contact)]);
      series.force.push_back(std::move(force));
    } else {
      series.force.push_back(sample.force);
    }
    series.velocity.push_back(velocities(impact, sample, recorded_coordinates_));
  }
  return series;
}

Frames ImpactRecorder::frames(const ImpactOutcome& impact) const {
  Frames frames;
  std::vector<Eigen::Index> all(std::size_t(model_.mass.size()));
  std::iota(all.begin(), all.end(), Eigen::Index(0));
  for (const Sample& sample : samples_) {
    if (!sample.frame) continue;
    frames.time.push_back(impact.impact_times[sample.impact] - impact.impact_time + sample.time);
    frames.force.push_back(sample.force);
    // v = v- + M^-1 W P, all coordinates at once
    Eigen::Map<const Eigen::VectorXd> impulse(sample.impulse.data(),
                                              Eigen::Index(sample.impulse.size()));
    Eigen::VectorXd v =
        impact.velocities_before[sample.impact] + (model_.W * impulse).cwiseQuotient(model_.mass);
    if (model_.rotation) {  // + M^-1 W_t P_t, and omega = omega- + I^-1 R_t P_t
      const Rotation& rotation = *model_.rotation;
      const Eigen::VectorXd tangential = tangential_impulse(sample);
      v += (rotation.W_t * tangential).cwiseQuotient(model_.mass);
      const Eigen::VectorXd omega =
          turned(rotation, impact.angular_velocities_before[sample.impact], tangential);
      frames.angular_velocity.emplace_back(omega.data(), omega.data() + omega.size());
    }
    frames.velocity.emplace_back(v.data(), v.data() + v.size());
  }
  return frames;
}

}  // namespace mimpact::granular
