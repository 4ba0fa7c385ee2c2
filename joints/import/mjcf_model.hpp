/// \file
/// What the MJCF reader (mjcf_import.cpp) and the MuJoCo peer
/// (mujoco_peer.cpp) share: MuJoCo's compiled model of a file, its keyframes
/// by name or index, and MuJoCo's own switches for what an import leaves
/// out. Declared on MuJoCo's opaque `mjModel_` so that this header compiles
/// without MuJoCo; the definitions exist only in builds with it.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "joints/import/import_options.hpp"
#include "joints/visual_shape.hpp"

struct mjModel_;
struct mjData_;

namespace lieflow {
namespace model_import {

/// MuJoCo's own error (its mju_error), thrown while a MujocoMessageGuard lives.
struct MujocoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// While it lives, MuJoCo's errors (mju_error: memory it cannot allocate, a
/// model its engine refuses), which would otherwise print and end the
/// process, throw MujocoError, and its warnings ("Nan, Inf or huge value in
/// QPOS"), which would go to stdout and to MUJOCO_LOG.TXT in the current
/// directory, are kept (warnings()). MuJoCo's compiler makes its errors throw
/// the same way while it compiles. The handlers are global: one guard at a
/// time per thread, restored when it goes.
class MujocoMessageGuard {
 public:
  MujocoMessageGuard();
  ~MujocoMessageGuard();
  MujocoMessageGuard(const MujocoMessageGuard&) = delete;
  MujocoMessageGuard& operator=(const MujocoMessageGuard&) = delete;
  const std::string& warnings() const { return warnings_; }
  void keep(const char* text);

 private:
  void (*previous_error_)(const char*);
  void (*previous_warning_)(const char*);
  MujocoMessageGuard* previous_guard_;
  std::string warnings_;
};

struct MjcfModelDeleter {
  void operator()(mjModel_* m) const;
};
using MjcfModel = std::unique_ptr<mjModel_, MjcfModelDeleter>;
struct MjcfDataDeleter {
  void operator()(mjData_* d) const;
};
using MjcfData = std::unique_ptr<mjData_, MjcfDataDeleter>;

/// mj_makeData for `m`. Throws InvalidInput naming `path` when MuJoCo
/// cannot (the data a model asks for, its nstack, beyond the memory).
MjcfData makeMjcfData(const mjModel_* m, const std::string& path);

/// MuJoCo's 3-vectors and row-major 3×3 matrices (mjtNum is double) as Eigen's.
inline Eigen::Vector3d mjVec3(const double* x) { return Eigen::Vector3d(x[0], x[1], x[2]); }
inline Eigen::Matrix3d mjMat3(const double* x) {
  Eigen::Matrix3d R;
  R << x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], x[8];
  return R;
}

/// The name the importer gives MuJoCo body `b` (b >= 1): its own, or
/// "body B" when it has none; the MuJoCo peer finds scene bodies by it.
std::string mjcfBodyName(const mjModel_* m, int b);

/// MuJoCo's compiler on `path` (its warnings kept, not printed). Throws
/// InvalidInput naming the file and MuJoCo's reason.
MjcfModel compileMjcf(const std::string& path);

/// MuJoCo's compiler on `text` as the file `name` (MJCF or URDF by MuJoCo's
/// reading of it), from memory. Throws InvalidInput naming `field`.
MjcfModel compileModelText(const std::string& name, const std::string& text, const std::string& field);

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

/// The keyframe `wanted` names (its name, else its index), or −1 when
/// `wanted` is empty. Throws InvalidInput (field "PATH: --keyframe") listing
/// the model's keyframes when there is no such one.
int keyframeIndex(const mjModel_* m, const std::string& path, const std::string& wanted);

/// Switches off in MuJoCo what the import leaves out by `options.ignore`,
/// so that MuJoCo simulates the same mechanism as the imported scene:
/// contacts, limits (joints and tendons), actuation (mjDSBL_* flags),
/// friction loss, armature, tendons' springs and dashpots, and the
/// equalities lieflow does not represent.
void switchOffIgnored(mjModel_* m, const ModelImportOptions& options);

/// The shapes of MuJoCo body `body` (geoms of groups 0-2, meshes as the
/// compiler's triangles), placed in the world at `d`'s kinematics
/// (mj_kinematics done): mjcf_visuals.cpp.
std::vector<VisualShape> mjcfBodyShapes(const mjModel_* m, const mjData_* d, int body);

}  // namespace model_import
}  // namespace lieflow
