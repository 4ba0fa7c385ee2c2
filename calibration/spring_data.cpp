#include "calibration/spring_data.hpp"

#include <algorithm>

#include <Eigen/QR>

#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {

SpringData selectSpringData(const Recording& recording, const SpringJoint& joint, int coordinate) {
  SpringData d;
  d.source = recording.source;
  d.time = recording.time;
  const std::string& J = joint.joint_name;
  for (int i = 0; i < joint.coordinates; ++i) {
    const std::string name = J + (joint.coordinates == 1 ? ".phi" : (i == 0 ? ".phi1" : ".phi2"));
    if (const std::vector<double>* values = recording.column(name)) {
      d.angle[i] = *values;
      d.column[i] = name;
    }
  }
  if (!d.has(coordinate)) {
    const std::string wanted = J + (joint.coordinates == 1 ? ".phi" : (coordinate == 0 ? ".phi1" : ".phi2"));
    throw InvalidInput(recording.source, "no column " + wanted + ": calibrate spring fits the recorded angle of joint '" +
                                             J + "' (" + (joint.coordinates == 1 ? "J.phi" : "J.phi1, J.phi2") +
                                             " in the trajectory CSV)");
  }
  return d;
}

Eigen::Vector2d localAngleAndRate(const SpringData& data, int i, int j, int half_width) {
  const int n = data.size();
  const int first = std::max(0, j - half_width), last = std::min(n - 1, j + half_width);
  const int m = last - first + 1;
  // φ(t) ≈ a + b (t − t_j) + c (t − t_j)²: (a, b) = (φ, φ̇) at t_j.
  const int terms = std::min(3, m);
  Eigen::MatrixXd A(m, terms);
  Eigen::VectorXd y(m);
  for (int r = 0; r < m; ++r) {
    const double dt = data.time[first + r] - data.time[j];
    for (int c = 0; c < terms; ++c) A(r, c) = c == 0 ? 1.0 : (c == 1 ? dt : dt * dt);
    y[r] = data.angle[i][first + r];
  }
  const Eigen::VectorXd coef = A.colPivHouseholderQr().solve(y);
  return Eigen::Vector2d(coef[0], terms > 1 ? coef[1] : 0.0);
}

}  // namespace calibration
}  // namespace lieflow
