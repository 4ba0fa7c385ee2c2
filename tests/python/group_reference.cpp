/// \file
/// The C++ side of the Python group tests (tests/python/test_groups.py): reads
/// lines "OP x1 x2 ..." (numbers as C99 hex floats, so nothing is rounded in
/// transit), applies lieflow's SO3<double>/SE3<double> one element at a time,
/// and prints the results as hex floats, one line per input line. The Python
/// module must give the same bits on the same inputs.
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "liegroup/se3.hpp"
#include "liegroup/so3.hpp"

namespace {

using lieflow::SE3d;
using lieflow::SO3d;

std::vector<double> parse(std::istringstream& in) {
  std::vector<double> v;
  std::string token;
  while (in >> token) v.push_back(std::strtod(token.c_str(), nullptr));
  return v;
}

SO3d so3(const double* p) { return SO3d(Eigen::Quaterniond(p[0], p[1], p[2], p[3])); }
SE3d se3(const double* p) { return SE3d(so3(p), Eigen::Vector3d(p[4], p[5], p[6])); }

template <typename Derived>
void print(const Eigen::MatrixBase<Derived>& m) {
  for (int i = 0; i < m.rows(); ++i)  // row-major, as NumPy
    for (int j = 0; j < m.cols(); ++j) std::printf("%a ", m(i, j));
  std::printf("\n");
}
void print(const SO3d& R) {
  const Eigen::Quaterniond& q = R.quaternion();
  std::printf("%a %a %a %a\n", q.w(), q.x(), q.y(), q.z());
}
void print(const SE3d& X) {
  const Eigen::Quaterniond& q = X.quaternion();
  const Eigen::Vector3d& t = X.translation();
  std::printf("%a %a %a %a %a %a %a\n", q.w(), q.x(), q.y(), q.z(), t.x(), t.y(), t.z());
}

}  // namespace

int main() {
  std::string line;
  while (std::getline(std::cin, line)) {
    std::istringstream in(line);
    std::string op;
    in >> op;
    const std::vector<double> v = parse(in);
    const double* x = v.data();
    const Eigen::Vector3d w = v.size() >= 3 ? Eigen::Vector3d(x[0], x[1], x[2]) : Eigen::Vector3d::Zero();
    lieflow::Vector6<double> xi = lieflow::Vector6<double>::Zero();
    if (v.size() >= 6) xi << x[0], x[1], x[2], x[3], x[4], x[5];
    if (op == "so3_exp") print(SO3d::exp(w));
    else if (op == "so3_log") print(so3(x).log());
    else if (op == "so3_inverse") print(so3(x).inverse());
    else if (op == "so3_compose") print(so3(x) * so3(x + 4));
    else if (op == "so3_act") print(so3(x) * Eigen::Vector3d(x[4], x[5], x[6]));
    else if (op == "so3_matrix") print(so3(x).matrix());
    else if (op == "so3_Jr") print(SO3d::Jr(w));
    else if (op == "so3_Jl") print(SO3d::Jl(w));
    else if (op == "so3_JrInv") print(SO3d::JrInv(w));
    else if (op == "so3_JlInv") print(SO3d::JlInv(w));
    else if (op == "se3_exp") print(SE3d::exp(xi));
    else if (op == "se3_log") print(se3(x).log());
    else if (op == "se3_inverse") print(se3(x).inverse());
    else if (op == "se3_compose") print(se3(x) * se3(x + 7));
    else if (op == "se3_act") print(se3(x) * Eigen::Vector3d(x[7], x[8], x[9]));
    else if (op == "se3_matrix") print(se3(x).matrix());
    else if (op == "se3_Adj") print(se3(x).Adj());
    else if (op == "se3_Jr") print(SE3d::Jr(xi));
    else if (op == "se3_JlInv") print(SE3d::JlInv(xi));
    else {
      std::fprintf(stderr, "unknown op %s\n", op.c_str());
      return 2;
    }
  }
  return 0;
}
