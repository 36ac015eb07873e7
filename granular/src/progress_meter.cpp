#include "mimpact/granular/progress_meter.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "mimpact/common/error.hpp"

namespace mimpact::granular {

namespace {

using Clock = std::chrono::steady_clock;
Clock::duration seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

// 3.2 M, 45 k, 812
std::string count_text(std::int64_t n) {
  char text[32];
  if (n >= 1'000'000)
    std::snprintf(text, sizeof text, "%.1f M", double(n) / 1e6);
  else if (n >= 10'000)
    std::snprintf(text, sizeof text, "%.0f k", double(n) / 1e3);
  else
    std::snprintf(text, sizeof text, "%lld", static_cast<long long>(n));
  return text;
}

}  // namespace

ProgressMeter::ProgressMeter(Sink sink, double delay, double interval)
    : sink_(std::move(sink)), interval_(seconds(interval)), start_(Clock::now()) {
  if (sink_) next_line_ = start_ + seconds(delay);
  schedule(start_);
}

void ProgressMeter::limit_time(double limit, std::string option) {
  limit_seconds_ = limit;
  limit_option_ = std::move(option);
  // beyond a year, no limit (and no overflow of the clock's ticks)
  if (std::isfinite(limit) && limit < 3.2e7) deadline_ = start_ + seconds(limit);
  schedule(Clock::now());
}

std::unique_ptr<ProgressMeter> ProgressMeter::beside(const ProgressMeter* meter,
                                                     std::stop_token stop) {
  auto other = std::make_unique<ProgressMeter>(nullptr);
  if (meter) {
    other->start_ = meter->start_;
    other->deadline_ = meter->deadline_;
    other->limit_seconds_ = meter->limit_seconds_;
    other->limit_option_ = meter->limit_option_;
  }
  other->stop_when(std::move(stop));
  return other;
}

void ProgressMeter::stop_when(std::stop_token stop) {
  stop_ = std::move(stop);
  schedule(Clock::now());
}

void ProgressMeter::schedule(Clock::time_point now) {
  next_ = std::min(next_line_, deadline_);
  if (stop_.stop_possible()) next_ = std::min(next_, now + seconds(kStopPoll));
}

ProgressMeter::~ProgressMeter() { finish(); }

void ProgressMeter::begin(std::string phase, double end_time) {
  phase_ = std::move(phase);
  end_time_ = end_time;
}

void ProgressMeter::due(const ProgressState& state) {
  const Clock::time_point now = Clock::now();
  if (stop_.stop_requested()) throw RunStopped();
  if (now >= deadline_) {
    finish();
    throw TimeLimitReached("the run took more than its " + rounded_text(limit_seconds_) + " s (" +
                           limit_option_ + "): stopped in the " +
                           line(state, std::chrono::duration<double>(now - start_).count()) +
                           "; raise " + limit_option_ + ", or ask for a coarser step or accuracy");
  }
  if (now < next_line_) {
    schedule(now);
    return;
  }
  next_line_ = now + interval_;
  schedule(now);
  const std::string text = line(state, std::chrono::duration<double>(now - start_).count());
  const std::size_t pad = width_ > text.size() ? width_ - text.size() : 0;
  width_ = text.size();
  sink_("\r" + text + std::string(pad, ' '));
}

void ProgressMeter::finish() {
  if (width_ == 0) return;
  width_ = 0;
  sink_("\n");
}

std::string ProgressMeter::line(const ProgressState& state, double elapsed) const {
  char text[96];
  std::string out = phase_ + ": t = ";
  std::snprintf(text, sizeof text, "%.4g s", state.time);
  out += text;
  if (std::isfinite(end_time_) && end_time_ > 0.0) {
    std::snprintf(text, sizeof text, " of %.4g s (%.0f %%)", end_time_,
                  100.0 * state.time / end_time_);
    out += text;
  }
  if (std::isfinite(state.impulse)) {
    std::snprintf(text, sizeof text, ", impulse %.4g N s", state.impulse);
    out += text;
  }
  out += ", " + count_text(state.steps) + " steps";
  if (state.contacts >= 0) out += ", " + count_text(state.contacts) + " contacts in motion";
  std::snprintf(text, sizeof text, ", %.0f s", elapsed);
  return out + text;
}

ProgressMeter::Sink stream_sink(std::FILE* stream) {
  return [stream](const std::string& text) {
    std::fputs(text.c_str(), stream);
    std::fflush(stream);
  };
}

std::unique_ptr<ProgressMeter> run_meter(ProgressMeter::Sink sink, double seconds,
                                         const std::string& option) {
  if (!sink && !std::isfinite(seconds)) return nullptr;
  auto meter = std::make_unique<ProgressMeter>(std::move(sink));
  meter->limit_time(seconds, option);
  return meter;
}

}  // namespace mimpact::granular
