/// \file
/// MuJoCo peer of the benchmark free body (see mujoco_peer.hpp).
#include "bench/integrators/mujoco_peer.hpp"

#include <cstdio>
#include <cstring>
#include <stdexcept>

#ifdef LIEFLOW_HAVE_MUJOCO
#include <mujoco/mujoco.h>

#include "model/import/mjcf_model.hpp"
#endif

namespace lieflow {
namespace bench {

#ifdef LIEFLOW_HAVE_MUJOCO

bool mujocoAvailable() { return true; }

std::string mujocoDescription() {
  return std::string("MuJoCo ") + mj_versionString() + " (header " +
         std::to_string(mjVERSION_HEADER) + ")";
}

namespace {

/// The free body as MJCF. %.17g round-trips every double. No geom: the body
/// has its inertia from <inertial>, and nothing to collide.
std::string modelXml(const FreeBodyScene& s, MujocoFreeBody::Integrator integrator, double h) {
  const Eigen::Quaterniond& a = s.principal_axes;
  char buf[2048];
  std::snprintf(buf, sizeof buf,
                "<mujoco model=\"lieflow-free-body\">\n"
                "  <option timestep=\"%.17g\" gravity=\"0 0 0\" integrator=\"%s\">\n"
                "    <flag contact=\"disable\"/>\n"
                "  </option>\n"
                "  <worldbody>\n"
                "    <body name=\"body\" pos=\"0 0 0\">\n"
                "      <joint name=\"free\" type=\"free\"/>\n"
                "      <inertial pos=\"0 0 0\" mass=\"%.17g\" diaginertia=\"%.17g %.17g %.17g\"\n"
                "                quat=\"%.17g %.17g %.17g %.17g\"/>\n"
                "    </body>\n"
                "  </worldbody>\n"
                "</mujoco>\n",
                h, integrator == MujocoFreeBody::Integrator::kRk4 ? "RK4" : "Euler", s.mass,
                s.principal_moments.x(), s.principal_moments.y(), s.principal_moments.z(), a.w(),
                a.x(), a.y(), a.z());
  return buf;
}

}  // namespace

struct MujocoFreeBody::Impl {
  FreeBodyScene scene;
  std::string xml;
  model_import::MjcfModel model;
  model_import::MjcfData data;
  mjModel* m = nullptr;  // model.get()
  mjData* d = nullptr;   // data.get()
};

MujocoFreeBody::MujocoFreeBody(const FreeBodyScene& scene, Integrator integrator, double h)
    : impl_(new Impl) {
  impl_->scene = scene;
  impl_->xml = modelXml(scene, integrator, h);
  impl_->model = model_import::compileModelText("lieflow_free_body.xml", impl_->xml, "MuJoCo free body");
  impl_->m = impl_->model.get();
  if (impl_->m->nq != 7 || impl_->m->nv != 6)
    throw std::runtime_error("MuJoCo: expected one free joint (nq = 7, nv = 6)");
  impl_->data = model_import::makeMjcfData(impl_->m, "MuJoCo free body");
  impl_->d = impl_->data.get();
  reset();
}

MujocoFreeBody::~MujocoFreeBody() = default;

const std::string& MujocoFreeBody::xml() const { return impl_->xml; }

void MujocoFreeBody::reset() {
  const FreeBodyScene& s = impl_->scene;
  mj_resetData(impl_->m, impl_->d);
  mjtNum* qpos = impl_->d->qpos;
  mjtNum* qvel = impl_->d->qvel;
  qpos[0] = s.p0.x();
  qpos[1] = s.p0.y();
  qpos[2] = s.p0.z();
  qpos[3] = s.q0.w();
  qpos[4] = s.q0.x();
  qpos[5] = s.q0.y();
  qpos[6] = s.q0.z();
  // Free joint: linear velocity in the world frame, angular in the body frame.
  qvel[0] = s.v0_world.x();
  qvel[1] = s.v0_world.y();
  qvel[2] = s.v0_world.z();
  qvel[3] = s.omega0_body.x();
  qvel[4] = s.omega0_body.y();
  qvel[5] = s.omega0_body.z();
  impl_->d->time = 0.0;
}

void MujocoFreeBody::step() { mj_step(impl_->m, impl_->d); }

void MujocoFreeBody::steps(long n) {
  const mjModel* m = impl_->m;
  mjData* d = impl_->d;
  for (long i = 0; i < n; ++i) mj_step(m, d);
}

Eigen::Quaterniond MujocoFreeBody::orientation() const {
  const mjtNum* q = impl_->d->qpos + 3;
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
}
Eigen::Vector3d MujocoFreeBody::position() const {
  const mjtNum* p = impl_->d->qpos;
  return Eigen::Vector3d(p[0], p[1], p[2]);
}
Eigen::Vector3d MujocoFreeBody::angularVelocityBody() const {
  const mjtNum* w = impl_->d->qvel + 3;
  return Eigen::Vector3d(w[0], w[1], w[2]);
}
Eigen::Vector3d MujocoFreeBody::velocityWorld() const {
  const mjtNum* v = impl_->d->qvel;
  return Eigen::Vector3d(v[0], v[1], v[2]);
}
double MujocoFreeBody::time() const { return impl_->d->time; }

#else  // !LIEFLOW_HAVE_MUJOCO

bool mujocoAvailable() { return false; }

std::string mujocoDescription() {
  return "MuJoCo not built in (CMake found no mujoco/mujoco.h and libmujoco, or "
         "LIEFLOW_BENCH_WITH_MUJOCO=OFF; apt-get install libmujoco-dev and re-run CMake)";
}

struct MujocoFreeBody::Impl {};

MujocoFreeBody::MujocoFreeBody(const FreeBodyScene&, Integrator, double) {
  throw std::runtime_error(mujocoDescription());
}
MujocoFreeBody::~MujocoFreeBody() = default;
const std::string& MujocoFreeBody::xml() const {
  static const std::string empty;
  return empty;
}
void MujocoFreeBody::reset() {}
void MujocoFreeBody::step() {}
void MujocoFreeBody::steps(long) {}
Eigen::Quaterniond MujocoFreeBody::orientation() const { return Eigen::Quaterniond::Identity(); }
Eigen::Vector3d MujocoFreeBody::position() const { return Eigen::Vector3d::Zero(); }
Eigen::Vector3d MujocoFreeBody::angularVelocityBody() const { return Eigen::Vector3d::Zero(); }
Eigen::Vector3d MujocoFreeBody::velocityWorld() const { return Eigen::Vector3d::Zero(); }
double MujocoFreeBody::time() const { return 0.0; }

#endif

}  // namespace bench
}  // namespace lieflow
