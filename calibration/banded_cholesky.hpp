/// \file
/// Cholesky factorization A = L Lᵀ of a symmetric positive definite banded
/// matrix, and its solves: O(N B²) to factor, O(N B) per right-hand side.
/// The lower triangle is stored by rows, band[k (B + 1) + d] = A(k, k − d)
/// for d = 0 … B (B the half-bandwidth; entries before row 0 unused), and is
/// overwritten by L in the same layout. The likelihood hinge fit's normal
/// equations in the joint angles are banded with B = 4
/// (hinge_likelihood_problem.hpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace lieflow {
namespace calibration {

/// In place; false at a pivot not above `singular` times its diagonal entry
/// (or not a number): the matrix is singular to that threshold.
template <int B>
bool bandedCholesky(std::vector<double>* band, int n, double singular) {
  const auto L = [&](int row, int col) -> double& {
    return (*band)[static_cast<std::size_t>(row) * (B + 1) + (row - col)];
  };
  for (int k = 0; k < n; ++k)
    for (int j = std::max(0, k - B); j <= k; ++j) {
      const double diagonal = L(k, j);
      double s = diagonal;
      for (int i = std::max(0, k - B); i < j; ++i) s -= L(k, i) * L(j, i);
      if (j < k) {
        L(k, j) = s / L(j, j);
      } else {
        if (!(s > singular * diagonal)) return false;
        L(k, k) = std::sqrt(s);
      }
    }
  return true;
}

/// X ← (L Lᵀ)⁻¹ X for a factor from bandedCholesky, every column at once:
/// X an Eigen matrix of n rows (row-major, so that a row's update is one
/// short vector operation).
template <int B, typename Rhs>
void bandedSolve(const std::vector<double>& band, int n, Rhs* x) {
  const auto L = [&](int row, int col) { return band[static_cast<std::size_t>(row) * (B + 1) + (row - col)]; };
  for (int k = 0; k < n; ++k) {
    for (int i = std::max(0, k - B); i < k; ++i) x->row(k) -= L(k, i) * x->row(i);
    x->row(k) /= L(k, k);
  }
  for (int k = n - 1; k >= 0; --k) {
    for (int i = k + 1; i <= std::min(n - 1, k + B); ++i) x->row(k) -= L(i, k) * x->row(i);
    x->row(k) /= L(k, k);
  }
}

}  // namespace calibration
}  // namespace lieflow
