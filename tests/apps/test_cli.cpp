// The command line contract: `mimpact chain`, `packing`, `converge` and `lcp` outputs, errors and
// exit codes.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <cmath>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "../support/published.hpp"

namespace {

namespace fs = std::filesystem;
using mimpact::testing::published_steps;

struct CliRun {
  int exit_code;
  std::string out;
  std::string err;
};

// Runs the mimpact executable with `arguments` (shell words), capturing both streams.
CliRun mimpact(const std::string& arguments) {
  const fs::path err_file =
      fs::temp_directory_path() / ("mimpact_test_err_" + std::to_string(::getpid()));
  const std::string command =
      std::string(MIMPACT_CLI) + " " + arguments + " 2>" + err_file.string();
  CliRun run;
  FILE* pipe = ::popen(command.c_str(), "r");
  std::array<char, 4096> buffer;
  while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe))
    run.out.append(buffer.data(), n);
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
  EXPECT_NEAR(summary["kinetic_energy"]["after"].get<double>(), before,
              1e-6 * before);  // measured 2.7e-8
  // the time of the largest force moves down the chain
  EXPECT_LT(summary["contacts"][5]["time_of_max"].get<double>(),
            summary["contacts"][15]["time_of_max"].get<double>());
}

// The energy ledger: C3 (e = 0.6) loses most of its kinetic energy, all of it dissipated at the
// contacts, balanced to round-off; the per-contact shares add up to the total.
TEST(ChainCommand, SummaryHoldsTheEnergyLedger) {
  const CliRun run = mimpact("chain " + scene("c3.json") + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto energy = nlohmann::json::parse(run.out)["energy"];
  const double before = energy["kinetic_before"].get<double>() +
                        energy["potential_before"].get<double>() +
                        energy["work_of_forces"].get<double>();
  const double after = energy["kinetic_after"].get<double>() +
                       energy["dissipated_total"].get<double>() +
                       energy["potential_left"].get<double>();
  EXPECT_NEAR(after, before, 1e-12 * before);  // 3.1e-13 over its 136 725 steps
  double total = 0.0;
  for (const auto& d : energy["dissipated"]) {
    EXPECT_GE(d.get<double>(), 0.0);
    total += d.get<double>();
  }
  EXPECT_NEAR(total, energy["dissipated_total"].get<double>(), 1e-14);
  EXPECT_EQ(energy["dissipated"].size(), 20u);
  EXPECT_GT(energy["dissipated_total"].get<double>(), 0.9 * before);
}

TEST(ChainCommand, OutWritesSummaryIntoTheDirectory) {
  const fs::path dir = fs::temp_directory_path() / ("mimpact_out_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const CliRun run =
      mimpact("chain " + scene("c1.json") + " --delta-p 1e-4 --quiet --out " + dir.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.out, "");
  std::ifstream in(dir / "summary.json");
  const auto summary = nlohmann::json::parse(in);
  // the paper's step count at 1e-4, less one (it counts one more than the steps taken)
  const double taken = double(published_steps("C1", 1e-4) - 1);
  EXPECT_NEAR(summary["impulse_steps"].get<double>(), taken, 0.01 * taken);
  int entries = 0;
  for (const auto& entry : fs::directory_iterator(dir)) entries += entry.is_regular_file();
  EXPECT_EQ(entries, 1);  // no temporary file left behind
  fs::remove_all(dir);
}

// Every bad scene gives one line naming the problem, a non-zero exit and no output directory.
struct BadScene {
  const char* name;
  const char* from;  // a piece of the good scene, and what replaces it
  const char* to;
  const char* message;
};

void PrintTo(const BadScene& bad, std::ostream* out) { *out << bad.name; }

class BadSceneFile : public ::testing::TestWithParam<BadScene> {};

TEST_P(BadSceneFile, FailsInOneLineAndWritesNothing) {
  const BadScene bad = GetParam();
  std::string text = R"({"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
    "chain": {"segments": [{"count": 5, "radius": 0.01, "taper": 0.1}]},
    "strikers": [{"side": "left", "radius": 0.01, "velocity": 1}],
    "contact": {"restitution": 0.9}, "impact": {"delta_p": 1e-5}})";
  const std::size_t at = text.find(bad.from);
  ASSERT_NE(at, std::string::npos) << bad.from;
  text.replace(at, std::string(bad.from).size(), bad.to);
  const std::string id = std::to_string(::getpid()) + "_" + bad.name;
  const fs::path dir = fs::temp_directory_path() / ("mimpact_bad_" + id);
  const fs::path file = fs::temp_directory_path() / ("mimpact_bad_" + id + ".json");
  std::ofstream(file) << text;
  const CliRun run = mimpact("chain " + file.string() + " --out " + dir.string());
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find(bad.message), std::string::npos) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_FALSE(fs::exists(dir));
  for (const auto& entry : fs::directory_iterator(fs::temp_directory_path()))
    EXPECT_EQ(entry.path().filename().string().find("mimpact_bad_" + id + ".partial"),
              std::string::npos);
  fs::remove(file);
}

INSTANTIATE_TEST_SUITE_P(
    Issue4, BadSceneFile,
    ::testing::Values(
        BadScene{"malformed", "\"impact\"", "\"impact\" [", "malformed JSON"},
        BadScene{"missing", "\"radius\": 0.01, \"taper\"", "\"taper\"",
                 "missing field chain.segments[0].radius"},
        BadScene{"unknown", "\"restitution\"", "\"restitutio\": 1, \"restitution\"",
                 "unknown key \"restitutio\" in contact"},
        BadScene{"negative_radius", "\"radius\": 0.01, \"taper\"", "\"radius\": -0.01, \"taper\"",
                 "chain.segments[0].radius = -0.01 is invalid"},
        BadScene{"restitution", "\"restitution\": 0.9", "\"restitution\": 1.2",
                 "contact.restitution = 1.2 is invalid; allowed: 0 <= e <= 1"},
        BadScene{"taper", "\"taper\": 0.1", "\"taper\": 1",
                 "chain.segments[0].taper = 1 is invalid"},
        BadScene{"zero_beads", "\"count\": 5", "\"count\": 0",
                 "chain.segments[0].count = 0 is invalid"},
        BadScene{
            "away", "\"velocity\": 1", "\"velocity\": -1",
            "strikers[0].velocity = -1 is invalid; allowed: >= 1e-100 (m/s, towards the chain"},
        BadScene{"threshold", "\"delta_p\": 1e-5",
                 "\"delta_p\": 1e-5, \"fixed_thresholds\": {\"velocity\": 0, \"energy\": 1e-8}",
                 "impact.fixed_thresholds.velocity = 0 is invalid; allowed: > 0 (m/s)"}),
    [](const auto& param_info) { return std::string(param_info.param.name); });

// Fields valid one by one whose values the run cannot carry: each is refused by name before
// anything runs, instead of a NaN in the summary, a wrapped index or a run that never ends.
INSTANTIATE_TEST_SUITE_P(
    OutOfRange, BadSceneFile,
    ::testing::Values(
        BadScene{"exponent", "\"restitution\": 0.9",
                 "\"restitution\": 0.9, \"exponent\": 1e300, \"stiffness\": 1e9",
                 "contact.exponent = 1e+300 is invalid; allowed: 0 < eta <= 10"},
        BadScene{"index_wraps", "\"impact\"",
                 "\"record\": {\"contacts\": [4294967296]}, \"impact\"",
                 "record.contacts[0] = 4294967296 is invalid"},
        BadScene{"interval", "\"impact\"",
                 "\"method\": \"compliant\", \"record\": {\"contacts\": [1], \"interval\": "
                 "1e-300}, \"impact\"",
                 "record.interval = 1e-300 s: at least 3.04e+295 samples) needs about"},
        BadScene{"compliant_tolerance", "\"impact\"",
                 "\"method\": \"compliant\", \"compliant\": {\"tolerance\": 1e-300}, \"impact\"",
                 "compliant.tolerance = 1e-300 is invalid; allowed: 1e-14 <= tolerance <= 1e-1"},
        BadScene{"compliant_tolerance_loose", "\"impact\"",
                 "\"method\": \"compliant\", \"compliant\": {\"tolerance\": 1e-3}, \"impact\"",
                 "compliant.tolerance = 0.001 is invalid where the frozen geometry integrates (a "
                 "chain, or "
                 "compliant.geometry \"frozen\"); allowed: 1e-14 <= tolerance <= 1e-4"},
        BadScene{"precompression", "\"impact\"",
                 "\"wall\": {}, \"method\": \"compliant\", \"compliant\": {\"end_time\": 1e-3}, "
                 "\"precompression\": 1e300, \"impact\"",
                 "precompression = 1e+300 is invalid"},
        BadScene{"radius_underflow", "\"radius\": 0.01, \"taper\"", "\"radius\": 1e-120, \"taper\"",
                 "mass = 0 is invalid; allowed: a finite mass > 0 kg"},
        BadScene{"delta_p_coarse", "\"delta_p\": 1e-5", "\"delta_p\": 0.5",
                 "impact.delta_p = 0.5 is invalid"},
        BadScene{"delta_p_fine", "\"delta_p\": 1e-5", "\"delta_p\": 1e-300",
                 "impact.delta_p = 1e-300 is invalid"},
        BadScene{"threshold_above_the_approach", "\"delta_p\": 1e-5",
                 "\"delta_p\": 1e-5, \"fixed_thresholds\": {\"velocity\": 1e300, \"energy\": 1e-8}",
                 "took no impulse step"},
        BadScene{"top_level", "\"contact\"", "\"bogus\": 1, \"contact\"",
                 "unknown key \"bogus\" in the top level"}),
    [](const auto& param_info) { return std::string(param_info.param.name); });

TEST(ChainCommand, RecordWritesTimeSeriesThatAgreeWithTheSummary) {
  const fs::path dir = fs::temp_directory_path() / ("mimpact_series_" + std::to_string(::getpid()));
  const fs::path file = dir.string() + ".json";
  fs::remove_all(dir);
  std::ofstream(file) << R"({"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
    "chain": {"segments": [{"count": 6, "radius": 0.01}]}, "wall": {},
    "strikers": [{"radius": 0.01, "velocity": 1.0}], "impact": {"delta_p": 1e-5},
    "record": {"contacts": [2, 6], "bodies": [0, 6], "every": 1}})";
  const CliRun run = mimpact("chain " + file.string() + " --out " + dir.string() + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto summary = nlohmann::json::parse(std::ifstream(dir / "summary.json"));
  auto rows = [](const fs::path& path) {
    std::ifstream in(path);
    std::vector<std::vector<double>> table;
    std::string line;
    std::getline(in, line);
    table.push_back({});  // the header, kept apart
    while (std::getline(in, line)) {
      std::vector<double> row;
      std::stringstream fields(line);
      std::string field;
      while (std::getline(fields, field, ',')) row.push_back(std::stod(field));
      table.push_back(row);
    }
    return table;
  };
  std::ifstream forces_file(dir / "forces.csv");
  std::string header;
  std::getline(forces_file, header);
  EXPECT_EQ(header, "time,F_2,F_6");
  const auto forces = rows(dir / "forces.csv");
  const auto velocities = rows(dir / "velocities.csv");
  // every step recorded: the largest recorded force is the summary's peak
  for (int column : {1, 2}) {
    double peak = 0.0;
    for (std::size_t r = 1; r < forces.size(); ++r) peak = std::max(peak, forces[r][column]);
    const double expected = summary["contacts"][column == 1 ? 2 : 6]["max_force"];
    EXPECT_NEAR(peak, expected, 1e-12 * expected);
  }
  // the last sample is the end of the impact
  EXPECT_NEAR(velocities.back()[1], summary["post_impact_velocities"][0].get<double>(), 1e-12);
  EXPECT_NEAR(velocities.back()[2], summary["post_impact_velocities"][6].get<double>(), 1e-12);
  ASSERT_EQ(summary["pulses"].size(), 2u);
  EXPECT_EQ(summary["pulses"][1]["contact"], 6);
  fs::remove_all(dir);
  fs::remove(file);
}

TEST(ChainCommand, BadDeltaPIsNamed) {
  const CliRun run = mimpact("chain " + scene("c1.json") + " --delta-p -1");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find("--delta-p = -1 is invalid"), std::string::npos) << run.err;
}

// A delta_p at or past the striker's momentum resolves no approach (the striker would pass
// through), one too fine for max_steps never ends: both are refused before the run.
TEST(ChainCommand, DeltaPMustResolveTheImpactInMaxSteps) {
  const CliRun coarse = mimpact("chain " + scene("c1.json") + " --delta-p 0.5");
  EXPECT_EQ(coarse.exit_code, 1);
  EXPECT_NE(coarse.err.find(
                "--delta-p = 0.5 is invalid; allowed: 0 < delta_p < the striker's momentum m V"),
            std::string::npos)
      << coarse.err;
  const CliRun fine = mimpact("chain " + scene("c1.json") + " --delta-p 1e-300");
  EXPECT_EQ(fine.exit_code, 1);
  EXPECT_NE(fine.err.find("--delta-p = 1e-300 is invalid; allowed: >= P / max_steps"),
            std::string::npos)
      << fine.err;
  const CliRun from = mimpact("converge " + scene("c1.json") + " --from -1");
  EXPECT_EQ(from.exit_code, 1);
  EXPECT_NE(from.err.find("--from = -1 is invalid"), std::string::npos) << from.err;
}

// A run past --max-seconds stops with the phase and where it was, and writes nothing; C1 at a
// delta_p of 1e-10 N s (P / delta_p = 3.3e8 steps at least) cannot end in 0.3 s. A limit <= 0 is
// refused.
TEST(ChainCommand, MaxSecondsStopsALongRunAndWritesNothing) {
  const fs::path out = fs::temp_directory_path() / ("mimpact_test_out_" + std::to_string(getpid()));
  fs::remove_all(out);
  const CliRun run = mimpact("chain " + scene("c1.json") +
                             " --delta-p 1e-10 --max-seconds 0.3 --out " + out.string());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("the run took more than its 0.3 s (--max-seconds): stopped in the LZB "
                         "impact: t = "),
            std::string::npos)
      << run.err;
  EXPECT_FALSE(fs::exists(out));
  const CliRun zero = mimpact("chain " + scene("c1.json") + " --max-seconds 0");
  EXPECT_EQ(zero.exit_code, 1);
  EXPECT_NE(zero.err.find("--max-seconds = 0 is invalid; allowed: > 0 (s)"), std::string::npos)
      << zero.err;
}

// c1.json under the compliant method, cut at `end_time` (s) when given
// C1's scene text, and a variant of it written to a temporary file named by `tag`.
std::string c1_text() {
  std::ifstream in(scene("c1.json"));
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

fs::path write_scene(const std::string& tag, const std::string& text) {
  const fs::path file =
      fs::temp_directory_path() / ("mimpact_" + tag + "_" + std::to_string(::getpid()) + ".json");
  std::ofstream(file) << text;
  return file;
}

fs::path compliant_c1(const std::string& tag, const std::string& end_time) {
  std::string text = c1_text();
  const std::string compliant =
      "\"method\": \"compliant\", " +
      (end_time.empty() ? "" : "\"compliant\": {\"end_time\": " + end_time + "}, ");
  text.replace(text.find("\"impact\""), 0, compliant);
  return write_scene(tag, text);
}

// delta_p and the convergence study belong to the LZB method: asked of a compliant scene,
// they are errors, not silently dropped.
// --threads 1 runs the error estimate's companion after the run, 2 (the default) beside it: the
// same summary but for the seconds; any other count is refused before the run.
TEST(ChainCommand, ThreadsRunTheCompanionBesideOrAfterTheRun) {
  auto without_seconds = [](const std::string& out) {
    nlohmann::json summary = nlohmann::json::parse(out);
    summary.erase("wall_time");
    summary["error_estimate"].erase("companion_seconds");
    return summary;
  };
  const CliRun beside = mimpact("chain " + scene("c1.json") + " --quiet --accuracy 1e-5");
  const CliRun after =
      mimpact("chain " + scene("c1.json") + " --quiet --accuracy 1e-5 --threads 1");
  ASSERT_EQ(beside.exit_code, 0) << beside.err;
  ASSERT_EQ(after.exit_code, 0) << after.err;
  EXPECT_EQ(without_seconds(beside.out), without_seconds(after.out));
  const CliRun three = mimpact("chain " + scene("c1.json") + " --threads 3");
  EXPECT_EQ(three.exit_code, 1);
  EXPECT_NE(three.err.find("--threads = 3 is invalid; allowed: 1 (an error estimate's companion "
                           "after the run) or 2 (beside it; the default)"),
            std::string::npos)
      << three.err;
}

TEST(ChainCommand, LzbOptionsOnACompliantSceneAreErrors) {
  const fs::path file = compliant_c1("compliant", "");
  const CliRun delta_p = mimpact("chain " + file.string() + " --delta-p 1e-5");
  EXPECT_EQ(delta_p.exit_code, 1);
  EXPECT_NE(delta_p.err.find("--delta-p = 1e-05 is the step of the LZB method"), std::string::npos)
      << delta_p.err;
  const CliRun converge = mimpact("converge " + file.string());
  EXPECT_EQ(converge.exit_code, 1);
  EXPECT_NE(converge.err.find("has method \"compliant\""), std::string::npos) << converge.err;
  fs::remove(file);
}

// A compliant run that compliant.end_time stops before the contacts have all opened says
// so: the velocities are those of that time, with the wave still inside the chain.
TEST(ChainCommand, CompliantRunCutByEndTimeIsNotTerminated) {
  const fs::path cut = compliant_c1("cut", "1e-5"), whole = compliant_c1("whole", "");
  const auto cut_summary = nlohmann::json::parse(mimpact("chain " + cut.string() + " --quiet").out);
  const auto whole_summary =
      nlohmann::json::parse(mimpact("chain " + whole.string() + " --quiet").out);
  EXPECT_EQ(cut_summary["status"], "end_time");
  EXPECT_EQ(whole_summary["status"], "terminated");
  EXPECT_GT(cut_summary["post_impact_velocities"][0].get<double>(),
            0.1);  // the striker still moves
  fs::remove(cut);
  fs::remove(whole);
}

// "--out DIR/" names DIR; a rerun into DIR replaces the files an earlier run wrote, and
// removes those it does not write (no forces.csv of another run beside the new summary).
TEST(ChainCommand, OutDirectoryIsRewrittenWithoutStaleFiles) {
  const fs::path dir = fs::temp_directory_path() / ("mimpact_rerun_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  std::ifstream in(scene("c1.json"));
  std::string text((std::istreambuf_iterator<char>(in)), {});
  text.replace(text.find("\"impact\""), 0, "\"record\": {\"contacts\": [3], \"every\": 100}, ");
  const fs::path recorded = dir.string() + ".json";
  std::ofstream(recorded) << text;
  ASSERT_EQ(
      mimpact("chain " + recorded.string() + " --quiet --out " + dir.string() + "/").exit_code, 0);
  EXPECT_TRUE(fs::exists(dir / "forces.csv"));
  ASSERT_EQ(
      mimpact("chain " + scene("c1.json") + " --quiet --out " + dir.string() + "/.").exit_code, 0);
  EXPECT_TRUE(fs::exists(dir / "summary.json"));
  EXPECT_FALSE(fs::exists(dir / "forces.csv"));
  int entries = 0;
  for (const auto& entry : fs::directory_iterator(dir)) entries += entry.is_regular_file();
  EXPECT_EQ(entries, 1);
  fs::remove_all(dir);
  fs::remove(recorded);
}

TEST(ChainCommand, DirectoryAsSceneIsNamed) {
  const CliRun run = mimpact("chain " + fs::temp_directory_path().string());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("is a directory; allowed: a scene file"), std::string::npos) << run.err;
}

// The table of Nguyen & Brogliato's tables 2-4 as JSON; C2 from 1e-5 converges at the first halving
// below the paper's 1e-6 (its table 3: not converged at 1e-5, converged at 1e-6).
TEST(ConvergeCommand, PrintsTheRowsAndStopsWhereTheCriteriaHold) {
  const CliRun run = mimpact("converge " + scene("c2.json") + " --from 1e-5 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto study = nlohmann::json::parse(run.out);
  const auto& rows = study["rows"];
  ASSERT_EQ(rows.size(), 4u);  // 1e-5, 5e-6, 2.5e-6, 1.25e-6
  for (std::size_t k = 0; k < rows.size(); ++k) {
    EXPECT_DOUBLE_EQ(rows[k]["delta_p"].get<double>(), 1e-5 / double(1 << k));
    EXPECT_EQ(rows[k]["converged"].get<bool>(), k + 1 == rows.size());
    EXPECT_GT(rows[k]["impulse_steps"].get<double>(), 22000.0 * double(1 << k));
    EXPECT_GE(rows[k]["wall_time"].get<double>(), 0.0);
    EXPECT_GT(rows[k]["max_eta"].get<double>(), rows[k]["eta_plus"].get<double>());
  }
  EXPECT_LE(rows[3]["max_eta"].get<double>(), 0.01);
  EXPECT_EQ(study["extrapolated_velocities"].size(), 21u);
  EXPECT_TRUE(study["converged"].get<bool>());
}

TEST(ConvergeCommand, ExitsWith4WhenNotConvergedWithinTheHalvings) {
  const CliRun run = mimpact("converge " + scene("c1.json") + " --from 1e-4 --halvings 2");
  EXPECT_EQ(run.exit_code, 4) << run.err;
  EXPECT_NE(run.out.find("not converged within the halvings"), std::string::npos) << run.out;
}

// --tolerance runs the study and the chain at the delta_p it chose: C1 from 1e-4 at
// eps+ = 1e-3 only (eps = 1) needs eta+_h <= 1e-3, met at 2.5e-5 (eta+ 0.00096).
TEST(ChainCommand, ToleranceChoosesDeltaP) {
  const CliRun run =
      mimpact("chain " + scene("c1.json") + " --delta-p 1e-4 --tolerance 1e-3 1 --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto summary = nlohmann::json::parse(run.out);
  EXPECT_DOUBLE_EQ(summary["delta_p"].get<double>(), 2.5e-5);
  const auto& rows = summary["convergence"]["rows"];
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_LE(rows[2]["eta_plus"].get<double>(), 1e-3);
  EXPECT_GT(rows[1]["eta_plus"].get<double>(), 1e-3);
  EXPECT_NEAR(summary["impulse_steps"].get<double>(), rows[2]["impulse_steps"].get<double>(), 2.0);
}

// C1 with "impact": {} (neither delta_p nor an integrator) is a scene for the adaptive
// integrator: a tolerance tightened tenfold from the one asked until v+ changes by at most it.
fs::path open_c1(const std::string& tag, const std::string& impact) {
  std::string text = c1_text();
  const std::size_t at = text.find("{\"delta_p\"");
  text.replace(at, text.find('}', at) + 1 - at, impact);
  return write_scene(tag, text);
}

TEST(ChainCommand, ToleranceMeetsTheAccuracyWithTheAdaptiveIntegrator) {
  const fs::path file = open_c1("open", "{}");
  const CliRun run = mimpact("chain " + file.string() + " --tolerance 1e-6 --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto summary = nlohmann::json::parse(run.out);
  EXPECT_EQ(summary["integrator"], "adaptive");
  EXPECT_DOUBLE_EQ(summary["tolerance"].get<double>(), 1e-7);
  const auto& rows = summary["convergence"]["rows"];
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_DOUBLE_EQ(rows[0]["tolerance"].get<double>(), 1e-6);
  EXPECT_LE(rows[0]["eta_plus"].get<double>(), 1e-6);
  EXPECT_TRUE(summary["convergence"]["converged"].get<bool>());
  // the chain is the study's finest run
  const auto& finest = summary["convergence"]["finest_velocities"];
  const auto& velocities = summary["post_impact_velocities"];
  ASSERT_EQ(finest.size(), velocities.size());
  for (std::size_t i = 0; i < finest.size(); ++i)
    EXPECT_NEAR(velocities[i].get<double>(), finest[i].get<double>(), 1e-12) << i;
  fs::remove(file);
}

TEST(ConvergeCommand, AnAdaptiveSceneTightensItsTolerance) {
  const fs::path file = open_c1("adaptive", R"({"integrator": "adaptive", "tolerance": 1e-3})");
  const CliRun run = mimpact("converge " + file.string() + " --tolerance 1e-5 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto study = nlohmann::json::parse(run.out);
  const auto& rows = study["rows"];
  ASSERT_GE(rows.size(), 2u);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    EXPECT_DOUBLE_EQ(rows[k]["tolerance"].get<double>(), 1e-3 / std::pow(10.0, double(k)));
    EXPECT_EQ(rows[k]["converged"].get<bool>(), k + 1 == rows.size());
  }
  EXPECT_TRUE(study["converged"].get<bool>());
  const CliRun unmeetable = mimpact("converge " + file.string() + " --from 1e-14");
  EXPECT_EQ(unmeetable.exit_code, 1);
  EXPECT_NE(unmeetable.err.find("--from = 1e-14 is invalid"), std::string::npos) << unmeetable.err;
  fs::remove(file);
}

// A delta_p past 1 % of the striker's momentum gives errors of percents: the run says so.
TEST(ChainCommand, CoarseDeltaPIsWarnedAbout) {
  const CliRun run = mimpact("chain " + scene("c1.json") + " --delta-p 1e-3");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("warning: delta_p = 0.001 N s is 0.0307 of the striker's momentum"),
            std::string::npos)
      << run.err;
  EXPECT_EQ(mimpact("chain " + scene("c1.json") + " --delta-p 1e-5").err.find("warning"),
            std::string::npos);
}

TEST(ChainCommand, BadToleranceIsNamed) {
  const CliRun run = mimpact("chain " + scene("c1.json") + " --tolerance -0.1");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find("tolerance eps+ = -0.1 is invalid"), std::string::npos) << run.err;
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
  EXPECT_EQ(nlohmann::json::parse(run.out)["status"], "ray_termination");
}

TEST(LcpCommand, BadMaxPivotsAndOversizedProblemsAreNamed) {
  const CliRun pivots = mimpact("lcp " + lcp("lcp_exp_murty2.dat") + " --max-pivots -5");
  EXPECT_EQ(pivots.exit_code, 1);
  EXPECT_NE(pivots.err.find("max_pivots = -5 is invalid"), std::string::npos) << pivots.err;
  // a valid header asking for 9 999 999 unknowns: refused before any allocation
  const fs::path file =
      fs::temp_directory_path() / ("mimpact_big_" + std::to_string(::getpid()) + ".dat");
  std::ofstream(file) << "9999999 0 9999999 9999999 9999999 9999999\n";
  const CliRun big = mimpact("lcp " + file.string());
  EXPECT_EQ(big.exit_code, 1);
  EXPECT_NE(big.err.find("n (problem size) = 9999999 is invalid"), std::string::npos) << big.err;
  fs::remove(file);
}

// Every bad input of `mimpact nesterenko` fails in one line with status 1, never an abort.
TEST(NesterenkoCommand, BadInputsAreNamed) {
  const std::pair<const char*, const char*> cases[] = {
      {"inf", "FORCES: \"inf\" is invalid"},
      {"\"\"", "FORCES is empty"},
      {"10 --shape 1", "--shape = 1 is invalid"},
      {"100 --static-force inf", "--static-force = inf is invalid"},
      {"1e20 --static-force 1", "peak force / static force = 1e+20 is invalid"},
      {"10 --radius -1", "bead chain radius = -1 is invalid"}};
  for (const auto& [arguments, message] : cases) {
    const CliRun run = mimpact(std::string("nesterenko ") + arguments);
    EXPECT_EQ(run.exit_code, 1) << arguments;
    EXPECT_NE(run.err.find(message), std::string::npos) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  }
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

namespace {

// `mimpact packing`: the example packing writes its geometry, frames and a summary whose
// velocities are [vx, vy] per body and whose momentum and energy are kept.
TEST(PackingCommand, OutWritesSummaryGeometryAndFrames) {
  const fs::path out =
      fs::temp_directory_path() / ("mimpact_packing_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const CliRun run =
      mimpact("packing " + scene("packings/hexagonal_10x10.json") + " --out " + out.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("100 beads, 1 strikers, 262 contacts, adaptive LZB"), std::string::npos)
      << run.err;
  std::ifstream file(out / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(file);
  EXPECT_EQ(summary["post_impact_velocities"].size(), 101u);
  EXPECT_EQ(summary["post_impact_velocities"][0].size(), 2u);
  const auto& momentum = summary["momentum"];
  for (int k = 0; k < 2; ++k)
    EXPECT_NEAR(momentum["after"][k].get<double>(), momentum["before"][k].get<double>(), 1e-15);
  EXPECT_NEAR(summary["kinetic_energy"]["after"].get<double>() /
                  summary["kinetic_energy"]["before"].get<double>(),
              1.0, 2e-8);
  for (const char* name :
       {"bodies.csv", "contacts.csv", "frame_forces.csv", "frame_velocities.csv"})
    EXPECT_TRUE(fs::exists(out / name)) << name;
  // issue 24, item e: the LZB run tells that its frozen configuration is 5 % of V from the beads
  // as they move, far beyond its tolerance (tests/packings/test_configuration_check.cpp)
  const auto& check = summary["configuration_check"];
  EXPECT_FALSE(check["holds"].get<bool>());
  EXPECT_GT(check["worst_error"].get<double>(), 1e-2);
  EXPECT_NE(run.err.find("warning: the LZB impact keeps the configuration of the impact"),
            std::string::npos)
      << run.err;
  EXPECT_NE(run.err.find("the scene needs \"method\": \"compliant\""), std::string::npos);
  const CliRun quiet = mimpact("packing " + scene("packings/hexagonal_10x10.json") + " --quiet");
  EXPECT_NE(quiet.err.find("warning: the LZB impact"), std::string::npos) << quiet.err;
  fs::remove_all(out);
}

TEST(PackingCommand, BadSceneIsNamedAndWritesNothing) {
  const fs::path dir =
      fs::temp_directory_path() / ("mimpact_bad_packing_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "scene.json")
      << R"({"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
             "lattice": {"type": "square", "rows": 2, "columns": 2, "radius": 0.005},
             "strikers": [{"target": [3, 0], "radius": 0.005, "velocity": [1, 0]}]})";
  const CliRun run =
      mimpact("packing " + (dir / "scene.json").string() + " --out " + (dir / "out").string());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("strikers[0].target[0] = 3 is invalid; allowed: a row in [0, 2)"),
            std::string::npos)
      << run.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

// Issue 24, item f: the three-dimensional packings' bad input, one clear error each, before
// anything is written.
TEST(PackingCommand, ThreeDimensionalBadInputIsNamedAndWritesNothing) {
  const fs::path dir =
      fs::temp_directory_path() / ("mimpact_bad_packing_3d_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string steel = R"("material": {"density": 7780, "young": 203e9, "poisson": 0.3})";
  std::ofstream(dir / "beads.csv") << "x,y,z,radius\n0,0,0,0.005\n0.009,0,0,0.005\n";
  const std::pair<std::string, std::string> kCases[] = {
      {R"("lattice": {"type": "fcc", "layers": 2, "rows": 2, "columns": 2, "radius": 0.005},
          "strikers": [{"target": [0, 0, 0], "radius": 0.005, "velocity": [0, 1]}])",
       "strikers[0].velocity = [0, 1] has 2 components; allowed: 3 in a three-dimensional "
       "packing"},
      {R"("lattice": {"type": "simple-cubic", "layers": 2, "rows": 2, "columns": 2,
          "radius": 0.005}, "walls": [{"point": [0, 0, -0.005], "normal": [0, 0, 0]}],
          "strikers": [{"target": [0, 0, 0], "radius": 0.005, "velocity": [0, 0, 1]}])",
       "walls[0].normal = [0, 0, 0] is invalid; allowed: a normal of length > 0"},
      {R"("beads": {"file": "beads.csv"},
          "strikers": [{"target": [0], "radius": 0.005, "velocity": [1, 0, 0]}])",
       "beads.csv lines 2 and 3: bead 0 and bead 1 overlap by 0.001"}};
  for (const auto& [body, message] : kCases) {
    std::ofstream(dir / "scene.json") << "{" << steel << ", " << body << "}";
    const CliRun run =
        mimpact("packing " + (dir / "scene.json").string() + " --out " + (dir / "out").string());
    EXPECT_EQ(run.exit_code, 1) << message;
    EXPECT_NE(run.err.find(message), std::string::npos) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
  }
  fs::remove_all(dir);
}

}  // namespace
