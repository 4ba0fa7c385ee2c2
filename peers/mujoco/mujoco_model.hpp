/// \file
/// MuJoCo's model of a file as the peer runs it: a URDF through MuJoCo's own
/// reader (mujoco_urdf.cpp), and what the import leaves out switched off in
/// MuJoCo too (mujoco_switches.cpp). The compiled model and its data are the
/// importer's (model/import/mjcf_model.hpp: one owner of MuJoCo's objects).
/// Declared on MuJoCo's opaque types; defined only in builds with MuJoCo.
#pragma once

#include <string>
#include <vector>

#include "model/import/import_options.hpp"
#include "model/import/mjcf_model.hpp"

namespace lieflow {
namespace mujoco_peer {

using model_import::MjcfData;
using model_import::MjcfModel;

/// MuJoCo's own URDF reader on the URDF `path`, for the MuJoCo peer: mesh
/// geometry and visuals left out in memory (MuJoCo would look for their
/// files; they never act with contacts ignored), welded links fused into
/// their parents as lieflow merges them (every body lieflow keeps is a
/// MuJoCo body of its link's name), the root link on a URDF floating joint
/// with options.floating_base, and, through MuJoCo's MJCF of the model, each
/// <mimic> as a joint equality (MuJoCo's URDF reader leaves mimics out).
/// An inertia MuJoCo refuses (A + B < C: a camera's in ANYmal C, which
/// lieflow merges into a physical whole) is balanced by MuJoCo's compiler
/// (balanceinertia), said in `notes`. Throws InvalidInput naming the file and
/// MuJoCo's reason.
MjcfModel compileUrdfForMujoco(const std::string& path, const ModelImportOptions& options,
                               std::vector<std::string>* notes);

/// Switches off in MuJoCo what the import leaves out by `options.ignore`,
/// so that MuJoCo simulates the same mechanism as the imported scene:
/// contacts, limits (joints and tendons), actuation (mjDSBL_* flags),
/// friction loss, armature, tendons' springs and dashpots, and the
/// equalities lieflow does not represent.
void switchOffIgnored(mjModel_* m, const ModelImportOptions& options);

}  // namespace mujoco_peer
}  // namespace lieflow
