/// \file
/// MuJoCo beside lieflow on the same model (`lieflow study MODEL.xml
/// --with-mujoco`, issue 15): the MJCF compiled by MuJoCo's own compiler,
/// with what the import left out switched off the same way in MuJoCo
/// (mjcf_model.hpp: contacts, limits, actuators, friction loss, armature,
/// tendons, unrepresented equalities), started from the same state (qpos0
/// at rest, or the same keyframe) and stepped by MuJoCo's own integrators.
/// A run is measured with MuJoCo's own quantities: its energy (kinetic +
/// gravity + springs, mj_energyPos/mj_energyVel), the power its dashpots
/// dissipate Σ b q̇² (integrated over the steps by lieflow's DissipatedWork,
/// simulation/invariants.hpp, as lieflow's own runs are), and the angular momenta of its bodies about
/// the world origin and about their centre of mass from MuJoCo's body
/// velocities (mj_objectVelocity) and inertias.
///
/// Without MuJoCo in the build, mujocoPeerAvailable() says so and a peer
/// cannot be made.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "model/import/import_options.hpp"
#include "model/scene.hpp"

namespace lieflow {

/// MuJoCo's integrators as lieflow names them: "mujoco-euler" (MuJoCo's
/// semi-implicit Euler), "mujoco-rk4" (classical Runge–Kutta 4) and
/// "mujoco-implicit" (Euler implicit in the velocity-dependent forces).
const std::vector<std::string>& mujocoPeerIntegrators();

/// Whether this build has MuJoCo; if not, `why` says what to install.
bool mujocoPeerAvailable(std::string* why);

/// MuJoCo's version ("2.2.2"; empty without MuJoCo).
std::string mujocoPeerVersion();

/// One observed instant of a peer run (MuJoCo's quantities).
struct MujocoPeerSample {
  double t = 0.0;
  double energy = 0.0;
  double dissipated_work = 0.0;  ///< ∫ Σ b q̇² dt so far
  Eigen::Vector3d L = Eigen::Vector3d::Zero();      ///< about the world origin
  Eigen::Vector3d L_com = Eigen::Vector3d::Zero();  ///< about the centre of mass
};

struct MujocoPeerRun {
  long steps = 0;
  double wall_seconds = 0.0;  ///< the stepping alone when not observed
  bool failed = false;
  std::string failure;
  /// The scene's bodies at the end (scene order, matched by name):
  /// orientation and angular velocity in the body frame.
  std::vector<Eigen::Quaterniond> orientations;
  std::vector<Eigen::Vector3d> angular_velocities;
  /// Observed runs: every `every`-th step and the last (the first at t = 0).
  std::vector<MujocoPeerSample> samples;
  /// Observed runs: the largest relative drifts over every step, against
  /// the initial value (|E₀| for the energy and the energy balance).
  double energy_drift = 0.0, energy_balance_drift = 0.0, momentum_drift = 0.0, com_momentum_drift = 0.0;
};

class MujocoPeer {
 public:
  /// The MJCF `path` as lieflow imported it into `scene` with `options`
  /// (the same --ignore and --keyframe). Throws InvalidInput naming the file
  /// when it cannot be compiled, a scene body has no MuJoCo body of its
  /// name, or this build has no MuJoCo.
  MujocoPeer(const std::string& path, const ModelImportOptions& options, const SceneDescription& scene);
  ~MujocoPeer();
  MujocoPeer(MujocoPeer&&) noexcept;
  MujocoPeer& operator=(MujocoPeer&&) noexcept;

  /// Runs `integrator` (mujocoPeerIntegrators()) from the start for t_end at
  /// step h (round(t_end / h) steps). With `observe`, every step is
  /// measured (MuJoCo's forward pass again after each step) and samples
  /// kept every `every` steps; without it only the stepping is timed.
  /// `heartbeat` (may be empty) is called every 65536 steps and may throw.
  /// A non-finite state ends the run as failed, saying when. Runs set the
  /// compiled model's integrator and step: one run at a time per peer.
  MujocoPeerRun run(const std::string& integrator, double h, double t_end, bool observe, long every,
                    const std::function<void()>& heartbeat = {}) const;

  /// Where MuJoCo's model differs from the file as lieflow reads it (a URDF
  /// inertia MuJoCo's compiler had to balance), for the comparison's record.
  const std::vector<std::string>& notes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lieflow
