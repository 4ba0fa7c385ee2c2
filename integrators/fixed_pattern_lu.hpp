/// \file
/// Sparse LU of a square matrix whose sparsity pattern stays fixed while its
/// values change, as the generalized-α iteration matrix with joints does from
/// one Newton iteration to the next: KLU (Davis & Palamadai Natarajan 2010,
/// "Algorithm 907: KLU, a direct sparse solver for circuit simulation
/// problems", ACM TOMS 37(3)) from SuiteSparse.
///
/// The pattern is ordered once (block triangular form, then AMD per block);
/// the first factorization chooses the pivots (partial pivoting with a
/// preference for the diagonal); later ones reuse them (klu_refactor: no
/// pivoting and no allocation) until they go bad: a refactorization meets a
/// zero pivot, or its crude reciprocal condition number min|u_kk| / max|u_kk|
/// (klu_rcond, O(n)) falls below kRepivotRatio times its value at the last
/// pivot choice, or the caller saw the solution fail (choosePivotsNext(): the
/// generalized-α Newton iteration calls it when its line search has to
/// shorten a correction); then pivots are chosen again (this allocates).
/// klu_rgrowth, the pivot growth itself, would cost as much as the
/// refactorization (measured: 25 % of a chain-30 step against 34 %).
///
/// Without KLU (a build without libsuitesparse-dev) Eigen's SparseLU does
/// every factorization, and allocates in each.
#pragma once

#include <memory>
#include <string>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace lieflow {

class FixedPatternLu {
 public:
  /// A refactorization whose reciprocal condition estimate dropped below
  /// this fraction of the one at the last pivot choice chooses pivots again.
  static constexpr double kRepivotRatio = 1e-3;

  FixedPatternLu();
  ~FixedPatternLu();
  FixedPatternLu(FixedPatternLu&&) noexcept;
  FixedPatternLu& operator=(FixedPatternLu&&) noexcept;

  /// Forgets the pattern: the next factorize() analyses its matrix's.
  void reset();

  /// Factors A (square, compressed; the pattern of the previous call unless
  /// reset() was called since). Returns false, with lastError(), when A is
  /// singular.
  bool factorize(const Eigen::SparseMatrix<double>& A);

  /// The next factorize() chooses pivots again.
  void choosePivotsNext();

  /// x ← A⁻¹ x with the last successful factorization.
  void solveInPlace(Eigen::VectorXd* x) const;

  /// Entries of L and U.
  long long factorNonzeros() const;
  /// Patterns analysed, and factorizations that chose pivots, so far.
  int analyzeCount() const;
  int pivotingFactorizations() const;
  const std::string& lastError() const;
  /// "KLU" or "Eigen SparseLU".
  static const char* backend();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lieflow
