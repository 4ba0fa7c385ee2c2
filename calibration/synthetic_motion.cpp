#include "calibration/synthetic_motion.hpp"

#include <cmath>

#include <Eigen/Geometry>

#include "calibration/unit_axis.hpp"
#include "liegroup/scalar.hpp"

namespace lieflow {
namespace calibration {
namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;

Eigen::Vector3d randomUnit(std::mt19937& gen) {
  std::normal_distribution<double> normal;
  Eigen::Vector3d v;
  do {
    v = Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
  } while (v.norm() < 1e-6);
  return v.normalized();
}

SineSum<Eigen::Vector3d> randomRotationAngles(std::mt19937& gen) {
  std::uniform_real_distribution<double> amplitude(-1.2, 1.2), frequency(0.3, 0.9), phase(0.0, kTwoPi);
  SineSum<Eigen::Vector3d> s;
  s.offset = Eigen::Vector3d(amplitude(gen), amplitude(gen), amplitude(gen));
  for (int k = 0; k < 3; ++k) {
    s.amplitude.emplace_back(amplitude(gen), amplitude(gen), amplitude(gen));
    s.frequency_hz.push_back(frequency(gen));
    s.phase.push_back(phase(gen));
  }
  return s;
}

SineSum<double> randomJointAngle(std::mt19937& gen) {
  std::uniform_real_distribution<double> amplitude(0.5, 1.0), frequency(0.2, 0.7), phase(0.0, kTwoPi);
  SineSum<double> s;
  s.offset = 0.0;
  for (int k = 0; k < 2; ++k) {
    s.amplitude.push_back(amplitude(gen));
    s.frequency_hz.push_back(frequency(gen));
    s.phase.push_back(phase(gen));
  }
  return s;
}

}  // namespace

template <typename V>
V SineSum<V>::value(double t) const {
  V x = offset;
  for (std::size_t k = 0; k < amplitude.size(); ++k)
    x += amplitude[k] * std::sin(kTwoPi * frequency_hz[k] * t + phase[k]);
  return x;
}

template <typename V>
V SineSum<V>::derivative(double t) const {
  V x = offset * 0.0;
  for (std::size_t k = 0; k < amplitude.size(); ++k)
    x += amplitude[k] * (kTwoPi * frequency_hz[k] * std::cos(kTwoPi * frequency_hz[k] * t + phase[k]));
  return x;
}

template <typename V>
V SineSum<V>::secondDerivative(double t) const {
  V x = offset * 0.0;
  for (std::size_t k = 0; k < amplitude.size(); ++k) {
    const double w = kTwoPi * frequency_hz[k];
    x -= amplitude[k] * (w * w * std::sin(w * t + phase[k]));
  }
  return x;
}

template struct SineSum<double>;
template struct SineSum<Eigen::Vector3d>;

SO3d SmoothRotation::orientation(double t) const { return SO3d::exp(angle.value(t)); }

Eigen::Vector3d SmoothRotation::bodyRate(double t) const {
  return SO3d::Jr(angle.value(t)) * angle.derivative(t);
}

TwoBodyState HingeMotion::at(double t) const {
  TwoBodyState s;
  s.R1 = main.orientation(t);
  s.w1 = main.bodyRate(t);
  const SO3d E = SO3d::exp(angle.value(t) * axis_main);
  s.R2 = s.R1 * E * mount;
  s.w2 = mount.inverse() * (E.inverse() * s.w1) + angle.derivative(t) * axisSecondary();
  return s;
}

TwoBodyState UniversalMotion::at(double t) const {
  TwoBodyState s;
  s.R1 = main.orientation(t);
  s.w1 = main.bodyRate(t);
  const SO3d E1 = SO3d::exp(angle1.value(t) * axis1_main);
  const SO3d E2 = SO3d::exp(angle2.value(t) * axis2_secondary);
  s.R2 = s.R1 * E1 * mount * E2;
  s.w2 = E2.inverse() * (mount.inverse() * (E1.inverse() * (s.w1 + angle1.derivative(t) * axis1_main))) +
         angle2.derivative(t) * axis2_secondary;
  return s;
}

void JointMotion::specificForces(double t, Eigen::Vector3d* f1, Eigen::Vector3d* f2) const {
  // ω̇ ≈ (ω(t−2h) − 8ω(t−h) + 8ω(t+h) − ω(t+2h)) / 12h.
  const double h = kRateDerivativeStep;
  const TwoBodyState m2 = at(t - 2.0 * h), m1 = at(t - h), p1 = at(t + h), p2 = at(t + 2.0 * h);
  const Eigen::Vector3d dw1 = (m2.w1 - 8.0 * m1.w1 + 8.0 * p1.w1 - p2.w1) / (12.0 * h);
  const Eigen::Vector3d dw2 = (m2.w2 - 8.0 * m1.w2 + 8.0 * p1.w2 - p2.w2) / (12.0 * h);
  const TwoBodyState s = at(t);
  const Eigen::Vector3d free_fall = sensors.centre.secondDerivative(t) - sensors.gravity;  // p̈ − g
  const Eigen::Vector3d& o1 = sensors.anchor_main;
  const Eigen::Vector3d& o2 = sensors.anchor_secondary;
  *f1 = s.R1.inverse() * free_fall - dw1.cross(o1) - s.w1.cross(s.w1.cross(o1));
  *f2 = s.R2.inverse() * free_fall - dw2.cross(o2) - s.w2.cross(s.w2.cross(o2));
}

SensorGeometry randomSensorGeometry(std::mt19937& gen) {
  std::uniform_real_distribution<double> distance(0.05, 0.25), swing(-0.05, 0.05), frequency(0.5, 1.5),
      phase(0.0, kTwoPi);
  SensorGeometry g;
  g.anchor_main = distance(gen) * randomUnit(gen);
  g.anchor_secondary = distance(gen) * randomUnit(gen);
  for (int k = 0; k < 2; ++k) {
    g.centre.amplitude.emplace_back(swing(gen), swing(gen), swing(gen));
    g.centre.frequency_hz.push_back(frequency(gen));
    g.centre.phase.push_back(phase(gen));
  }
  return g;
}

HingeMotion kneeLikeHingeMotion(std::mt19937& gen, double wobble) {
  std::uniform_real_distribution<double> swing(-0.6, 0.6), small(-1.0, 1.0), frequency(0.4, 1.2),
      phase(0.0, kTwoPi);
  HingeMotion m;
  const Eigen::Vector3d u = randomUnit(gen);
  const Eigen::Vector3d e1 = orthogonalUnit(u), e2 = u.cross(e1);
  m.axis_main = u;  // R₁ u = u while the main body turns about u: the world axis is u
  m.main.angle.offset = Eigen::Vector3d::Zero();
  for (int k = 0; k < 2; ++k) {
    m.main.angle.amplitude.push_back(swing(gen) * u + wobble * (small(gen) * e1 + small(gen) * e2));
    m.main.angle.frequency_hz.push_back(frequency(gen));
    m.main.angle.phase.push_back(phase(gen));
  }
  m.angle.offset = 0.0;
  for (int k = 0; k < 2; ++k) {
    m.angle.amplitude.push_back(swing(gen));
    m.angle.frequency_hz.push_back(frequency(gen));
    m.angle.phase.push_back(phase(gen));
  }
  m.mount = SO3d::random(gen);
  m.sensors = randomSensorGeometry(gen);
  // Sagittal: the centre moves and gravity points perpendicular to the axis.
  for (Eigen::Vector3d& a : m.sensors.centre.amplitude) a -= a.dot(u) * u;
  const double down = phase(gen);
  m.sensors.gravity = -9.81 * (std::cos(down) * e1 + std::sin(down) * e2);
  return m;
}

HingeMotion randomHingeMotion(std::mt19937& gen) {
  HingeMotion m;
  m.main.angle = randomRotationAngles(gen);
  m.angle = randomJointAngle(gen);
  m.axis_main = randomUnit(gen);
  m.mount = SO3d::random(gen);
  return m;
}

UniversalMotion randomUniversalMotion(std::mt19937& gen) {
  UniversalMotion m;
  m.main.angle = randomRotationAngles(gen);
  m.angle1 = randomJointAngle(gen);
  m.angle2 = randomJointAngle(gen);
  m.axis1_main = randomUnit(gen);
  m.axis2_secondary = randomUnit(gen);
  // C takes a₂ to a direction u ⟂ a₁, then turns about u.
  std::uniform_real_distribution<double> angle(-3.14159, 3.14159);
  const Eigen::Vector3d e = orthogonalUnit(m.axis1_main);
  const Eigen::Vector3d u = SO3d::exp(angle(gen) * m.axis1_main) * e;
  const SO3d align(Eigen::Quaterniond::FromTwoVectors(m.axis2_secondary, u));
  m.mount = SO3d::exp(angle(gen) * u) * align;
  return m;
}

HingeTruthSamples hingeTruth(const HingeMotion& motion, int n, double rate_hz) {
  HingeTruthSamples t;
  for (int k = 0; k < n; ++k) {
    const double time = k / rate_hz;
    t.time.push_back(time);
    t.main_rate.push_back(motion.main.bodyRate(time));
    t.angle.push_back(motion.angle.value(time));
  }
  t.axis_main = motion.axis_main;
  t.mount = motion.mount;
  return t;
}

JointSamples recordMotion(const JointMotion& motion, int n, double rate_hz, const RecordingNoise& noise,
                          std::mt19937& gen) {
  std::normal_distribution<double> normal;
  auto gaussian = [&](double sigma) {
    return Eigen::Vector3d(sigma * normal(gen), sigma * normal(gen), sigma * normal(gen));
  };
  JointSamples out;
  out.source = "synthetic";
  out.main.name = "main";
  out.secondary.name = "secondary";
  // RecordingNoise::wobble_rate: axis, frequency and phase per body (drawn
  // only when asked for, so that other recordings keep their random stream).
  Eigen::Vector3d wobble_axis[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  double wobble_hz[2] = {0.0, 0.0}, wobble_phase[2] = {0.0, 0.0};
  if (noise.wobble_rate > 0.0) {
    std::uniform_real_distribution<double> frequency(noise.wobble_min_hz, noise.wobble_max_hz),
        phase(0.0, 2.0 * kPi);
    for (int b = 0; b < 2; ++b) {
      wobble_axis[b] = gaussian(1.0).normalized();
      wobble_hz[b] = frequency(gen);
      wobble_phase[b] = phase(gen);
    }
  }
  const auto wobble = [&](int b, double t) -> Eigen::Vector3d {
    return noise.wobble_rate * std::sin(2.0 * kPi * wobble_hz[b] * t + wobble_phase[b]) * wobble_axis[b];
  };
  for (int k = 0; k < n; ++k) {
    const double t = k / rate_hz;
    const TwoBodyState s = motion.at(t);
    out.time.push_back(t);
    // The secondary sensor's own clock (RecordingNoise::secondary_clock_offset).
    const TwoBodyState late = noise.secondary_clock_offset != 0.0 ? motion.at(t + noise.secondary_clock_offset) : s;
    if (noise.orientations) {
      out.main.orientation.push_back((s.R1 * SO3d::exp(gaussian(noise.orientation_sigma))).normalized());
      out.secondary.orientation.push_back((late.R2 * SO3d::exp(gaussian(noise.orientation_sigma))).normalized());
    }
    if (noise.rates) {
      out.main.angular_velocity.push_back(s.w1 + noise.gyro_bias_main + wobble(0, t) + gaussian(noise.rate_sigma));
      out.secondary.angular_velocity.push_back(late.w2 + noise.gyro_bias_secondary + wobble(1, t) +
                                               gaussian(noise.rate_sigma));
    }
    if (noise.accelerometers) {
      Eigen::Vector3d f1, f2, unused;
      motion.specificForces(t, &f1, &f2);
      if (noise.secondary_clock_offset != 0.0) motion.specificForces(t + noise.secondary_clock_offset, &unused, &f2);
      out.main.specific_force.push_back(f1 + gaussian(noise.acc_sigma));
      out.secondary.specific_force.push_back(f2 + gaussian(noise.acc_sigma));
    }
  }
  return out;
}

}  // namespace calibration
}  // namespace lieflow
