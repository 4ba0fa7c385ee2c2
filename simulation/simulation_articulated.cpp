/// \file
/// Running a scene in joint coordinates (--formulation joint): the table of
/// steppers' joint columns, instantiated here apart from the single-body and
/// maximal ones (simulation.cpp) to keep each translation unit's build short.
#include <stdexcept>

#include "simulation/simulation_model.hpp"
#include "simulation/stepper_table_rows.hpp"

namespace lieflow {

SimulationResult runArticulated(const Simulation::Model& model, SystemKind kind, const SimulationOptions& o,
                                const std::vector<std::string>& columns,
                                const std::function<void(const std::vector<double>&)>& row) {
  using namespace stepper_table;
  const articulated::ArticulatedSystem& system = *model.articulated->system;
  const articulated::ArticulatedState& y0 = model.articulated->y0;
  switch (kind) {
    case SystemKind::kJointTree: return runStepper(JointTree{}, model, system, y0, o, columns, row);
    case SystemKind::kJointCoupled: return runStepper(JointCoupled{}, model, system, y0, o, columns, row);
    case SystemKind::kJointLoops: return runStepper(JointLoops{}, model, system, y0, o, columns, row);
    case SystemKind::kSingleBody:
    case SystemKind::kMaximal: break;
  }
  throw std::logic_error("runArticulated: the scene's column is not one of joint coordinates");
}

}  // namespace lieflow
