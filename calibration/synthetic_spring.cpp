#include "calibration/synthetic_spring.hpp"

#include <random>
#include <vector>

#include "simulation/simulation.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {

const char* const kSpringUniversalSceneJson = R"({
  "name": "spring-universal", "gravity": [0, 0, -9.81],
  "bodies": [{"name": "pod", "mass": 1.5, "inertia": [0.05, 0.04, 0.02], "position": [0, 0, -0.25]}],
  "joints": [{"name": "cross", "type": "universal", "main": "ground", "secondary": "pod",
              "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0.25],
              "axis1_main": [1, 0, 0], "axis2_secondary": [0, 1, 0], "initial_angles": [0.4, -0.5],
              "spring1": {"stiffness": 6.0}, "damper1": {"damping": 0.05},
              "spring2": {"stiffness": 10.0, "rest_angle": 0.1}, "damper2": {"damping": 0.08}}]})";

SpringData simulatedJointAngles(const SceneDescription& scene, const std::string& joint, int coordinates,
                                double t_end) {
  const Simulation sim(scene);
  const std::vector<std::string> columns = sim.columns();
  SpringData d;
  d.source = scene.source;
  std::vector<int> cols;
  for (int i = 0; i < coordinates; ++i) {
    d.column[i] = joint + (coordinates == 1 ? ".phi" : (i == 0 ? ".phi1" : ".phi2"));
    for (std::size_t c = 0; c < columns.size(); ++c)
      if (columns[c] == d.column[i]) cols.push_back(static_cast<int>(c));
  }
  if (static_cast<int>(cols.size()) != coordinates)
    throw InvalidInput(scene.source, "no angle column " + d.column[cols.size()] + " in the trajectory");
  SimulationOptions o;
  o.integrator = "rkmk4";
  o.dt = 1e-3;
  o.t_end = t_end;
  o.every = 10;
  sim.run(o, [&](const std::vector<double>& row) {
    d.time.push_back(row[0]);
    for (int i = 0; i < coordinates; ++i) d.angle[i].push_back(row[cols[i]]);
  });
  return d;
}

SpringData withAngleNoise(SpringData data, double sigma, unsigned seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> normal(0.0, sigma);
  for (auto& a : data.angle)
    for (double& x : a) x += normal(gen);
  return data;
}

}  // namespace calibration
}  // namespace lieflow
