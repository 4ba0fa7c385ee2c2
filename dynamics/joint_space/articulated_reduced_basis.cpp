/// \file
/// ReducedBasis (articulated_coupled_alpha.hpp): N = [identity on the
/// coordinates no coupling row touches; a dense block on the touched ones],
/// applied through that structure.
#include "dynamics/joint_space/articulated_coupled_alpha.hpp"

namespace lieflow {
namespace articulated {

ReducedBasis::ReducedBasis(const Eigen::MatrixXd& N) {
  const int n = static_cast<int>(N.rows()), k = static_cast<int>(N.cols());
  std::vector<bool> free_row(static_cast<std::size_t>(n), false);
  for (int c = 0; c < k; ++c) {
    // An identity column: a single entry, exactly 1 (kernelBasis writes it so).
    int nonzero = 0, at = -1;
    for (int r = 0; r < n; ++r)
      if (N(r, c) != 0.0) {
        ++nonzero;
        at = r;
      }
    if (nonzero == 1 && N(at, c) == 1.0) {
      free_rows.push_back(at);
      free_cols.push_back(c);
      free_row[static_cast<std::size_t>(at)] = true;
    } else {
      mixed_cols.push_back(c);
    }
  }
  for (int r = 0; r < n; ++r)
    if (!free_row[static_cast<std::size_t>(r)]) touched_rows.push_back(r);
  block.resize(static_cast<Eigen::Index>(touched_rows.size()), static_cast<Eigen::Index>(mixed_cols.size()));
  for (std::size_t i = 0; i < touched_rows.size(); ++i)
    for (std::size_t j = 0; j < mixed_cols.size(); ++j)
      block(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = N(touched_rows[i], mixed_cols[j]);
}

void ReducedBasis::expand(const Eigen::VectorXd& w, Eigen::VectorXd* u) const {
  u->resize(fullSize());
  for (std::size_t i = 0; i < free_rows.size(); ++i) (*u)(free_rows[i]) = w(free_cols[i]);
  for (std::size_t i = 0; i < touched_rows.size(); ++i) {
    double sum = 0.0;
    for (std::size_t j = 0; j < mixed_cols.size(); ++j)
      sum += block(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) * w(mixed_cols[j]);
    (*u)(touched_rows[i]) = sum;
  }
}

void ReducedBasis::project(const Eigen::VectorXd& u, Eigen::VectorXd* w) const {
  w->resize(reducedSize());
  for (std::size_t i = 0; i < free_rows.size(); ++i) (*w)(free_cols[i]) = u(free_rows[i]);
  for (std::size_t j = 0; j < mixed_cols.size(); ++j) {
    double sum = 0.0;
    for (std::size_t i = 0; i < touched_rows.size(); ++i)
      sum += block(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) * u(touched_rows[i]);
    (*w)(mixed_cols[j]) = sum;
  }
}

void ReducedBasis::reduce(const Eigen::MatrixXd& A, Eigen::MatrixXd* out, Scratch* s) const {
  // With F the free and T the touched coordinates, B the block:
  //   Nᵀ A N = [A_FF, A_FT B; Bᵀ A_TF, Bᵀ A_TT B].
  const Eigen::Index n = fullSize(), f = static_cast<Eigen::Index>(free_rows.size());
  const Eigen::Index t = static_cast<Eigen::Index>(touched_rows.size());
  out->resize(reducedSize(), reducedSize());
  for (Eigen::Index a = 0; a < f; ++a)
    for (Eigen::Index b = 0; b < f; ++b) (*out)(free_cols[a], free_cols[b]) = A(free_rows[a], free_rows[b]);
  if (mixed_cols.empty()) return;
  s->rows.resize(t, n);  // A's touched rows
  s->cols.resize(n, t);  // A's touched columns
  for (Eigen::Index i = 0; i < t; ++i) {
    s->rows.row(i) = A.row(touched_rows[i]);
    s->cols.col(i) = A.col(touched_rows[i]);
  }
  s->left.noalias() = block.transpose() * s->rows;  // Bᵀ A_T· (k × n)
  s->right.noalias() = s->cols * block;             // A_·T B (n × k)
  const Eigen::Index k = static_cast<Eigen::Index>(mixed_cols.size());
  for (Eigen::Index j = 0; j < k; ++j) {
    for (Eigen::Index a = 0; a < f; ++a) {
      (*out)(mixed_cols[j], free_cols[a]) = s->left(j, free_rows[a]);
      (*out)(free_cols[a], mixed_cols[j]) = s->right(free_rows[a], j);
    }
    for (Eigen::Index i = 0; i < k; ++i) {
      double sum = 0.0;
      for (Eigen::Index r = 0; r < t; ++r) sum += s->left(j, touched_rows[r]) * block(r, i);
      (*out)(mixed_cols[j], mixed_cols[i]) = sum;
    }
  }
}

}  // namespace articulated
}  // namespace lieflow
