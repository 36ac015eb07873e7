// The command line contract: `mimpact chain` and `mimpact lcp` outputs, errors and exit codes.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

namespace {

namespace fs = std::filesystem;

struct CliRun {
  int exit_code;
  std::string out;
  std::string err;
};

// Runs the mimpact executable with `arguments` (shell words), capturing both streams.
CliRun mimpact(const std::string& arguments) {
  const fs::path err_file = fs::temp_directory_path() / ("mimpact_test_err_" + std::to_string(::getpid()));
  const std::string command = std::string(MIMPACT_CLI) + " " + arguments + " 2>" + err_file.string();
  CliRun run;
  FILE* pipe = ::popen(command.c_str(), "r");
  std::array<char, 4096> buffer;
  while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) run.out.append(buffer.data(), n);
  run.exit_code = WEXITSTATUS(::pclose(pipe));
  std::ifstream err(err_file);
  run.err.assign(std::istreambuf_iterator<char>(err), {});
  fs::remove(err_file);
  return run;
}

std::string scene(const std::string& name) {
  return std::string(MIMPACT_SOURCE_DIR) + "/examples/scenes/" + name;
}
std::string lcp(const std::string& name) { return std::string(MIMPACT_LCP_DATA_DIR) + "/" + name; }

TEST(ChainCommand, PrintsTheSummaryContract) {
  const CliRun run = mimpact("chain " + scene("c1.json") + " --delta-p 1e-5 --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err, "");
  const auto summary = nlohmann::json::parse(run.out);
  ASSERT_EQ(summary["post_impact_velocities"].size(), 21u);
  ASSERT_EQ(summary["contacts"].size(), 20u);
  for (std::size_t i = 0; i < 20; ++i) {
    const auto& contact = summary["contacts"][i];
    EXPECT_EQ(contact["index"], i);
    EXPECT_GT(contact["max_force"].get<double>(), 0.0);
    EXPECT_GT(contact["time_of_max"].get<double>(), 0.0);
    EXPECT_GT(contact["impulse"].get<double>(), 0.0);
  }
  EXPECT_NEAR(summary["impulse_steps"].get<double>(), 45912, 0.01 * 45912);
  EXPECT_GT(summary["impact_duration"].get<double>(), 0.0);
  EXPECT_GE(summary["wall_time"].get<double>(), 0.0);
  const double before = summary["kinetic_energy"]["before"];
  EXPECT_NEAR(before, 0.5 * 4.0 / 3.0 * M_PI * 1e-6 * 7780, 1e-12);  // striker at 1 m/s
  EXPECT_NEAR(summary["kinetic_energy"]["after"].get<double>(), before, 1e-3 * before);
  // the time of the largest force moves down the chain
  EXPECT_LT(summary["contacts"][5]["time_of_max"].get<double>(),
            summary["contacts"][15]["time_of_max"].get<double>());
}

TEST(ChainCommand, OutWritesSummaryIntoTheDirectory) {
  const fs::path dir = fs::temp_directory_path() / ("mimpact_out_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const CliRun run = mimpact("chain " + scene("c1.json") + " --delta-p 1e-4 --quiet --out " + dir.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.out, "");
  std::ifstream in(dir / "summary.json");
  const auto summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["impulse_steps"].get<int>() > 4000, true);
  int entries = 0;
  for (const auto& entry : fs::directory_iterator(dir)) entries += entry.is_regular_file();
  EXPECT_EQ(entries, 1);  // no temporary file left behind
  fs::remove_all(dir);
}

TEST(ChainCommand, BadSceneFailsInOneLineAndWritesNothing) {
  const fs::path dir = fs::temp_directory_path() / ("mimpact_bad_" + std::to_string(::getpid()));
  const fs::path bad = fs::temp_directory_path() / ("mimpact_bad_" + std::to_string(::getpid()) + ".json");
  std::ofstream(bad) << R"({"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
    "chain": {"segments": [{"count": 5, "radius": 0.01}]},
    "strikers": [{"side": "left", "radius": 0.01, "velocity": 1}],
    "contact": {"restitution": 1.2}, "impact": {"delta_p": 1e-5}})";
  const CliRun run = mimpact("chain " + bad.string() + " --out " + dir.string());
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find("contact.restitution = 1.2 is invalid"), std::string::npos) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_FALSE(fs::exists(dir));
  fs::remove(bad);
}

TEST(ChainCommand, BadDeltaPIsNamed) {
  const CliRun run = mimpact("chain " + scene("c1.json") + " --delta-p -1");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find("delta_p = -1 is invalid"), std::string::npos) << run.err;
}

TEST(LcpCommand, PrintsStatusPivotsErrorAndZ) {
  const CliRun run = mimpact("lcp " + lcp("lcp_exp_murty2.dat"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto result = nlohmann::json::parse(run.out);
  EXPECT_EQ(result["status"], "solved");
  EXPECT_EQ(result["n"], 6);
  EXPECT_EQ(result["pivots"], 64);
  EXPECT_LE(result["complementarity_error"].get<double>(), 1e-9);
  EXPECT_EQ(result["z"].size(), 6u);
}

TEST(LcpCommand, RayTerminationIsAStatusNotAFailure) {
  const CliRun run = mimpact("lcp " + lcp("lcp_CPS_3.dat"));
  EXPECT_EQ(run.exit_code, 0) << run.err;
  const std::string status = nlohmann::json::parse(run.out)["status"];
  EXPECT_TRUE(status == "ray_termination" || status == "solved") << status;
}

TEST(LcpCommand, UnreadableFileGivesStatusInvalid) {
  const CliRun run = mimpact("lcp " + lcp("lcp_deudeu_block.dat"));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_EQ(nlohmann::json::parse(run.out)["status"], "invalid");
  EXPECT_NE(run.err.find("storage = 1"), std::string::npos) << run.err;
}

TEST(Cli, UnknownCommandIsAnError) {
  const CliRun run = mimpact("fly");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("unknown command \"fly\""), std::string::npos) << run.err;
}

}  // namespace
