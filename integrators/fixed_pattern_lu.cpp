#include "integrators/fixed_pattern_lu.hpp"

#ifdef LIEFLOW_HAVE_KLU
#include <klu.h>
#else
#include <Eigen/SparseLU>
#endif

namespace lieflow {

#ifdef LIEFLOW_HAVE_KLU

struct FixedPatternLu::Impl {
  klu_common common{};
  klu_symbolic* symbolic = nullptr;
  klu_numeric* numeric = nullptr;
  double pivot_rcond = 0.0;  ///< min|u_kk| / max|u_kk| at the last pivot choice
  bool repivot = false;      ///< the caller asked for new pivots
  int analyses = 0;
  int pivotings = 0;
  std::string error;

  Impl() { klu_defaults(&common); }
  ~Impl() { release(); }
  void release() {
    if (numeric) klu_free_numeric(&numeric, &common);
    if (symbolic) klu_free_symbolic(&symbolic, &common);
  }
  /// A fresh factorization with pivot choice.
  bool pivot(const Eigen::SparseMatrix<double>& A) {
    if (numeric) klu_free_numeric(&numeric, &common);
    numeric = klu_factor(const_cast<int*>(A.outerIndexPtr()), const_cast<int*>(A.innerIndexPtr()),
                         const_cast<double*>(A.valuePtr()), symbolic, &common);
    ++pivotings;
    if (!numeric || common.status != KLU_OK) {
      error = common.status == KLU_SINGULAR ? "the matrix is singular (KLU)" : "KLU factorization failed";
      if (numeric) klu_free_numeric(&numeric, &common);
      return false;
    }
    klu_rcond(symbolic, numeric, &common);
    pivot_rcond = common.rcond;
    repivot = false;
    return true;
  }
};

FixedPatternLu::FixedPatternLu() : impl_(std::make_unique<Impl>()) {}
FixedPatternLu::~FixedPatternLu() = default;
FixedPatternLu::FixedPatternLu(FixedPatternLu&&) noexcept = default;
FixedPatternLu& FixedPatternLu::operator=(FixedPatternLu&&) noexcept = default;

void FixedPatternLu::reset() { impl_->release(); }

bool FixedPatternLu::factorize(const Eigen::SparseMatrix<double>& A) {
  Impl& s = *impl_;
  s.error.clear();
  int* Ap = const_cast<int*>(A.outerIndexPtr());
  int* Ai = const_cast<int*>(A.innerIndexPtr());
  double* Ax = const_cast<double*>(A.valuePtr());
  if (!s.symbolic) {
    s.symbolic = klu_analyze(static_cast<int>(A.rows()), Ap, Ai, &s.common);
    ++s.analyses;
    if (!s.symbolic) {
      s.error = "KLU could not analyse the pattern";
      return false;
    }
  }
  if (!s.numeric || s.repivot) return s.pivot(A);
  // Same pivots, new values: no pivoting, no allocation.
  if (klu_refactor(Ap, Ai, Ax, s.symbolic, s.numeric, &s.common) && s.common.status == KLU_OK &&
      klu_rcond(s.symbolic, s.numeric, &s.common) && s.common.rcond >= kRepivotRatio * s.pivot_rcond)
    return true;
  return s.pivot(A);
}

void FixedPatternLu::choosePivotsNext() { impl_->repivot = true; }

void FixedPatternLu::solveInPlace(Eigen::VectorXd* x) const {
  Impl& s = *impl_;
  klu_solve(s.symbolic, s.numeric, static_cast<int>(x->size()), 1, x->data(), &s.common);
}

long long FixedPatternLu::factorNonzeros() const {
  return impl_->numeric ? static_cast<long long>(impl_->numeric->lnz) + impl_->numeric->unz : 0;
}

const char* FixedPatternLu::backend() { return "KLU"; }

#else  // Eigen's SparseLU

struct FixedPatternLu::Impl {
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
  bool analysed = false;
  int analyses = 0;
  int pivotings = 0;
  std::string error;
  Impl() {
    // The pattern is structurally symmetric (J and Jᵀ): symmetric mode with
    // a relaxed diagonal preference halves the fill on chains.
    lu.isSymmetric(true);
    lu.setPivotThreshold(0.1);
  }
};

FixedPatternLu::FixedPatternLu() : impl_(std::make_unique<Impl>()) {}
FixedPatternLu::~FixedPatternLu() = default;
FixedPatternLu::FixedPatternLu(FixedPatternLu&&) noexcept = default;
FixedPatternLu& FixedPatternLu::operator=(FixedPatternLu&&) noexcept = default;

void FixedPatternLu::reset() { impl_->analysed = false; }

bool FixedPatternLu::factorize(const Eigen::SparseMatrix<double>& A) {
  Impl& s = *impl_;
  s.error.clear();
  if (!s.analysed) {
    s.lu.analyzePattern(A);
    s.analysed = true;
    ++s.analyses;
  }
  s.lu.factorize(A);
  ++s.pivotings;
  if (s.lu.info() != Eigen::Success) {
    s.error = "SparseLU: " + s.lu.lastErrorMessage();
    return false;
  }
  return true;
}

void FixedPatternLu::choosePivotsNext() {}  // SparseLU pivots at every factorization

void FixedPatternLu::solveInPlace(Eigen::VectorXd* x) const { *x = impl_->lu.solve(*x); }

long long FixedPatternLu::factorNonzeros() const {
  return static_cast<long long>(impl_->lu.nnzL()) + impl_->lu.nnzU();
}

const char* FixedPatternLu::backend() { return "Eigen SparseLU"; }

#endif

int FixedPatternLu::analyzeCount() const { return impl_->analyses; }
int FixedPatternLu::pivotingFactorizations() const { return impl_->pivotings; }
const std::string& FixedPatternLu::lastError() const { return impl_->error; }

}  // namespace lieflow
