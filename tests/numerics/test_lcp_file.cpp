#include "mimpact/numerics/lcp_file.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "mimpact/common/error.hpp"

namespace mimpact::numerics {
namespace {

TEST(LcpFile, EachPrintedLineIsAColumn) {
  std::istringstream in("2\n0\n2\n2\n2 2\n1 2\n3 4\n-1 -2\n# comment\n");
  const LcpProblem problem = read_lcp(in, "inline");
  Eigen::MatrixXd expected(2, 2);
  expected << 1, 3, 2, 4;
  EXPECT_EQ(problem.M, expected);
  EXPECT_EQ(problem.q, Eigen::Vector2d(-1, -2));
}

TEST(LcpFile, SparseBlockStorageIsRefusedWithItsReason) {
  std::istringstream in("2\n1\n2\n2\n1\n1\n");
  try {
    read_lcp(in, "block.dat");
    FAIL() << "no error";
  } catch (const InvalidInput& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("block.dat"), std::string::npos) << what;
    EXPECT_NE(what.find("storage = 1"), std::string::npos) << what;
    EXPECT_NE(what.find("dense"), std::string::npos) << what;
  }
}

TEST(LcpFile, TruncatedFileNamesTheMissingEntry) {
  std::istringstream in("2\n0\n2\n2\n2 2\n1 2\n3 4\n-1\n");
  try {
    read_lcp(in, "short.dat");
    FAIL() << "no error";
  } catch (const InvalidInput& error) {
    EXPECT_NE(std::string(error.what()).find("q(1)"), std::string::npos) << error.what();
  }
}

TEST(LcpFile, MissingFileIsAnError) {
  EXPECT_THROW(read_lcp_file("/nonexistent/lcp.dat"), InvalidInput);
}

}  // namespace
}  // namespace mimpact::numerics
