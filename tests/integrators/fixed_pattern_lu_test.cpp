// FixedPatternLu (integrators/fixed_pattern_lu.hpp): solves against a dense
// LU on a fixed pattern whose values change, and chooses new pivots when the
// reused ones meet a zero or a tiny pivot.
#include <random>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <gtest/gtest.h>

#include "integrators/fixed_pattern_lu.hpp"

namespace lieflow {
namespace {

using Sparse = Eigen::SparseMatrix<double>;

bool usesKlu() { return std::string(FixedPatternLu::backend()) == "KLU"; }

/// A block-tridiagonal pattern like a chain's iteration matrix (n blocks of
/// 3), values drawn from `gen`, diagonal strengthened so that it is regular.
Sparse chainMatrix(int blocks, std::mt19937& gen) {
  std::normal_distribution<double> normal;
  std::vector<Eigen::Triplet<double>> t;
  const int n = 3 * blocks;
  for (int b = 0; b < blocks; ++b)
    for (int nb = std::max(0, b - 1); nb <= std::min(blocks - 1, b + 1); ++nb)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) t.emplace_back(3 * b + i, 3 * nb + j, normal(gen) + (b == nb && i == j ? 6.0 : 0.0));
  Sparse A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

double solveError(const FixedPatternLu& lu, const Sparse& A, std::mt19937& gen) {
  std::normal_distribution<double> normal;
  Eigen::VectorXd x_true(A.rows());
  for (Eigen::Index i = 0; i < x_true.size(); ++i) x_true[i] = normal(gen);
  Eigen::VectorXd x = A * x_true;
  lu.solveInPlace(&x);
  return (x - x_true).lpNorm<Eigen::Infinity>();
}

TEST(FixedPatternLu, SolvesWhileTheValuesOfAFixedPatternChange) {
  std::mt19937 gen(5);
  FixedPatternLu lu;
  for (int k = 0; k < 20; ++k) {
    const Sparse A = chainMatrix(30, gen);  // same pattern, new values
    ASSERT_TRUE(lu.factorize(A)) << lu.lastError();
    const Eigen::MatrixXd D = Eigen::MatrixXd(A);
    const double cond = D.norm() * D.inverse().norm();
    EXPECT_LT(solveError(lu, A, gen), 1e-15 * cond * 100) << "factorization " << k;
  }
  EXPECT_EQ(lu.analyzeCount(), 1);
  EXPECT_GT(lu.factorNonzeros(), 0);
  if (usesKlu()) {
    EXPECT_LT(lu.pivotingFactorizations(), 20);  // pivots reused
  }
}

TEST(FixedPatternLu, ChoosesNewPivotsWhenTheOldOnesFail) {
  // [[a, 1], [1, 1]] pivots on a = 2; a = 0 (a zero pivot) or a = 1e-13 (a
  // tiny one: element growth 1e13) then needs the other row as the pivot.
  for (const double a : {0.0, 1e-13}) {
    std::vector<Eigen::Triplet<double>> t = {{0, 0, 2.0}, {0, 1, 1.0}, {1, 0, 1.0}, {1, 1, 1.0}};
    Sparse A(2, 2);
    A.setFromTriplets(t.begin(), t.end());
    A.makeCompressed();
    std::mt19937 gen(1);
    FixedPatternLu lu;
    ASSERT_TRUE(lu.factorize(A));
    EXPECT_LT(solveError(lu, A, gen), 1e-15);
    EXPECT_EQ(lu.pivotingFactorizations(), 1);
    A.coeffRef(0, 0) = a;
    ASSERT_TRUE(lu.factorize(A)) << "a = " << a << ": " << lu.lastError();
    EXPECT_LT(solveError(lu, A, gen), 1e-14) << "a = " << a;
    EXPECT_EQ(lu.pivotingFactorizations(), 2) << "a = " << a;
    // A value the new pivots serve as well: they are kept.
    A.coeffRef(0, 0) = -0.5;
    ASSERT_TRUE(lu.factorize(A));
    EXPECT_LT(solveError(lu, A, gen), 1e-15);
    if (usesKlu()) {
      EXPECT_EQ(lu.pivotingFactorizations(), 2) << "a = " << a;
    }
  }
}

TEST(FixedPatternLu, ReportsASingularMatrix) {
  std::vector<Eigen::Triplet<double>> t = {{0, 0, 1.0}, {0, 1, 2.0}, {1, 0, 2.0}, {1, 1, 4.0}};
  Sparse A(2, 2);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  FixedPatternLu lu;
  EXPECT_FALSE(lu.factorize(A));
  EXPECT_FALSE(lu.lastError().empty());
}

}  // namespace
}  // namespace lieflow
