// The progress line of a long run (granular/progress_meter.hpp): nothing from a run shorter than
// its delay, then lines throttled by the clock, each kept in place over the last, and a newline
// at the end only where a line was shown; the run's wall-clock limit, kept with or without a line.
#include <gtest/gtest.h>

#include <chrono>
#include <limits>
#include <stop_token>
#include <string>
#include <thread>
#include <vector>

#include "mimpact/common/error.hpp"
#include "mimpact/granular/progress_meter.hpp"

namespace mimpact::granular {
namespace {

TEST(ProgressMeter, AShortRunShowsNothing) {
  std::vector<std::string> written;
  {
    ProgressMeter meter([&](const std::string& text) { written.push_back(text); }, 60.0);
    for (int k = 0; k < 1'000'000; ++k) meter.report({.time = 1e-9 * k, .steps = k});
  }
  EXPECT_TRUE(written.empty());
}

TEST(ProgressMeter, ReportsAreThrottledAndKeptInPlace) {
  std::vector<std::string> written;
  ProgressMeter meter([&](const std::string& text) { written.push_back(text); }, 0.0, 0.05);
  meter.begin("compliant contacts", 1e-3);
  const auto start = std::chrono::steady_clock::now();
  std::int64_t reports = 0;
  while (std::chrono::steady_clock::now() - start < std::chrono::milliseconds(220)) {
    meter.report({.time = 5e-4, .steps = 1'234'567, .contacts = 42});
    ++reports;
  }
  meter.finish();
  meter.finish();  // once
  // the first at once, then one each 50 ms: 5 lines in 220 ms (a slow machine shows fewer)
  ASSERT_GE(written.size(), 3u);
  EXPECT_LE(written.size(), 7u);
  EXPECT_GT(reports, std::int64_t(10 * written.size()));
  EXPECT_EQ(written.back(), "\n");
  const std::string& line = written.front();
  EXPECT_EQ(line.front(), '\r');
  EXPECT_NE(line.find("compliant contacts: t = 0.0005 s of 0.001 s (50 %)"), std::string::npos);
  EXPECT_NE(line.find("1.2 M steps, 42 contacts in motion"), std::string::npos);
}

TEST(ProgressMeter, AShorterLineCoversTheLongerOneBeforeIt) {
  std::vector<std::string> written;
  ProgressMeter meter([&](const std::string& text) { written.push_back(text); }, 0.0, 0.0);
  meter.begin("LZB impact");
  meter.report({.time = 1e-4, .steps = 123'456, .impulse = 0.25});
  meter.report({.time = 2e-4, .steps = 7});
  ASSERT_EQ(written.size(), 2u);
  EXPECT_NE(written[0].find("LZB impact: t = 0.0001 s, impulse 0.25 N s, 123 k steps"),
            std::string::npos);
  EXPECT_EQ(written[1].size(), written[0].size());
  EXPECT_EQ(written[1].back(), ' ');
}

// Past its limit, the first report stops the run, never before it; the message names the option,
// the phase and where it was.
TEST(ProgressMeter, StopsTheRunAtItsTimeLimit) {
  const std::unique_ptr<ProgressMeter> meter = run_meter(nullptr, 0.05, "--max-seconds");
  ASSERT_NE(meter, nullptr);
  meter->begin("LZB impact");
  const auto start = std::chrono::steady_clock::now();
  std::int64_t k = 0;
  std::string message;
  try {
    for (; k < std::int64_t(1) << 40; ++k) meter->report({.time = 1e-9 * double(k), .steps = k});
  } catch (const TimeLimitReached& stopped) {
    message = stopped.what();
  }
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(elapsed, 0.05);
  EXPECT_GT(k, 1000);
  EXPECT_NE(message.find("the run took more than its 0.05 s (--max-seconds): stopped in the LZB "
                         "impact: t = "),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("raise --max-seconds"), std::string::npos) << message;
}

TEST(ProgressMeter, ARunWithNeitherLineNorLimitHasNoMeter) {
  EXPECT_EQ(run_meter(nullptr, std::numeric_limits<double>::infinity(), "--max-seconds"), nullptr);
  std::vector<std::string> written;
  const std::unique_ptr<ProgressMeter> shown =
      run_meter([&](const std::string& text) { written.push_back(text); },
                std::numeric_limits<double>::infinity(), "--max-seconds");
  ASSERT_NE(shown, nullptr);
  shown->report({.time = 0.0, .steps = 1});  // a second before the first line: nothing
  EXPECT_TRUE(written.empty());
}

// A meter beside another (an error estimate's companion on a second thread) shows no line, keeps
// the other's deadline, and stops its run at a report after its stop is asked, never before.
TEST(ProgressMeter, AMeterBesideAnotherKeepsItsDeadlineAndStopsWhenAsked) {
  std::vector<std::string> written;
  ProgressMeter shown([&](const std::string& text) { written.push_back(text); }, 0.0, 0.0);
  shown.limit_time(0.05, "--max-seconds");
  const std::unique_ptr<ProgressMeter> beside = ProgressMeter::beside(&shown, {});
  beside->begin("compliant contacts");
  std::string message;
  const auto start = std::chrono::steady_clock::now();
  try {
    for (std::int64_t k = 0; k < std::int64_t(1) << 40; ++k) beside->report({.steps = k});
  } catch (const TimeLimitReached& stopped) {
    message = stopped.what();
  }
  EXPECT_GE(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 0.05);
  EXPECT_NE(message.find("more than its 0.05 s (--max-seconds): stopped in the compliant contacts"),
            std::string::npos)
      << message;
  EXPECT_TRUE(written.empty());

  std::stop_source stop;
  const std::unique_ptr<ProgressMeter> unlimited = ProgressMeter::beside(nullptr, stop.get_token());
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(60);
  std::int64_t reports = 0;
  while (std::chrono::steady_clock::now() < until) unlimited->report({.steps = ++reports});
  stop.request_stop();
  std::int64_t after = 0;
  EXPECT_THROW(
      while (after < std::int64_t(1) << 40) unlimited->report({.steps = reports + ++after}),
      RunStopped);
  EXPECT_GT(reports, 1000);  // three polls and more went by without a stop
  EXPECT_GE(after, 1);
}

}  // namespace
}  // namespace mimpact::granular
