// What the import leaves out, switched off in MuJoCo (mujoco_model.hpp).
#include "peers/mujoco/mujoco_model.hpp"

#ifdef LIEFLOW_HAVE_MUJOCO
#include <mujoco/mujoco.h>

namespace lieflow {
namespace mujoco_peer {

void switchOffIgnored(mjModel* m, const ModelImportOptions& options) {
  if (options.ignores("contacts")) m->opt.disableflags |= mjDSBL_CONTACT;
  if (options.ignores("limits")) m->opt.disableflags |= mjDSBL_LIMIT;
  if (options.ignores("actuators")) m->opt.disableflags |= mjDSBL_ACTUATION;
  if (options.ignores("friction")) m->opt.disableflags |= mjDSBL_FRICTIONLOSS;
  if (options.ignores("armature"))
    for (int i = 0; i < m->nv; ++i) m->dof_armature[i] = 0.0;
  if (options.ignores("tendons"))
    for (int t = 0; t < m->ntendon; ++t) {
      m->tendon_stiffness[t] = m->tendon_damping[t] = m->tendon_frictionloss[t] = 0.0;
      m->tendon_limited[t] = 0;
    }
  if (options.ignores("equalities"))
    for (int e = 0; e < m->neq; ++e)
      if (!model_import::representedEquality(m, e)) m->eq_active[e] = 0;
  if (options.ignores("fluid")) {
    m->opt.density = m->opt.viscosity = 0.0;
    for (int i = 0; i < 3; ++i) m->opt.wind[i] = 0.0;
  }
}

}  // namespace mujoco_peer
}  // namespace lieflow

#endif
