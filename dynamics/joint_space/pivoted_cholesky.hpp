/// \file
/// Cholesky factorization with diagonal pivoting of a symmetric positive
/// semidefinite matrix, stopped at the first pivot below a threshold (Higham,
/// "Accuracy and Stability of Numerical Algorithms", 2nd ed., §10.3; LAPACK's
/// dpstrf): A = P L Lᵀ Pᵀ on the first `rank` rows. The loops' matrices
/// G M⁻¹ Gᵀ are singular where a loop repeats a row (the point rows of a
/// universal joint between two bodies turning about their held centres, the
/// rows of a planar loop out of its plane); those rows get no pivot and a
/// zero multiplier, the others are solved exactly (the repeated rows'
/// equations then hold too: they are combinations of the pivot rows).
/// In place, on preallocated storage: nothing allocated.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace lieflow {
namespace articulated {

/// Pivots of G M⁻¹ Gᵀ below this fraction of its largest diagonal entry are
/// taken as zero: rows a loop repeats (their pivots are
/// rounding, ~1e-16 of the largest) drop out. A genuine row weaker than this
/// is a loop within 1e-10 of a singular configuration.
constexpr double kClosureRankTolerance = 1e-10;

/// Factors the symmetric A (m × m) in place: its lower triangle becomes L in
/// the pivot order `perm` (size m). Pivots at or below relative_tolerance ×
/// the largest diagonal entry end the factorization. Returns the rank.
inline int pivotedCholesky(Eigen::MatrixXd& A, std::vector<int>& perm, double relative_tolerance) {
  const int m = static_cast<int>(A.rows());
  for (int k = 0; k < m; ++k) perm[k] = k;
  const double floor = relative_tolerance * std::max(m > 0 ? A.diagonal().maxCoeff() : 0.0, 1e-300);
  int rank = 0;
  for (int k = 0; k < m; ++k) {
    int p = k;
    for (int i = k + 1; i < m; ++i)
      if (A(i, i) > A(p, p)) p = i;
    if (!(A(p, p) > floor)) break;
    if (p != k) {
      A.row(k).swap(A.row(p));
      A.col(k).swap(A.col(p));
      std::swap(perm[k], perm[p]);
    }
    const double l = std::sqrt(A(k, k));
    A(k, k) = l;
    for (int i = k + 1; i < m; ++i) A(i, k) /= l;
    for (int j = k + 1; j < m; ++j)
      for (int i = j; i < m; ++i) {
        A(i, j) -= A(i, k) * A(j, k);
        A(j, i) = A(i, j);
      }
    rank = k + 1;
  }
  return rank;
}

/// x with L Lᵀ (P x) = P rhs on the first `rank` pivot rows and 0 on the
/// others, from pivotedCholesky's L, perm and rank; s is scratch (size m).
inline void pivotedCholeskySolve(const Eigen::MatrixXd& L, const std::vector<int>& perm, int rank,
                                 const Eigen::VectorXd& rhs, Eigen::VectorXd& s, Eigen::VectorXd* x) {
  for (int i = 0; i < rank; ++i) {
    double v = rhs[perm[i]];
    for (int k = 0; k < i; ++k) v -= L(i, k) * s[k];
    s[i] = v / L(i, i);
  }
  for (int i = rank - 1; i >= 0; --i) {
    double v = s[i];
    for (int k = i + 1; k < rank; ++k) v -= L(k, i) * s[k];
    s[i] = v / L(i, i);
  }
  x->setZero();
  for (int i = 0; i < rank; ++i) (*x)[perm[i]] = s[i];
}

}  // namespace articulated
}  // namespace lieflow
