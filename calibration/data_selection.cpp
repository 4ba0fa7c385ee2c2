#include "calibration/data_selection.hpp"

#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {
namespace {

std::string has(const BodySamples& b) {
  if (b.hasOrientation() && b.hasAngularVelocity()) return "orientations and angular velocities";
  if (b.hasOrientation()) return "only orientations";
  if (b.hasAngularVelocity()) return "only angular velocities";
  return "neither orientations nor angular velocities";
}

void requireGroup(const JointSamples& s, bool orientation, const std::string& joint) {
  for (const BodySamples* b : {&s.main, &s.secondary}) {
    const bool present = orientation ? b->hasOrientation() : b->hasAngularVelocity();
    if (!present) {
      const std::string& n = b->name;
      throw InvalidInput(s.source, joint + " fit with " + (orientation ? "orientations" : "gyroscopes") +
                                       ": body '" + n + "' has no columns " +
                                       (orientation ? n + ".qw," + n + ".qx," + n + ".qy," + n + ".qz"
                                                    : n + ".wx," + n + ".wy," + n + ".wz"));
    }
  }
}

}  // namespace

std::string DataSelection::name() const {
  if (orientations && rates) return "orientations+gyroscopes";
  return orientations ? "orientations" : "gyroscopes";
}

DataSelection selectData(const JointSamples& samples, DataUse use, const std::string& joint) {
  for (const BodySamples* b : {&samples.main, &samples.secondary})
    if ((b->hasOrientation() && b->orientation.size() != samples.time.size()) ||
        (b->hasAngularVelocity() && b->angular_velocity.size() != samples.time.size()))
      throw InvalidInput(samples.source, "body '" + b->name + "' has a different number of samples than t");
  DataSelection d;
  switch (use) {
    case DataUse::kAuto:
      d.orientations = samples.hasOrientations();
      d.rates = samples.hasAngularVelocities();
      if (!d.orientations && !d.rates)
        throw InvalidInput(samples.source, "a " + joint +
                                               " fit needs both bodies' orientations (B.qw,B.qx,B.qy,B.qz) or "
                                               "both bodies' angular velocities (B.wx,B.wy,B.wz); '" +
                                               samples.main.name + "' has " + has(samples.main) + ", '" +
                                               samples.secondary.name + "' has " + has(samples.secondary));
      return d;
    case DataUse::kOrientations: d.orientations = true; break;
    case DataUse::kAngularVelocities: d.rates = true; break;
    case DataUse::kBoth: d.orientations = d.rates = true; break;
  }
  if (d.orientations) requireGroup(samples, true, joint);
  if (d.rates) requireGroup(samples, false, joint);
  return d;
}

std::vector<Eigen::Matrix3d> relativeOrientations(const JointSamples& samples) {
  std::vector<Eigen::Matrix3d> R12(samples.main.orientation.size());
  for (std::size_t k = 0; k < R12.size(); ++k)
    R12[k] = (samples.main.orientation[k].inverse() * samples.secondary.orientation[k]).matrix();
  return R12;
}

std::vector<Eigen::Vector3d> relativeRates(const JointSamples& samples, const std::vector<Eigen::Matrix3d>& R12) {
  std::vector<Eigen::Vector3d> u(R12.size());
  for (std::size_t k = 0; k < u.size(); ++k)
    u[k] = R12[k] * samples.secondary.angular_velocity[k] - samples.main.angular_velocity[k];
  return u;
}

}  // namespace calibration
}  // namespace lieflow
