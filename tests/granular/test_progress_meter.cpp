// The progress line of a long run (granular/progress_meter.hpp): nothing from a run shorter than
// its delay, then lines throttled by the clock, each kept in place over the last, and a newline
// at the end only where a line was shown.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

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

}  // namespace
}  // namespace mimpact::granular
