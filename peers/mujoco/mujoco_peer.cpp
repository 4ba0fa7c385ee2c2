// MuJoCo beside lieflow on the same MJCF model (mujoco_peer.hpp).
#include "peers/mujoco/mujoco_peer.hpp"

#include "liegroup/invalid_input.hpp"

#ifdef LIEFLOW_HAVE_MUJOCO
#include <mujoco/mujoco.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

#include "integrators/integrate.hpp"
#include "model/import/mjcf_model.hpp"
#include "model/import/model_import.hpp"
#include "simulation/invariants.hpp"
#include "peers/mujoco/mujoco_model.hpp"
#include "simulation/progress_pacer.hpp"
#endif

namespace lieflow {

const std::vector<std::string>& mujocoPeerIntegrators() {
  static const std::vector<std::string> kNames = {"mujoco-euler", "mujoco-rk4", "mujoco-implicit"};
  return kNames;
}

#ifndef LIEFLOW_HAVE_MUJOCO

std::string mujocoPeerVersion() { return ""; }

bool mujocoPeerAvailable(std::string* why) {
  if (why) *why = "this build has no MuJoCo (install Debian's libmujoco-dev and rebuild lieflow)";
  return false;
}

struct MujocoPeer::Impl {};

MujocoPeer::MujocoPeer(const std::string&, const ModelImportOptions&, const SceneDescription&) {
  std::string why;
  mujocoPeerAvailable(&why);
  throw InvalidInput("`with_mujoco`", why);
}

const std::vector<std::string>& MujocoPeer::notes() const {
  static const std::vector<std::string> kNone;
  return kNone;
}

MujocoPeerRun MujocoPeer::run(const std::string&, double, double, bool, long, const std::function<void()>&) const {
  return {};
}

#else

namespace {

using model_import::mjMat3;
using model_import::mjVec3;

/// MuJoCo's quantities at d, after mj_forward: energy, dashpot power,
/// angular momenta (about the origin and about the centre of mass) from the
/// bodies' velocities at their centres and their inertias (body_inertia is
/// diagonal in the body's inertial frame ximat).
struct Measured {
  double energy = 0.0, power = 0.0;
  Eigen::Vector3d L = Eigen::Vector3d::Zero(), L_com = Eigen::Vector3d::Zero();
};

/// The turn of --spin (free_tree_spin.hpp) on MuJoCo's free roots: each
/// tree turning rigidly at ω (world) about its centre of mass, subtree_com of
/// its root, with the joints' rates unchanged: the free joint's qvel gains
/// ω × (x − c) (the linear velocity of the body's origin, world axes) and
/// Rᵀ ω (the angular velocity, body axes).
void addSpin(const mjModel* m, mjData* d, const Eigen::Vector3d& omega) {
  mj_kinematics(m, d);
  mj_comPos(m, d);
  for (int j = 0; j < m->njnt; ++j) {
    const int b = m->jnt_bodyid[j];
    if (m->jnt_type[j] != mjJNT_FREE || m->body_parentid[b] != 0) continue;
    const Eigen::Vector3d linear = omega.cross(mjVec3(d->xpos + 3 * b) - mjVec3(d->subtree_com + 3 * b));
    const Eigen::Vector3d angular = mjMat3(d->xmat + 9 * b).transpose() * omega;
    mjtNum* v = d->qvel + m->jnt_dofadr[j];
    for (int i = 0; i < 3; ++i) {
      v[i] += linear[i];
      v[3 + i] += angular[i];
    }
  }
}

Measured measure(const mjModel* m, mjData* d) {
  Measured out;
  mj_energyPos(m, d);
  mj_energyVel(m, d);
  out.energy = d->energy[0] + d->energy[1];
  for (int i = 0; i < m->nv; ++i) out.power += m->dof_damping[i] * d->qvel[i] * d->qvel[i];
  // Each body's centre and velocity, then the momenta about the origin and,
  // from differences to the centre (not as L − c × M v_c, which loses the
  // digits of L_com once the body has fallen far), about the centre.
  const int n = m->nbody - 1;
  std::vector<Eigen::Vector3d> c(n), v(n);
  double mass = 0.0;
  Eigen::Vector3d mc = Eigen::Vector3d::Zero(), mv = Eigen::Vector3d::Zero(), spin = Eigen::Vector3d::Zero();
  for (int b = 1; b < m->nbody; ++b) {
    mjtNum velocity[6];  // (ω, v at the centre of mass), world
    mj_objectVelocity(m, d, mjOBJ_BODY, b, velocity, 0);
    const double mb = m->body_mass[b];
    c[b - 1] = mjVec3(d->xipos + 3 * b);
    v[b - 1] = mjVec3(velocity + 3);
    const Eigen::Matrix3d Ri = mjMat3(d->ximat + 9 * b);
    spin += Ri * mjVec3(m->body_inertia + 3 * b).asDiagonal() * Ri.transpose() * mjVec3(velocity);
    mass += mb;
    mc += mb * c[b - 1];
    mv += mb * v[b - 1];
  }
  const Eigen::Vector3d centre = mass > 0.0 ? Eigen::Vector3d(mc / mass) : Eigen::Vector3d::Zero();
  const Eigen::Vector3d vc = mass > 0.0 ? Eigen::Vector3d(mv / mass) : Eigen::Vector3d::Zero();
  out.L = out.L_com = spin;
  for (int b = 1; b < m->nbody; ++b) {
    const double mb = m->body_mass[b];
    out.L += c[b - 1].cross(mb * v[b - 1]);
    out.L_com += (c[b - 1] - centre).cross(mb * (v[b - 1] - vc));
  }
  return out;
}

/// The first non-finite number of the state, or an empty string.
std::string nonFinite(const mjModel* m, const mjData* d) {
  for (int i = 0; i < m->nq; ++i)
    if (!std::isfinite(d->qpos[i])) return "qpos[" + std::to_string(i) + "]";
  for (int i = 0; i < m->nv; ++i)
    if (!std::isfinite(d->qvel[i])) return "qvel[" + std::to_string(i) + "]";
  return "";
}

}  // namespace

bool mujocoPeerAvailable(std::string*) { return true; }

std::string mujocoPeerVersion() { return mj_versionString(); }

struct MujocoPeer::Impl {
  std::string path;
  std::vector<std::string> notes;
  model_import::MjcfModel model;
  int key = -1;
  bool has_spin = false;
  Eigen::Vector3d spin = Eigen::Vector3d::Zero();
  std::vector<int> bodies;  ///< MuJoCo body of each scene body
};

MujocoPeer::MujocoPeer(const std::string& path, const ModelImportOptions& options, const SceneDescription& scene)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->model = isUrdfFile(path) ? mujoco_peer::compileUrdfForMujoco(path, options, &impl_->notes)
                                  : model_import::compileMjcf(path);
  mjModel* m = impl_->model.get();
  mujoco_peer::switchOffIgnored(m, options);
  impl_->key = model_import::keyframeIndex(m, path, options.keyframe);
  impl_->has_spin = options.has_spin;
  impl_->spin = Eigen::Vector3d(options.spin[0], options.spin[1], options.spin[2]);
  // Scene bodies by the names the importer gave MuJoCo's bodies (unnamed
  // ones included: mjcfBodyName).
  std::map<std::string, int> by_name;
  for (int b = 1; b < m->nbody; ++b) by_name.emplace(model_import::mjcfBodyName(m, b), b);
  for (const BodyDescription& b : scene.bodies) {
    const auto found = by_name.find(b.name);
    const int id = found == by_name.end() ? -1 : found->second;
    if (id <= 0)
      throw InvalidInput(path + ": `with_mujoco`", "the scene's body '" + b.name +
                                                       "' is not a MuJoCo body of this model (was the scene "
                                                       "imported from it?)");
    impl_->bodies.push_back(id);
  }
}

const std::vector<std::string>& MujocoPeer::notes() const { return impl_->notes; }

MujocoPeerRun MujocoPeer::run(const std::string& integrator, double h, double t_end, bool observe, long every,
                              const std::function<void()>& heartbeat) const {
  const std::vector<std::string>& names = mujocoPeerIntegrators();
  const auto it = std::find(names.begin(), names.end(), integrator);
  if (it == names.end()) throw InvalidInput("`integrators`", "'" + integrator + "' is not a MuJoCo integrator");
  if (!(h > 0.0) || !(t_end > 0.0)) throw InvalidInput("`dt`", "a MuJoCo run needs a positive step and end time");
  // MuJoCo's warnings kept off stdout and out of MUJOCO_LOG.TXT (a bad
  // state is found below from d->warning); its errors throw MujocoError, a
  // failed computation for the caller.
  const model_import::MujocoMessageGuard guard;
  mjModel* m = impl_->model.get();
  static constexpr int kIntegrator[] = {mjINT_EULER, mjINT_RK4, mjINT_IMPLICIT};
  m->opt.integrator = kIntegrator[it - names.begin()];
  m->opt.timestep = h;
  // MuJoCo computes its energy only when asked (and then in every step).
  if (observe)
    m->opt.enableflags |= mjENBL_ENERGY;
  else
    m->opt.enableflags &= ~mjENBL_ENERGY;
  const model_import::MjcfData d = model_import::makeMjcfData(m, impl_->path);
  if (impl_->key >= 0)
    mj_resetDataKeyframe(m, d.get(), impl_->key);
  else
    mj_resetData(m, d.get());
  if (impl_->has_spin) addSpin(m, d.get(), impl_->spin);
  d->time = 0.0;

  MujocoPeerRun run;
  // The steps lieflow takes (integrate.hpp): the last one shortened to land
  // on t_end when t_end is not a multiple of h, so both engines are compared
  // at the same time.
  const long steps = std::max(1L, stepCount(0.0, t_end, h));
  const auto time_at = [&](long k) { return k == steps ? t_end : static_cast<double>(k) * h; };
  every = std::max(1L, every);
  Measured first;
  DissipatedWork dissipated;
  const auto sample = [&](long k) {
    mj_forward(m, d.get());
    const Measured now = measure(m, d.get());
    if (k == 0) first = now;
    dissipated.add(time_at(k), now.power);
    const double work = dissipated.value();
    const double scale = std::abs(first.energy);
    run.energy_drift = std::max(run.energy_drift, relativeDrift(std::abs(now.energy - first.energy), scale));
    run.energy_balance_drift =
        std::max(run.energy_balance_drift, relativeDrift(std::abs(now.energy + work - first.energy), scale));
    run.momentum_drift = std::max(run.momentum_drift, relativeDrift((now.L - first.L).norm(), first.L.norm()));
    run.com_momentum_drift =
        std::max(run.com_momentum_drift, relativeDrift((now.L_com - first.L_com).norm(), first.L_com.norm()));
    if (k % every == 0 || k == steps) run.samples.push_back({time_at(k), now.energy, work, now.L, now.L_com});
  };
  const auto failed = [&](long k) {
    std::string what = nonFinite(m, d.get());
    if (what.empty() && d->warning[mjWARN_BADQACC].number == 0) return false;
    std::ostringstream why;
    if (!what.empty())
      why << "MuJoCo's state " << what << " became non-finite";
    else
      why << "MuJoCo found a bad acceleration and reset the simulation";
    why << " by t = " << time_at(k) << " (step " << k << ")";
    run.failed = true;
    run.failure = why.str();
    return true;
  };

  if (observe) sample(0);
  ProgressPacer pacer;
  const auto start = std::chrono::steady_clock::now();
  long k = 0;
  while (k < steps) {
    if (k + 1 == steps) m->opt.timestep = t_end - static_cast<double>(k) * h;  // h unless shortened
    mj_step(m, d.get());
    ++k;
    if (heartbeat && pacer.due(k)) heartbeat();
    if (observe) {
      if (failed(k)) break;
      sample(k);
    }
  }
  const auto stop = std::chrono::steady_clock::now();
  run.steps = k;
  run.wall_seconds = std::chrono::duration<double>(stop - start).count();
  if (!observe) failed(k);
  if (run.failed) return run;
  mj_kinematics(m, d.get());
  mj_comPos(m, d.get());
  mj_comVel(m, d.get());
  for (int b : impl_->bodies) {
    const Eigen::Quaterniond q(d->xquat[4 * b], d->xquat[4 * b + 1], d->xquat[4 * b + 2], d->xquat[4 * b + 3]);
    mjtNum velocity[6];
    mj_objectVelocity(m, d.get(), mjOBJ_XBODY, b, velocity, 1);  // in the body frame
    run.orientations.push_back(q);
    run.angular_velocities.push_back(mjVec3(velocity));
  }
  return run;
}

#endif

MujocoPeer::~MujocoPeer() = default;
MujocoPeer::MujocoPeer(MujocoPeer&&) noexcept = default;
MujocoPeer& MujocoPeer::operator=(MujocoPeer&&) noexcept = default;

}  // namespace lieflow
