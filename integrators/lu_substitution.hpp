/// \file
/// Solves with an Eigen::PartialPivLU factorization P A = L U by plain
/// column-oriented substitution, with U's diagonal inverted once per
/// factorization. For the small systems of an implicit stepper's Newton
/// iteration (Radau IIA's real and complex n × n systems, n the tangent's
/// size, often 6–60) this avoids Eigen's blocked triangular solves, built for
/// large right-hand sides, and a complex division per row (libgcc's
/// __divdc3): on slider_crank (n = 6) those took 14 % of a radau5 run.
/// No heap allocation: x is sized by the caller.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>

namespace lieflow {

template <typename Scalar>
class LuSubstitution {
 public:
  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;

  /// Factors A (P A = L U, partial pivoting) and inverts U's diagonal.
  /// Precondition: A square and invertible (a zero pivot gives inf).
  void compute(const Matrix& A) {
    lu_.compute(A);
    inverse_diagonal_ = lu_.matrixLU().diagonal().cwiseInverse();
  }

  /// x = A⁻¹ b (any Eigen vectors of the scalar, fixed or dynamic size).
  /// Precondition: x and b of A's size and distinct.
  template <typename In, typename Out>
  void solve(const In& b, Out* x) const {
    const Matrix& LU = lu_.matrixLU();
    const auto& perm = lu_.permutationP().indices();
    const Eigen::Index n = LU.rows();
    for (Eigen::Index i = 0; i < n; ++i) (*x)[perm[i]] = b[i];  // P b
    // L y = P b (unit diagonal), column by column.
    for (Eigen::Index j = 0; j < n; ++j) {
      const Scalar xj = (*x)[j];
      for (Eigen::Index i = j + 1; i < n; ++i) (*x)[i] -= LU(i, j) * xj;
    }
    // U x = y, column by column from the last.
    for (Eigen::Index j = n - 1; j >= 0; --j) {
      const Scalar xj = (*x)[j] * inverse_diagonal_[j];
      (*x)[j] = xj;
      for (Eigen::Index i = 0; i < j; ++i) (*x)[i] -= LU(i, j) * xj;
    }
  }

 private:
  Eigen::PartialPivLU<Matrix> lu_;
  Vector inverse_diagonal_;
};

}  // namespace lieflow
