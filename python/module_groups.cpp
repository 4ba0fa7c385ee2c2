/// \file
/// The vectorized SO(3) and SE(3) kernels of the Python module: each takes
/// arrays of shape (N, k), applies lieflow's own SO3<double> / SE3<double>
/// to every row (so the numbers are those of the C++ library, bit for bit)
/// and returns an (N, m) array. Binary operations broadcast a single row
/// against N. Storage: SO(3) as unit quaternions (w, x, y, z), SE(3) as
/// (qw, qx, qy, qz, x, y, z). The Python classes (lieflow/groups.py) shape
/// the results; the GIL is released inside the loops.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "liegroup/input_number.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/se3.hpp"
#include "liegroup/so3.hpp"
#include "python/module_parts.hpp"

namespace py = pybind11;

namespace lieflow {
namespace python {
namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// Rows of an (N, k) array; a wrong shape is an InvalidInput naming `what`.
long rowsOf(const Array& a, long k, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != k) {
    std::ostringstream reason;
    reason << "expected an array of shape (N, " << k << "), got shape (";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) reason << (i ? ", " : "") << a.shape(i);
    reason << ")";
    throw InvalidInput(what, reason.str());
  }
  return static_cast<long>(a.shape(0));
}

/// Every entry a usable input number (finite, within ±kMaxInputMagnitude:
/// liegroup/input_number.hpp), else an InvalidInput naming the row and column.
void checkFinite(const Array& a, long k, const char* what) {
  const double* x = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i) {
    const std::string problem = inputNumberProblem(x[i]);
    if (!problem.empty())
      throw InvalidInput(std::string(what) + "[" + std::to_string(i / k) + ", " + std::to_string(i % k) + "]",
                         problem);
  }
}

template <typename F>
Array unary(const Array& in, long k, long m, const char* what, F&& f) {
  const long n = rowsOf(in, k, what);
  checkFinite(in, k, what);
  Array out({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(m)});
  const double* x = in.data();
  double* y = out.mutable_data();
  {
    py::gil_scoped_release release;
    for (long i = 0; i < n; ++i) f(x + i * k, y + i * m, i);
  }
  return out;
}

template <typename F>
Array binary(const Array& a, long ka, const Array& b, long kb, long m, const char* what, F&& f) {
  const long na = rowsOf(a, ka, what), nb = rowsOf(b, kb, what);
  checkFinite(a, ka, what);
  checkFinite(b, kb, what);
  if (na != nb && na != 1 && nb != 1) {
    std::ostringstream reason;
    reason << "cannot pair " << na << " elements with " << nb << " (give equal counts, or one of them)";
    throw InvalidInput(what, reason.str());
  }
  const long n = std::max(na, nb);
  Array out({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(m)});
  const double* x = a.data();
  const double* z = b.data();
  double* y = out.mutable_data();
  {
    py::gil_scoped_release release;
    for (long i = 0; i < n; ++i) f(x + (na == 1 ? 0 : i) * ka, z + (nb == 1 ? 0 : i) * kb, y + i * m);
  }
  return out;
}

/// Stored rows hold group elements the module made (unit to rounding), read
/// without the checks of the factories.
SO3d so3At(const double* p) { return SO3d(Eigen::Quaterniond(p[0], p[1], p[2], p[3])); }
SE3d se3At(const double* p) { return SE3d(so3At(p), Eigen::Vector3d(p[4], p[5], p[6])); }
void put(const SO3d& R, double* out) {
  const Eigen::Quaterniond& q = R.quaternion();
  out[0] = q.w(), out[1] = q.x(), out[2] = q.y(), out[3] = q.z();
}
void put(const SE3d& X, double* out) {
  put(X.rotation(), out);
  for (int i = 0; i < 3; ++i) out[4 + i] = X.translation()[i];
}
template <int R, int C>
void putMatrix(const Eigen::Matrix<double, R, C>& M, double* out) {
  Eigen::Map<Eigen::Matrix<double, R, C, Eigen::RowMajor>> rows(out);  // NumPy's row-major order
  rows = M;
}
template <int N>
Eigen::Map<Eigen::Matrix<double, N, 1>> mapOut(double* p) {
  return Eigen::Map<Eigen::Matrix<double, N, 1>>(p);
}
Eigen::Map<const Eigen::Vector3d> vec3(const double* p) { return Eigen::Map<const Eigen::Vector3d>(p); }
Eigen::Map<const Vector6<double>> vec6(const double* p) { return Eigen::Map<const Vector6<double>>(p); }
std::string rowName(const char* what, long i) { return std::string(what) + "[" + std::to_string(i) + "]"; }

void defineSo3(py::module_& m) {
  m.def("so3_exp", [](const Array& w) {
    return unary(w, 3, 4, "SO3.exp: tangent", [](const double* x, double* y, long) { put(SO3d::exp(vec3(x)), y); });
  });
  m.def("so3_log", [](const Array& q) {
    return unary(q, 4, 3, "SO3.log", [](const double* x, double* y, long) {
      mapOut<3>(y) = so3At(x).log();
    });
  });
  m.def("so3_inverse", [](const Array& q) {
    return unary(q, 4, 4, "SO3.inverse", [](const double* x, double* y, long) { put(so3At(x).inverse(), y); });
  });
  m.def("so3_compose", [](const Array& a, const Array& b) {
    return binary(a, 4, b, 4, 4, "SO3 compose", [](const double* x, const double* z, double* y) {
      put(so3At(x) * so3At(z), y);
    });
  });
  m.def("so3_act", [](const Array& q, const Array& p) {
    return binary(q, 4, p, 3, 3, "SO3.act: points", [](const double* x, const double* z, double* y) {
      mapOut<3>(y) = so3At(x) * Eigen::Vector3d(vec3(z));
    });
  });
  m.def("so3_matrix", [](const Array& q) {
    return unary(q, 4, 9, "SO3.matrix", [](const double* x, double* y, long) { putMatrix(so3At(x).matrix(), y); });
  });
  m.def("so3_adj", [](const Array& q) {
    return unary(q, 4, 9, "SO3.Adj", [](const double* x, double* y, long) { putMatrix(so3At(x).Adj(), y); });
  });
  m.def("so3_jacobian", [](const Array& w, const std::string& which) {
    using Fn = Matrix3<double> (*)(const Eigen::Vector3d&);
    const Fn fn = which == "Jr" ? Fn(&SO3d::Jr) : which == "Jl" ? Fn(&SO3d::Jl)
                : which == "JrInv" ? Fn(&SO3d::JrInv) : Fn(&SO3d::JlInv);
    return unary(w, 3, 9, "SO3 Jacobian: tangent", [fn](const double* x, double* y, long) {
      putMatrix(fn(Eigen::Vector3d(vec3(x))), y);
    });
  });
  m.def("so3_from_quaternion", [](const Array& q) {
    return unary(q, 4, 4, "SO3.from_quaternion", [](const double* x, double* y, long i) {
      put(SO3d::fromQuaternionChecked(Eigen::Quaterniond(x[0], x[1], x[2], x[3]), rowName("quaternion", i)), y);
    });
  });
  m.def("so3_from_matrix", [](const Array& M) {
    return unary(M, 9, 4, "SO3.from_matrix", [](const double* x, double* y, long i) {
      const Matrix3<double> R = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(x);
      put(SO3d::fromRotationMatrixChecked(R, rowName("matrix", i)), y);
    });
  });
}

void defineSe3(py::module_& m) {
  m.def("se3_exp", [](const Array& xi) {
    return unary(xi, 6, 7, "SE3.exp: tangent", [](const double* x, double* y, long) { put(SE3d::exp(vec6(x)), y); });
  });
  m.def("se3_log", [](const Array& X) {
    return unary(X, 7, 6, "SE3.log", [](const double* x, double* y, long) {
      mapOut<6>(y) = se3At(x).log();
    });
  });
  m.def("se3_inverse", [](const Array& X) {
    return unary(X, 7, 7, "SE3.inverse", [](const double* x, double* y, long) { put(se3At(x).inverse(), y); });
  });
  m.def("se3_compose", [](const Array& a, const Array& b) {
    return binary(a, 7, b, 7, 7, "SE3 compose", [](const double* x, const double* z, double* y) {
      put(se3At(x) * se3At(z), y);
    });
  });
  m.def("se3_act", [](const Array& X, const Array& p) {
    return binary(X, 7, p, 3, 3, "SE3.act: points", [](const double* x, const double* z, double* y) {
      mapOut<3>(y) = se3At(x) * Eigen::Vector3d(vec3(z));
    });
  });
  m.def("se3_matrix", [](const Array& X) {
    return unary(X, 7, 16, "SE3.matrix", [](const double* x, double* y, long) { putMatrix(se3At(x).matrix(), y); });
  });
  m.def("se3_adj", [](const Array& X) {
    return unary(X, 7, 36, "SE3.Adj", [](const double* x, double* y, long) { putMatrix(se3At(x).Adj(), y); });
  });
  m.def("se3_jacobian", [](const Array& xi, const std::string& which) {
    using Fn = Matrix6<double> (*)(const Vector6<double>&);
    const Fn fn = which == "Jr" ? Fn(&SE3d::Jr) : which == "Jl" ? Fn(&SE3d::Jl)
                : which == "JrInv" ? Fn(&SE3d::JrInv) : Fn(&SE3d::JlInv);
    return unary(xi, 6, 36, "SE3 Jacobian: tangent", [fn](const double* x, double* y, long) {
      putMatrix(fn(Vector6<double>(vec6(x))), y);
    });
  });
  m.def("se3_from_quaternion_translation", [](const Array& X) {
    return unary(X, 7, 7, "SE3.from_quaternion_translation", [](const double* x, double* y, long i) {
      put(SE3d::fromQuaternionTranslationChecked(Eigen::Quaterniond(x[0], x[1], x[2], x[3]),
                                                 Eigen::Vector3d(x[4], x[5], x[6]), rowName("pose", i)),
          y);
    });
  });
  m.def("se3_from_matrix", [](const Array& M) {
    return unary(M, 16, 7, "SE3.from_matrix", [](const double* x, double* y, long i) {
      const Eigen::Matrix4d T = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(x);
      put(SE3d::fromMatrixChecked(T, rowName("matrix", i)), y);
    });
  });
}

}  // namespace

void defineGroups(py::module_& m) {
  defineSo3(m);
  defineSe3(m);
}

}  // namespace python
}  // namespace lieflow
