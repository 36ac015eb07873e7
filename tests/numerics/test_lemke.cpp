// Lemke's method against the Siconos LCP suite, brute-force enumeration and Murty's
// exponential family.
#include "mimpact/numerics/lemke.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <random>

#include "mimpact/numerics/lcp_file.hpp"
#include "mimpact/numerics/lcp_problem.hpp"

namespace mimpact::numerics {
namespace {

namespace fs = std::filesystem;

fs::path lcp_data(const std::string& name) { return fs::path(MIMPACT_LCP_DATA_DIR) / name; }

// Every dense file Siconos 4.5's Lemke solves is solved and verified.
class LcpSuiteFile : public ::testing::TestWithParam<std::string> {};

TEST_P(LcpSuiteFile, SolvedWithSmallComplementarityError) {
  const LcpProblem problem = read_lcp_file(lcp_data(GetParam()));
  const LemkeResult result = solve_lemke(problem.M, problem.q);
  EXPECT_EQ(result.status, LemkeStatus::solved) << result.message;
  EXPECT_LE(result.complementarity_error, 1e-9);
  // the error is measured again here from z alone, not taken from the solver
  EXPECT_LE(complementarity_error(problem.M, problem.q, result.z), 1e-9);
  EXPECT_GE(result.z.minCoeff(), -1e-12 * std::max(1.0, result.z.cwiseAbs().maxCoeff()));
}

INSTANTIATE_TEST_SUITE_P(SiconosSuite, LcpSuiteFile,
                         ::testing::Values("lcp_CPS_1.dat", "lcp_CPS_2.dat", "lcp_CPS_4.dat",
                                           "lcp_CPS_4bis.dat", "lcp_CPS_5.dat",
                                           "lcp_Pang_isolated_sol.dat", "lcp_deudeu.dat",
                                           "lcp_enum_fails.dat", "lcp_exp_murty.dat",
                                           "lcp_exp_murty2.dat", "lcp_inf_sol_perturbed.dat",
                                           "lcp_mmc.dat", "lcp_ortiz.dat", "lcp_tobenna.dat",
                                           "lcp_trivial.dat"),
                         [](const auto& param_info) {
                           std::string name = fs::path(param_info.param).stem().string();
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

TEST(LcpSuite, EveryDenseFileIsCovered) {
  // the files not in the list above are the ones the suite's README excludes
  int dense = 0;
  for (const auto& entry : fs::directory_iterator(MIMPACT_LCP_DATA_DIR)) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() == ".dat" && name.find("_block") == std::string::npos) ++dense;
  }
  EXPECT_EQ(dense, 15 + 2);  // 15 solved above, lcp_CPS_3 and lcp_Pang_isolated_sol_perturbed
}

TEST(LcpSuite, BimatrixGameCps3EndsInRayTermination) {
  const LcpProblem problem = read_lcp_file(lcp_data("lcp_CPS_3.dat"));
  const LemkeResult result = solve_lemke(problem.M, problem.q);
  EXPECT_EQ(result.status, LemkeStatus::ray_termination);
  EXPECT_FALSE(result.message.empty());
}

TEST(LcpSuite, MmcTakesFewPivotsDespiteLargeEntries) {
  // Siconos needs 22 pivots; a lexicographic Lemke on the same data may differ a little
  const LcpProblem problem = read_lcp_file(lcp_data("lcp_mmc.dat"));
  const LemkeResult result = solve_lemke(problem.M, problem.q);
  ASSERT_TRUE(result.solved());
  EXPECT_LE(result.pivots, 2 * 26 + 2);
}

TEST(Lemke, NonNegativeQGivesZeroWithoutPivoting) {
  Eigen::MatrixXd M(2, 2);
  M << 1, -3, 2, 0.5;
  const Eigen::VectorXd q = Eigen::Vector2d(0.0, 4.0);
  const LemkeResult result = solve_lemke(M, q);
  EXPECT_EQ(result.status, LemkeStatus::solved);
  EXPECT_EQ(result.pivots, 0);
  EXPECT_EQ(result.z, Eigen::VectorXd::Zero(2));
  EXPECT_EQ(result.w, q);
}

TEST(Lemke, OneDimensionalProblemHasTheClosedFormSolution) {
  // z = -q/m for m > 0, q < 0: z0 enters, z leaves it at once: two pivots
  const LemkeResult result =
      solve_lemke(Eigen::MatrixXd::Constant(1, 1, 4.0), Eigen::VectorXd::Constant(1, -2.0));
  ASSERT_TRUE(result.solved());
  EXPECT_DOUBLE_EQ(result.z(0), 0.5);
  EXPECT_EQ(result.pivots, 2);
}

TEST(Lemke, InfeasibleProblemEndsInRayTermination) {
  // w = -z - 1 can never be >= 0
  const LemkeResult result =
      solve_lemke(Eigen::MatrixXd::Constant(1, 1, -1.0), Eigen::VectorXd::Constant(1, -1.0));
  EXPECT_EQ(result.status, LemkeStatus::ray_termination);
}

TEST(Lemke, InvalidInputIsReportedWithItsReason) {
  Eigen::MatrixXd M = Eigen::MatrixXd::Identity(2, 3);
  LemkeResult result = solve_lemke(M, Eigen::VectorXd::Ones(2));
  EXPECT_EQ(result.status, LemkeStatus::invalid_input);
  EXPECT_NE(result.message.find("square"), std::string::npos) << result.message;

  result = solve_lemke(Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Ones(3));
  EXPECT_EQ(result.status, LemkeStatus::invalid_input);
  EXPECT_NE(result.message.find("q has 3 entries"), std::string::npos) << result.message;

  M = Eigen::MatrixXd::Identity(2, 2);
  M(1, 0) = NAN;
  result = solve_lemke(M, -Eigen::VectorXd::Ones(2));
  EXPECT_EQ(result.status, LemkeStatus::invalid_input);
  EXPECT_NE(result.message.find("NaN"), std::string::npos) << result.message;

  LemkeOptions options;
  options.acceptance_tolerance = -1.0;
  result = solve_lemke(Eigen::MatrixXd::Identity(2, 2), -Eigen::VectorXd::Ones(2), options);
  EXPECT_EQ(result.status, LemkeStatus::invalid_input);
  EXPECT_NE(result.message.find("acceptance_tolerance"), std::string::npos) << result.message;
}

TEST(Lemke, PivotLimitIsReported) {
  // Murty's n = 6 problem needs 64 pivots
  const LcpProblem problem = read_lcp_file(lcp_data("lcp_exp_murty2.dat"));
  LemkeOptions options;
  options.max_pivots = 10;
  const LemkeResult result = solve_lemke(problem.M, problem.q, options);
  EXPECT_EQ(result.status, LemkeStatus::pivot_limit);
  EXPECT_EQ(result.pivots, 10);
}

// Murty's family: M upper triangular with 1 on the diagonal and 2 above it,
// q_i = -(2^(n+1) - 2^i); Lemke's method takes exactly 2^n pivots (Murty 1988, ch. 6).
TEST(Lemke, MurtyFamilyTakesExactlyTwoToTheNPivots) {
  for (int n = 2; n <= 12; ++n) {
    Eigen::MatrixXd M = Eigen::MatrixXd::Identity(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) M(i, j) = 2.0;
    Eigen::VectorXd q(n);
    for (int i = 1; i <= n; ++i) q(i - 1) = -(std::ldexp(1.0, n + 1) - std::ldexp(1.0, i));
    LemkeOptions options;
    options.max_pivots = 1 << 14;
    const LemkeResult result = solve_lemke(M, q, options);
    ASSERT_TRUE(result.solved()) << "n = " << n << ": " << result.message;
    EXPECT_EQ(result.pivots, 1 << n) << "n = " << n;
    EXPECT_LE(result.complementarity_error, 1e-12);
  }
}

TEST(Lemke, MurtyFileMatchesTheFamilyAtSizeSix) {
  const LcpProblem problem = read_lcp_file(lcp_data("lcp_exp_murty2.dat"));
  EXPECT_EQ(problem.M(0, 1), 2.0);  // upper triangular: the file's lines are columns
  EXPECT_EQ(problem.M(1, 0), 0.0);
  const LemkeResult result = solve_lemke(problem.M, problem.q);
  ASSERT_TRUE(result.solved());
  EXPECT_EQ(result.pivots, 64);
}

// --- agreement with brute-force enumeration of the 2^n complementary bases -------------

struct Enumeration {
  bool feasible = false;
  Eigen::VectorXd z;  // one solution when feasible
  int solutions = 0;  // number of distinct bases giving a solution
};

Enumeration enumerate_lcp(const Eigen::MatrixXd& M, const Eigen::VectorXd& q) {
  const int n = int(q.size());
  Enumeration found;
  for (unsigned mask = 0; mask < (1u << n); ++mask) {
    std::vector<Eigen::Index> support;
    for (int i = 0; i < n; ++i)
      if (mask & (1u << i)) support.push_back(i);
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
    if (!support.empty()) {
      Eigen::FullPivLU<Eigen::MatrixXd> lu(M(support, support));
      if (!lu.isInvertible()) continue;
      z(support) = lu.solve(-q(support));
    }
    if (complementarity_error(M, q, z) <= 1e-10) {
      if (!found.feasible) found.z = z;
      found.feasible = true;
      ++found.solutions;
    }
  }
  return found;
}

Eigen::VectorXd degenerate_q(std::mt19937& random, int n) {
  // repeated values and exact zeros: ties in every ratio test
  std::uniform_int_distribution<int> pick(-2, 1);
  Eigen::VectorXd q(n);
  for (int i = 0; i < n; ++i) q(i) = double(pick(random));
  if (q.minCoeff() >= 0.0) q(0) = -1.0;
  return q;
}

TEST(LemkeVersusEnumeration, PMatricesHaveTheUniqueSolution) {
  std::mt19937 random(2026);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 1 + trial % 8;
    Eigen::MatrixXd A(n, n);
    for (auto& x : A.reshaped()) x = normal(random);
    Eigen::MatrixXd S(n, n);
    for (auto& x : S.reshaped()) x = normal(random);
    // positive definite plus skew-symmetric: a P-matrix, not symmetric
    const Eigen::MatrixXd M =
        A * A.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n) + (S - S.transpose());
    Eigen::VectorXd q(n);
    if (trial % 3 == 0) {
      q = degenerate_q(random, n);
    } else {
      for (auto& x : q) x = normal(random);
    }
    const Enumeration exact = enumerate_lcp(M, q);
    ASSERT_TRUE(exact.feasible);
    ASSERT_EQ(exact.solutions, 1) << "a P-matrix LCP has one solution";
    const LemkeResult result = solve_lemke(M, q);
    ASSERT_TRUE(result.solved()) << "trial " << trial << ": " << result.message;
    EXPECT_LE((result.z - exact.z).cwiseAbs().maxCoeff(),
              1e-9 * std::max(1.0, exact.z.cwiseAbs().maxCoeff()))
        << "trial " << trial;
  }
}

TEST(LemkeVersusEnumeration, PositiveSemidefiniteSolvedExactlyWhenFeasible) {
  std::mt19937 random(7);
  std::normal_distribution<double> normal;
  int feasible = 0, infeasible = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 2 + trial % 7;
    const int rank = 1 + trial % (n - 1);  // singular on purpose
    Eigen::MatrixXd A(n, rank);
    for (auto& x : A.reshaped()) x = normal(random);
    const Eigen::MatrixXd M = A * A.transpose();
    Eigen::VectorXd q(n);
    if (trial % 2 == 0) {
      q = degenerate_q(random, n);
    } else {
      for (auto& x : q) x = normal(random);
    }
    const Enumeration exact = enumerate_lcp(M, q);
    const LemkeResult result = solve_lemke(M, q);
    if (exact.feasible) {
      ++feasible;
      ASSERT_TRUE(result.solved()) << "trial " << trial << ": " << result.message;
      EXPECT_LE(complementarity_error(M, q, result.z), 1e-9);
      // w = M z + q is the same at every solution of a symmetric PSD LCP
      EXPECT_LE((result.w - (M * exact.z + q)).cwiseAbs().maxCoeff(),
                1e-8 * std::max(1.0, q.cwiseAbs().maxCoeff()))
          << "trial " << trial;
    } else {
      ++infeasible;
      EXPECT_EQ(result.status, LemkeStatus::ray_termination) << "trial " << trial;
    }
  }
  EXPECT_GT(feasible, 50);
  EXPECT_GT(infeasible, 20);
}

}  // namespace
}  // namespace mimpact::numerics
