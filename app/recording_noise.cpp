#include "app/recording_noise.hpp"

#include "liegroup/so3.hpp"

namespace lieflow {
namespace app {

namespace {
bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}
}  // namespace

RecordingNoise::RecordingNoise(const std::vector<std::string>& columns, const NoiseOptions& options)
    : options_(options), gen_(options.seed) {
  for (int i = 0; i < static_cast<int>(columns.size()); ++i) {
    const std::string& c = columns[i];
    if (endsWith(c, ".wx") || endsWith(c, ".wy") || endsWith(c, ".wz")) gyro_.push_back(i);
    if (endsWith(c, ".phi") || endsWith(c, ".phi1") || endsWith(c, ".phi2") || endsWith(c, ".phi3")) angle_.push_back(i);
    if (endsWith(c, ".qw") && i + 3 < static_cast<int>(columns.size())) quat_.push_back(i);
    if (endsWith(c, ".ax") || endsWith(c, ".ay") || endsWith(c, ".az")) acc_.push_back(i);
  }
  // The biases first, so that the rows' noise is the same with and without them.
  if (options_.gyro_bias > 0.0)
    for (std::size_t k = 0; k < gyro_.size(); ++k) bias_.push_back(options_.gyro_bias * normal_(gen_));
}

void RecordingNoise::apply(std::vector<double>* row) {
  std::vector<double>& r = *row;
  for (std::size_t k = 0; k < bias_.size(); ++k) r[gyro_[k]] += bias_[k];
  if (options_.gyro > 0.0)
    for (int i : gyro_) r[i] += options_.gyro * normal_(gen_);
  if (options_.acc > 0.0)
    for (int i : acc_) r[i] += options_.acc * normal_(gen_);
  if (options_.angle > 0.0)
    for (int i : angle_) r[i] += options_.angle * normal_(gen_);
  if (options_.quaternion > 0.0)
    for (int i : quat_) {
      Eigen::Vector3d d;
      for (int k = 0; k < 3; ++k) d[k] = options_.quaternion * normal_(gen_);
      const Eigen::Quaterniond q(r[i], r[i + 1], r[i + 2], r[i + 3]);
      Eigen::Quaterniond p = (SO3d(q.normalized()) * SO3d::exp(d)).quaternion();
      if (p.w() < 0.0) p.coeffs() = -p.coeffs();
      r[i] = p.w();
      r[i + 1] = p.x();
      r[i + 2] = p.y();
      r[i + 3] = p.z();
    }
}

}  // namespace app
}  // namespace lieflow
