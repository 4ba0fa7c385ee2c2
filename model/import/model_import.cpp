#include "model/import/model_import.hpp"

#include <algorithm>
#include <cctype>
#include <map>
#include <regex>
#include <sstream>

#include "model/import/model_readers.hpp"
#include "model/import/free_tree_spin.hpp"
#include "model/import/model_to_scene.hpp"
#include "model/input_file.hpp"
#include "model/scene_writer.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  return std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                    [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
}

/// A scene reader's field for an imported scene ("arm.urdf: bodies[1].inertia")
/// as the model element it came from ("arm.urdf: link 'arm' (line 3), as the
/// scene's bodies[1].inertia"): the scene is lieflow's, the file the user's.
std::string modelElementOf(const model_import::ModelDescription& model, const SceneDescription& scene,
                           const std::string& field) {
  static const std::regex indexed(R"((bodies|joints)\[(\d+)\])");
  std::smatch m;
  if (!std::regex_search(field, m, indexed)) return field;
  const std::size_t k = std::stoul(m[2].str());
  const bool body = m[1].str() == "bodies";
  if (k >= (body ? scene.bodies.size() : scene.joints.size())) return field;
  const std::string& name = body ? scene.bodies[k].name : scene.joints[k].name;
  std::string element = (body ? "link '" : "joint '") + name + "'";
  const auto label = [&](const char* kind, int line) {
    element = model_import::elementLabel(kind, name, line);
  };
  if (body) {
    for (const auto& l : model.links)
      if (l.name == name) label("link", l.line);
  } else {
    for (const auto& j : model.joints)
      if (j.name == name) label("joint", j.line);
    for (const auto& c : model.closures)
      if (c.name == name) label("equality", c.line);
    for (const auto& c : model.couplings)
      if (c.name == name) label("coupling", c.line);
  }
  return model.source + ": " + element + ", as the scene's " + field.substr(static_cast<std::size_t>(m.position(0)));
}

}  // namespace

namespace model_import {

void UnsupportedFeatures::resolve(const ModelImportOptions& options, ModelDescription* model) const {
  std::map<std::string, std::vector<std::string>> refused;
  for (const Item& i : items_) {
    if (options.ignores(i.category))
      model->ignored.push_back("ignored " + i.category + ": " + i.element);
    else
      refused[i.category].push_back(i.element);
  }
  if (refused.empty()) return;
  std::ostringstream why;
  why << "lieflow cannot represent";
  std::string categories;
  for (const auto& [category, elements] : refused) {
    why << (categories.empty() ? " " : "; ") << category << ": ";
    constexpr std::size_t kListed = 8;
    for (std::size_t k = 0; k < elements.size() && k < kListed; ++k) why << (k ? ", " : "") << elements[k];
    if (elements.size() > kListed) why << " and " << elements.size() - kListed << " more";
    categories += (categories.empty() ? "" : ",") + category;
  }
  why << " (rerun with `ignore` " << categories << " to simulate without them)";
  throw InvalidInput(model->source, why.str());
}

}  // namespace model_import

const std::vector<std::pair<std::string, std::string>>& ignorableFeatures() {
  static const std::vector<std::pair<std::string, std::string>> kFeatures = {
      {"contacts", "collision geometry (URDF <collision>, MJCF geoms that collide): lieflow has no contact"},
      {"limits", "joint limits (URDF <limit lower upper>, <safety_controller>; MJCF limited joints)"},
      {"friction", "joint friction (URDF <dynamics friction>, MJCF frictionloss)"},
      {"actuators", "actuators and transmissions (MJCF <actuator>, URDF <transmission>)"},
      {"armature", "rotor inertia added to a joint coordinate (MJCF armature)"},
      {"tendons", "MJCF tendons"},
      {"equalities", "MJCF equality constraints other than connect, weld and linear joint couplings"},
      {"fluid", "MJCF forces of the medium (<option density, viscosity, wind>: lift, drag, buoyancy)"},
  };
  return kFeatures;
}

ModelImportOptions parseIgnoreList(const std::string& list) {
  ModelImportOptions o;
  std::stringstream s(list);
  std::string item;
  while (std::getline(s, item, ',')) {
    if (item.empty()) continue;
    if (item == "all") {
      for (const auto& f : ignorableFeatures()) o.ignore.insert(f.first);
      continue;
    }
    const auto& known = ignorableFeatures();
    if (std::none_of(known.begin(), known.end(), [&](const auto& f) { return f.first == item; })) {
      std::string names;
      for (const auto& f : known) names += (names.empty() ? "" : ", ") + f.first;
      throw InvalidInput("`ignore`", "unknown feature '" + item + "' (known: " + names + ", all)");
    }
    o.ignore.insert(item);
  }
  return o;
}

bool isModelFile(const std::string& path) { return endsWith(path, ".xml") || isUrdfFile(path); }

bool isUrdfFile(const std::string& path) { return endsWith(path, ".urdf"); }

SceneDescription importModel(const std::string& path, const ModelImportOptions& options,
                             const ResourceLimits& limits) {
  std::string text;
  if (!readInputFile(path, limits.max_input_bytes, &text))
    throw InvalidInput(path, "cannot open the model file");
  const bool urdf = isUrdfFile(path);
  if (urdf && !options.keyframe.empty())
    throw InvalidInput(path + ": `keyframe`", "a URDF has no keyframes (it starts at its zero configuration, at rest)");
  if (!urdf && options.floating_base)
    throw InvalidInput(path + ": `floating_base`", "frees a URDF's root link; an MJCF model says which bodies are free "
                                                   "itself (<freejoint/>)");
  model_import::ModelDescription model =
      urdf ? model_import::readUrdf(text, path, options) : model_import::readMjcf(text, path, options, limits);
  if (static_cast<long>(model.links.size()) > limits.max_bodies)
    throw InvalidInput(path, "the model has " + std::to_string(model.links.size()) + " links, more than `max_bodies` " +
                                 std::to_string(limits.max_bodies));
  // Through the scene file's reader, so that an imported model passes every
  // check a scene file does and `lieflow import` writes what runs.
  SceneDescription built = model_import::sceneFromModel(model);
  if (options.has_spin)
    model_import::spinFreeTrees(Eigen::Vector3d(options.spin[0], options.spin[1], options.spin[2]), path, &built);
  try {
    SceneDescription scene = parseScene(sceneToJson(built), path, limits.max_bodies);
    scene.import_notes = built.import_notes;
    // The shapes, which the scene file does not hold (only the replay reads
    // them); the reader keeps the bodies, their names and their frames.
    scene.ground_visuals = std::move(built.ground_visuals);
    const auto index = scene.bodyIndices();
    for (BodyDescription& b : built.bodies)
      if (const auto it = index.find(b.name); it != index.end()) scene.bodies[it->second].visuals = std::move(b.visuals);
    return scene;
  } catch (const InvalidInput& e) {
    throw InvalidInput(modelElementOf(model, built, e.field()), e.reason());
  }
}

}  // namespace lieflow
