#pragma once

#include <limits>
#include <string>

#include "mimpact/granular/contact_model.hpp"

// What a run may take of the machine. Every size and sampling of a scene is estimated before the
// run starts and refused by name when the estimate exceeds the limit; the recorders count what
// they keep as they go and stop the run where an estimate fell short. The message gives the
// estimate, the limit and the option that raises it, for a user who means it.
namespace mimpact::granular {

struct RunLimits {
  double memory_gb = 4.0;                      // GB (1e9 bytes) a run may hold
  std::string memory_option = "--max-memory";  // what raises it: "max_memory=" in Python
  // s of wall-clock time the run may take (infinite: no limit), kept by its ProgressMeter
  double seconds = std::numeric_limits<double>::infinity();
  std::string seconds_option = "--max-seconds";
  // threads a run may use: 2 runs an error estimate's companion beside the run it estimates
  // (the finer of the two on the caller's thread), 1 one after the other
  int threads = 2;
  std::string threads_option = "--threads";

  double memory_bytes() const { return memory_gb * 1e9; }
  // Throws InvalidInput naming the option unless memory_gb is finite and > 0, seconds > 0 and
  // threads is 1 or 2.
  void check() const;
};

// Bytes of a scene's model and its impact run, per body and per contact: measured on chains
// (1e6 beads, 1.84 GB with the adaptive integrator's buffers) and on hexagonal packings
// (300 x 300 beads and 2.7e5 contacts, 0.63 GB; 600 x 600, 2.1 GB) with a margin.
double model_bytes(double bodies, double contacts, int dimension);

// Throws InvalidInput "WHAT needs about X GB; allowed: at most Y GB (raise it with OPTION)".
void check_memory(double bytes, const std::string& what, const RunLimits& limits);

// A lower bound of the impact's duration (s): the compression of the fastest approaching contact
// alone, I(eta) delta_max / |u|, I(eta) = integral of (1 - x^(1+eta))^(-1/2) over [0, 1] (the
// power-law oscillator's quarter period; 1.47 for Hertz). Recorders sample at least this long.
double impact_duration_bound(const ContactModel& model);

// What a recorder keeps, counted as it goes: stops the run with InvalidInput naming the record's
// fields once the samples outgrow the limit.
class RecordingBudget {
 public:
  // bytes one sample and one frame keep (a frame: every contact and body); `fields` names what
  // sets their number, for the messages ("record.every and record.frames").
  RecordingBudget(double sample_bytes, double frame_bytes, const RunLimits& limits,
                  std::string fields);

  void name(std::string fields) { fields_ = std::move(fields); }
  // Refuses before the run a recording of at least `samples` samples and `frames` frames.
  void check_estimate(double samples, double frames) const;
  // One more sample (a frame when `frame`); throws once the limit is passed.
  void add(bool frame);

 private:
  double sample_bytes_, frame_bytes_;
  RunLimits limits_;
  std::string fields_;
  double kept_ = 0.0;  // bytes
};

}  // namespace mimpact::granular
