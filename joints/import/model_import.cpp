#include "joints/import/model_import.hpp"

#include <algorithm>
#include <cctype>
#include <map>
#include <sstream>

#include "joints/import/model_readers.hpp"
#include "joints/import/model_to_scene.hpp"
#include "joints/input_file.hpp"
#include "joints/scene_writer.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  return std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                    [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
}

}  // namespace

namespace model_import {

void UnsupportedFeatures::resolve(const ModelImportOptions& options, ModelDescription* model) const {
  std::map<std::string, std::vector<std::string>> refused;
  for (const Item& i : items_) {
    if (options.ignores(i.category))
      model->ignored.push_back(i.category + ": " + i.element);
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
  why << " (rerun with --ignore " << categories << " to simulate without them)";
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
      throw InvalidInput("--ignore", "unknown feature '" + item + "' (known: " + names + ", all)");
    }
    o.ignore.insert(item);
  }
  return o;
}

bool isModelFile(const std::string& path) { return endsWith(path, ".xml") || endsWith(path, ".urdf"); }

SceneDescription importModel(const std::string& path, const ModelImportOptions& options,
                             const ResourceLimits& limits) {
  std::string text;
  if (!readInputFile(path, limits.max_input_bytes, &text))
    throw InvalidInput(path, "cannot open the model file");
  const bool urdf = endsWith(path, ".urdf");
  if (urdf && !options.keyframe.empty())
    throw InvalidInput(path + ": --keyframe", "a URDF has no keyframes (it starts at its zero configuration, at rest)");
  model_import::ModelDescription model =
      urdf ? model_import::readUrdf(text, path, options) : model_import::readMjcf(text, path, options, limits);
  if (static_cast<long>(model.links.size()) > limits.max_bodies)
    throw InvalidInput(path, "the model has " + std::to_string(model.links.size()) + " links, more than --max-bodies " +
                                 std::to_string(limits.max_bodies));
  // Through the scene file's reader, so that an imported model passes every
  // check a scene file does and `lieflow import` writes what runs.
  const SceneDescription built = model_import::sceneFromModel(model);
  SceneDescription scene = parseScene(sceneToJson(built), path, limits.max_bodies);
  scene.import_notes = built.import_notes;
  return scene;
}

}  // namespace lieflow
