/// \file
/// What the MJCF reader (mjcf_import.cpp) and the MuJoCo peer
/// (peers/mujoco/) share: MuJoCo's compiled model of a file, its keyframes
/// by name or index, and MuJoCo's own switches for what an import leaves
/// out. Declared on MuJoCo's opaque `mjModel_` so that this header compiles
/// without MuJoCo; the definitions exist only in builds with it.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "model/import/import_options.hpp"
#include "model/visual_shape.hpp"

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

/// MuJoCo's compiler on files[0] with every (name, text) of `files` in memory
/// (an MJCF that includes the others). Throws InvalidInput naming `field`.
MjcfModel compileModelFiles(const std::vector<std::pair<std::string, std::string>>& files,
                            const std::string& field);

/// Whether lieflow represents MuJoCo equality `e` (a connect, a weld, a
/// linear joint coupling); the import refuses the others unless ignored.
bool representedEquality(const mjModel_* m, int e);

/// The keyframe `wanted` names (its name, else its index), or −1 when
/// `wanted` is empty. Throws InvalidInput (field "PATH: --keyframe") listing
/// the model's keyframes when there is no such one.
int keyframeIndex(const mjModel_* m, const std::string& path, const std::string& wanted);

/// The shapes of MuJoCo body `body` (geoms of groups 0-2, meshes as the
/// compiler's triangles), placed in the world at `d`'s kinematics
/// (mj_kinematics done): mjcf_visuals.cpp.
std::vector<VisualShape> mjcfBodyShapes(const mjModel_* m, const mjData_* d, int body);

}  // namespace model_import
}  // namespace lieflow
