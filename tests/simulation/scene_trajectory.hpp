/// \file
/// Scenes run through the public path (Simulation::run with a row callback,
/// the CSV contract's columns) for the tests of scenes with joints: the
/// trajectory with its columns by name, and small helpers to write scenes.
#pragma once

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "model/scene.hpp"
#include "simulation/simulation.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace scene_testing {

/// A run's output: the CSV columns and every row.
struct Trajectory {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  SimulationResult result;

  int col(const std::string& name) const {
    for (std::size_t i = 0; i < columns.size(); ++i)
      if (columns[i] == name) return static_cast<int>(i);
    ADD_FAILURE() << "no column '" << name << "'";
    return 0;
  }
  /// Value of column `name` in row r.
  double at(std::size_t r, const std::string& name) const { return rows[r][col(name)]; }
  /// A body's orientation in row r (columns B.qw … B.qz).
  Eigen::Quaterniond orientation(std::size_t r, const std::string& body) const {
    return Eigen::Quaterniond(at(r, body + ".qw"), at(r, body + ".qx"), at(r, body + ".qy"), at(r, body + ".qz"));
  }
  Eigen::Vector3d omega(std::size_t r, const std::string& body) const {
    return Eigen::Vector3d(at(r, body + ".wx"), at(r, body + ".wy"), at(r, body + ".wz"));
  }
};

/// The options of a run of `integrator` in `formulation` ("" for the default).
inline SimulationOptions runOptions(const std::string& integrator, const std::string& formulation, double dt,
                                    double t_end) {
  SimulationOptions o;
  o.integrator = integrator;
  o.formulation = formulation;
  o.dt = dt;
  o.t_end = t_end;
  return o;
}

/// Every `every`-th row of a run in `formulation` ("" for the default).
inline Trajectory simulate(const SceneDescription& scene, const std::string& integrator, double dt, double t_end,
                           int every = 1, const std::string& formulation = "") {
  const Simulation sim(scene);
  SimulationOptions o = runOptions(integrator, formulation, dt, t_end);
  o.every = every;
  Trajectory out;
  out.columns = sim.columns();
  out.result = sim.run(o, [&](const std::vector<double>& row) { out.rows.push_back(row); });
  EXPECT_FALSE(out.result.failed) << out.result.failure;
  EXPECT_FALSE(out.rows.empty());
  EXPECT_NEAR(out.rows.back()[0], t_end, 1e-12);
  return out;
}

/// The ends of a run in a formulation ("maximal", "joint" or "" for the
/// default): its columns, first and last rows and summary (not checked here:
/// tests of failures read `result`).
struct RunEnds {
  std::vector<std::string> columns;
  std::vector<double> first, last;
  SimulationResult result;
};

inline RunEnds runEnds(const Simulation& sim, const std::string& formulation, const std::string& integrator,
                       double dt, double t_end) {
  const SimulationOptions o = runOptions(integrator, formulation, dt, t_end);
  RunEnds r;
  r.columns = sim.columns();
  r.result = sim.run(o, [&](const std::vector<double>& row) {
    if (r.first.empty()) r.first = row;
    r.last = row;
  });
  return r;
}

inline std::string num(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

/// Replaces the first occurrence of `from` in `text` by `to` (the fragment must occur).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "'" << from << "' not in the scene";
  if (pos == std::string::npos) return text;
  return text.replace(pos, from.size(), to);
}

/// The message of the InvalidInput that parseScene + the Simulation
/// constructor throw for `json` read as "joints.json" (empty, with a test
/// failure, if accepted).
inline std::string rejection(const std::string& json) {
  try {
    const Simulation sim(parseScene(json, "joints.json"));
    ADD_FAILURE() << "accepted: " << json;
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

}  // namespace scene_testing
}  // namespace lieflow
