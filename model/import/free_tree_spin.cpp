/// \file
/// A model's free trees set turning (free_tree_spin.hpp).
#include "model/import/free_tree_spin.hpp"

#include <map>
#include <vector>

#include <Eigen/Geometry>

#include "model/union_find.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace model_import {

void spinFreeTrees(const Eigen::Vector3d& omega, const std::string& path, SceneDescription* scene) {
  std::vector<BodyDescription>& bodies = scene->bodies;
  const int n = static_cast<int>(bodies.size());
  std::map<std::string, int> index;
  for (int i = 0; i < n; ++i) index.emplace(bodies[i].name, i);
  // Trees as the joints join them; a tree with a joint to the ground (or a
  // body held at a point, rotation-only) is not free.
  UnionFind trees(n);
  std::vector<bool> grounded(n, false);
  for (int i = 0; i < n; ++i) grounded[i] = bodies[i].rotation_only;
  // A gear's rows hold rates relative to its carriers: a carrier that is the
  // ground grounds its nodes (a turn of theirs alone would break the rows).
  for (const JointDescription& j : scene->joints) {
    std::vector<std::string> members = {j.main, j.secondary};
    if (j.isGear()) members.insert(members.end(), {j.tertiary, j.carrier, j.carrier_secondary});
    int first = -1;
    bool to_ground = false;
    for (const std::string& name : members) {
      if (name.empty()) continue;
      const auto found = index.find(name);
      if (found == index.end()) {
        to_ground = true;  // "ground", the world
        continue;
      }
      if (first < 0)
        first = found->second;
      else
        trees.join(found->second, first);
    }
    if (to_ground && first >= 0) grounded[first] = true;
  }
  std::vector<bool> tree_grounded(n, false);
  for (int i = 0; i < n; ++i)
    if (grounded[i]) tree_grounded[trees.find(i)] = true;
  // Each free tree's mass and centre of mass.
  std::vector<double> mass(n, 0.0);
  std::vector<Eigen::Vector3d> moment(n, Eigen::Vector3d::Zero());
  for (int i = 0; i < n; ++i) {
    const int r = trees.find(i);
    mass[r] += bodies[i].mass;
    moment[r] += bodies[i].mass * bodies[i].position;
  }
  int free_trees = 0;
  for (int i = 0; i < n; ++i) {
    const int r = trees.find(i);
    if (tree_grounded[r]) continue;
    if (r == i) ++free_trees;
    BodyDescription& b = bodies[i];
    const Eigen::Vector3d centre = moment[r] / mass[r];
    b.angular_velocity += b.orientation.conjugate() * omega;
    b.velocity += omega.cross(b.position - centre);
    b.has_velocity = true;
  }
  if (free_trees == 0)
    throw InvalidInput(path + ": `spin`", "the model has no free body or tree to turn (every tree is joined to the "
                                          "world; a URDF's root link floats with `floating_base`)");
}

}  // namespace model_import
}  // namespace lieflow
