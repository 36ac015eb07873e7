#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <stop_token>
#include <string>

// Where a long run is: one line updated in place, as LAMMPS's thermo output or tqdm show it.
namespace mimpact::granular {

// What a run's loop knows of itself when it reports.
struct ProgressState {
  double time = 0.0;  // s, simulated
  std::int64_t steps = 0;
  std::int64_t contacts = -1;  // contacts loaded or in motion; < 0: not known
  double impulse = std::numeric_limits<double>::quiet_NaN();  // N s, LZB's principal impulse
};

// Thrown by a meter beside another (ProgressMeter::beside) at its first report after its stop
// was asked: the run it measures is no longer wanted. It never leaves run_scene.
class RunStopped : public std::runtime_error {
 public:
  RunStopped() : std::runtime_error("the run beside this one stopped it") {}
};

// Throttled by the clock: a loop reports as often as it likes, and its sink gets the first line
// after `delay` s and then one every `interval` s (one clock read when none is due), so that a
// short run prints nothing. Each phase of a run (the LZB impact, its configuration check, the
// compliant contacts) names itself and the simulated time it is to reach, when it knows it.
// A meter also keeps the run's wall-clock limit (limit_time): the first report past it throws
// TimeLimitReached, naming the phase, where it was and the option that raises the limit. A meter
// with no sink shows nothing and only keeps the limit.
class ProgressMeter {
 public:
  // Writes what it is given: a line kept in place ("\r", the line, spaces over the rest of the
  // last one), and a newline when the run is done, if any line was shown.
  using Sink = std::function<void(const std::string& text)>;
  explicit ProgressMeter(Sink sink, double delay = 2.0, double interval = 0.5);
  ProgressMeter(const ProgressMeter&) = delete;
  ProgressMeter& operator=(const ProgressMeter&) = delete;
  ~ProgressMeter();

  // Stops the run `seconds` (wall-clock) after the meter was made; `option` raises the limit.
  void limit_time(double seconds, std::string option);
  // From now on, a RunStopped at the first report after `stop` is asked (the reports are looked
  // at every kStopPoll s for it); an empty token undoes it.
  void stop_when(std::stop_token stop);
  static constexpr double kStopPoll = 0.02;  // s
  // A meter for a run on another thread beside the one `meter` measures (none: no limit): no
  // line, the same deadline, and stopped when `stop` is asked.
  static std::unique_ptr<ProgressMeter> beside(const ProgressMeter* meter, std::stop_token stop);
  void begin(std::string phase, double end_time = std::numeric_limits<double>::quiet_NaN());
  void report(const ProgressState& state) {
    if (std::chrono::steady_clock::now() >= next_) due(state);
  }
  // Closes the line, if one was shown.
  void finish();

  // The line for `state` after `elapsed` s of the current phase.
  std::string line(const ProgressState& state, double elapsed) const;

 private:
  using Clock = std::chrono::steady_clock;
  // Throws past the deadline; else shows the line if one is due, and sets the next report due.
  void due(const ProgressState& state);
  // The next report looked at: the next line, the deadline or the next look at the stop.
  void schedule(Clock::time_point now);

  Sink sink_;
  Clock::duration interval_;
  Clock::time_point start_;
  Clock::time_point next_line_ = Clock::time_point::max(), deadline_ = Clock::time_point::max();
  Clock::time_point next_;  // the earlier of the two
  double limit_seconds_ = std::numeric_limits<double>::infinity();
  std::string limit_option_;
  std::string phase_ = "run";
  double end_time_ = std::numeric_limits<double>::quiet_NaN();
  std::size_t width_ = 0;  // of the line shown, 0 if none
  std::stop_token stop_;   // stop_when(): asked to stop
};

// A sink that writes to `stream` (a terminal) at once.
ProgressMeter::Sink stream_sink(std::FILE* stream);

// The meter of a run: showing on `sink` (nothing when it is empty) and stopping the run after
// `seconds` (none when infinite), raised by `option`; null when it would do neither.
std::unique_ptr<ProgressMeter> run_meter(ProgressMeter::Sink sink, double seconds,
                                         const std::string& option);

}  // namespace mimpact::granular
