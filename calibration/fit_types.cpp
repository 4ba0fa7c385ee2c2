#include "calibration/fit_types.hpp"

#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {

const char* robustLossName(RobustLoss loss) {
  switch (loss) {
    case RobustLoss::kHuber: return "huber";
    case RobustLoss::kCauchy: return "cauchy";
    case RobustLoss::kNone: break;
  }
  return "none";
}

RobustLoss parseRobustLoss(const std::string& text, const std::string& field) {
  for (RobustLoss loss : {RobustLoss::kNone, RobustLoss::kHuber, RobustLoss::kCauchy})
    if (text == robustLossName(loss)) return loss;
  throw InvalidInput(field, "unknown robust loss '" + text + "' (none, huber, cauchy)");
}

const char* dataUseName(DataUse use) {
  switch (use) {
    case DataUse::kAngularVelocities: return "gyroscopes";
    case DataUse::kOrientations: return "orientations";
    case DataUse::kBoth: return "both";
    case DataUse::kGyroscopesAccelerometers: return "gyroscopes+accelerometers";
    case DataUse::kAll: return "all";
    case DataUse::kAuto: break;
  }
  return "auto";
}

const char* hingeEstimatorName(HingeEstimator e) {
  switch (e) {
    case HingeEstimator::kConstraint: return "constraint";
    case HingeEstimator::kLikelihood: return "likelihood";
    case HingeEstimator::kAuto: break;
  }
  return "auto";
}

HingeEstimator parseHingeEstimator(const std::string& text, const std::string& field) {
  for (HingeEstimator e : {HingeEstimator::kAuto, HingeEstimator::kConstraint, HingeEstimator::kLikelihood})
    if (text == hingeEstimatorName(e)) return e;
  throw InvalidInput(field, "unknown estimator '" + text + "' (auto, constraint, likelihood)");
}

DataUse parseDataUse(const std::string& text, const std::string& field) {
  for (DataUse use : {DataUse::kAuto, DataUse::kAngularVelocities, DataUse::kOrientations, DataUse::kBoth,
                      DataUse::kGyroscopesAccelerometers, DataUse::kAll})
    if (text == dataUseName(use)) return use;
  throw InvalidInput(field, "unknown data selection '" + text +
                                "' (auto, gyroscopes, orientations, both, gyroscopes+accelerometers, all)");
}

}  // namespace calibration
}  // namespace lieflow
