// URDF robots through urdfdom (Debian liburdfdom-dev): model_readers.hpp.
#include "model/import/model_readers.hpp"

#include "liegroup/invalid_input.hpp"

#ifdef LIEFLOW_HAVE_URDFDOM
#include <tinyxml2.h>

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <deque>
#include <map>
#include <cstdlib>
#include <set>
#include <sstream>
#include <vector>

#include "model/import/model_to_scene.hpp"
#include "model/import/urdf_visuals.hpp"
#include "model/import/xml_lines.hpp"
#endif

namespace lieflow {

#ifndef LIEFLOW_HAVE_URDFDOM

bool canReadUrdf() { return false; }

namespace model_import {
ModelDescription readUrdf(const std::string&, const std::string& path, const ModelImportOptions&) {
  throw InvalidInput(path, "reading URDF needs urdfdom, which this lieflow was built without "
                           "(apt-get install liburdfdom-dev libtinyxml2-dev, then rebuild lieflow)");
}
}  // namespace model_import

#else

bool canReadUrdf() { return true; }

namespace model_import {

namespace {

/// urdfdom's messages (console_bridge), kept instead of printed while a file
/// is parsed.
class MessageCapture : public console_bridge::OutputHandler {
 public:
  MessageCapture() { console_bridge::useOutputHandler(this); }
  ~MessageCapture() override { console_bridge::restorePreviousOutputHandler(); }
  MessageCapture(const MessageCapture&) = delete;
  MessageCapture& operator=(const MessageCapture&) = delete;
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors += (errors.empty() ? "" : "; ") + text;
  }
  std::string errors;
};

/// What lieflow does not represent, from the elements themselves: <collision>
/// (contacts), <limit lower upper> of revolute and prismatic joints and
/// <safety_controller> (limits), <dynamics friction> (friction),
/// <transmission> (actuators); a planar joint is an error.
void listUnsupported(const XmlLines& xml, const std::string& path, UnsupportedFeatures* out) {
  for (const tinyxml2::XMLElement* e : xml.elements()) {
    const std::string tag = e->Name();
    const tinyxml2::XMLElement* parent = e->Parent() ? e->Parent()->ToElement() : nullptr;
    const std::string owner = parent && parent->Attribute("name") ? parent->Attribute("name") : "";
    const int line = e->GetLineNum();
    if (tag == "collision" && parent && std::string(parent->Name()) == "link") {
      out->add("contacts", "collision of link '" + owner + "' (line " + std::to_string(line) + ")");
    } else if (tag == "joint" && parent && std::string(parent->Name()) == "robot") {
      const char* type = e->Attribute("type");
      const std::string name = e->Attribute("name") ? e->Attribute("name") : "";
      if (type && std::string(type) == "planar")
        throw InvalidInput(path + ": " + elementLabel("joint", name, line),
                           "is planar: lieflow has no planar joint (model it as two prismatic joints and a revolute one)");
      for (const tinyxml2::XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
        const std::string ctag = c->Name();
        const bool bounded = type && (std::string(type) == "revolute" || std::string(type) == "prismatic");
        if ((ctag == "limit" && bounded) || ctag == "safety_controller")
          out->add("limits", ctag + " of joint '" + name + "' (line " + std::to_string(c->GetLineNum()) + ")");
        if (ctag == "dynamics" && c->DoubleAttribute("friction", 0.0) != 0.0)
          out->add("friction", "dynamics of joint '" + name + "' (line " + std::to_string(c->GetLineNum()) + ")");
      }
    } else if (tag == "transmission") {
      out->add("actuators", elementLabel("transmission", e->Attribute("name") ? e->Attribute("name") : "", line));
    }
  }
}

/// The URDF attributes that hold numbers, by element, and how many: urdfdom
/// reads them with a stream that takes decimal numbers only, and refuses a
/// file with a wrong count or a word (or hex) there with a message that names
/// no line ("joint xml is not initialized correctly").
struct NumericAttribute {
  const char* tag;
  const char* attribute;
  int count;
};
constexpr NumericAttribute kUrdfNumbers[] = {
    {"origin", "xyz", 3},    {"origin", "rpy", 3},         {"axis", "xyz", 3},        {"mass", "value", 1},
    {"inertia", "ixx", 1},   {"inertia", "ixy", 1},        {"inertia", "ixz", 1},     {"inertia", "iyy", 1},
    {"inertia", "iyz", 1},   {"inertia", "izz", 1},        {"limit", "lower", 1},     {"limit", "upper", 1},
    {"limit", "effort", 1},  {"limit", "velocity", 1},     {"dynamics", "damping", 1}, {"dynamics", "friction", 1},
    {"mimic", "multiplier", 1}, {"mimic", "offset", 1},    {"box", "size", 3},        {"cylinder", "radius", 1},
    {"cylinder", "length", 1}, {"sphere", "radius", 1},    {"mesh", "scale", 3},      {"color", "rgba", 4},
    {"safety_controller", "soft_lower_limit", 1}, {"safety_controller", "soft_upper_limit", 1},
    {"safety_controller", "k_position", 1}, {"safety_controller", "k_velocity", 1},
    {"calibration", "rising", 1}, {"calibration", "falling", 1},
};

/// Each numeric attribute holds its count of decimal numbers (their values
/// are checked by XmlLines::requireUsableNumbers). Throws InvalidInput naming
/// the element, its line and the attribute.
void requireNumberFormats(const XmlLines& xml, const std::string& path) {
  for (const tinyxml2::XMLElement* e : xml.elements())
    for (const NumericAttribute& n : kUrdfNumbers) {
      if (std::string(e->Name()) != n.tag) continue;
      const char* value = e->Attribute(n.attribute);
      if (!value) continue;
      std::istringstream tokens(value);
      std::string token;
      int count = 0;
      bool numbers = true;
      while (tokens >> token) {
        ++count;
        char* end = nullptr;
        std::strtod(token.c_str(), &end);
        numbers = numbers && end == token.c_str() + token.size() && token.find_first_of("xXnN") == std::string::npos;
      }
      if (!numbers || count != n.count)
        throw InvalidInput(path + ": " + XmlLines::label(e) + ", attribute " + n.attribute,
                           "expected " + std::to_string(n.count) + (n.count == 1 ? " decimal number" : " decimal numbers") +
                               ", got '" + std::string(value).substr(0, 60) + "'");
    }
}

/// A URDF is a tree: every link but the root is the child of exactly one
/// joint, no joint joins a link to itself, and every link hangs from the one
/// root. Checked on the file's elements, before urdfdom reads it: urdfdom
/// links a child of two joints under both parents and a link that is its own
/// parent under itself (a walk from the root then revisits links without
/// end), never reaches links on a cycle apart from the root, and names two
/// roots where a link has two parents. Mimics must lead to another joint of
/// the robot and not in a circle. Throws InvalidInput naming the joints and
/// links, with their lines.
void requireTree(const XmlLines& xml, const std::string& path) {
  struct Joint {
    std::string parent, child, mimic;
    int line = 0;
  };
  std::map<std::string, Joint> joints;
  std::map<std::string, int> links;  // name → line
  for (const tinyxml2::XMLElement* e : xml.elements()) {
    const tinyxml2::XMLElement* up = e->Parent() ? e->Parent()->ToElement() : nullptr;
    if (!up || std::string(up->Name()) != "robot") continue;
    const std::string tag = e->Name();
    if (tag != "link" && tag != "joint") continue;
    const char* name = e->Attribute("name");
    if (!name || !*name) throw InvalidInput(path + ": " + tag + " (line " + std::to_string(e->GetLineNum()) + ")",
                                            "has no name");
    const std::string here = elementLabel(tag, name, e->GetLineNum());
    if (tag == "link") {
      const auto [it, first] = links.emplace(name, e->GetLineNum());
      if (!first)
        throw InvalidInput(path + ": " + here, "a link of this name is on line " + std::to_string(it->second) +
                                                    " too: each link's name is its own");
      continue;
    }
    Joint j;
    j.line = e->GetLineNum();
    const auto attribute = [&](const char* child, const char* attr) {
      const tinyxml2::XMLElement* c = e->FirstChildElement(child);
      return c && c->Attribute(attr) ? std::string(c->Attribute(attr)) : std::string();
    };
    j.parent = attribute("parent", "link");
    j.child = attribute("child", "link");
    j.mimic = attribute("mimic", "joint");
    if (j.parent.empty() || j.child.empty())
      throw InvalidInput(path + ": " + here, std::string("needs <parent link=\"...\"/> and <child link=\"...\"/>"));
    const char* type = e->Attribute("type");
    static const std::set<std::string> kTypes = {"revolute", "continuous", "prismatic", "fixed", "floating",
                                                 "planar"};
    if (!type || !kTypes.count(type))
      throw InvalidInput(path + ": " + here + ", attribute type",
                         std::string(type ? "'" + std::string(type) + "' is not a URDF joint type" : "missing") +
                             " (revolute, continuous, prismatic, fixed, floating, planar)");
    if ((std::string(type) == "revolute" || std::string(type) == "prismatic") && !e->FirstChildElement("limit"))
      throw InvalidInput(path + ": " + here,
                         std::string("a ") + type + " joint needs <limit effort=\"...\" velocity=\"...\"/> (URDF "
                                                    "requires it; use type continuous for a joint without limits)");
    const auto [it, first] = joints.emplace(name, j);
    if (!first)
      throw InvalidInput(path + ": " + here, "a joint of this name is on line " + std::to_string(it->second.line) +
                                                  " too: each joint's name is its own");
  }
  if (links.empty()) throw InvalidInput(path, "the robot has no <link>");
  for (const auto& [name, j] : joints)
    for (const std::string* l : {&j.parent, &j.child})
      if (!links.count(*l))
        throw InvalidInput(path + ": " + elementLabel("joint", name, j.line),
                           "names link '" + *l + "', which the robot does not have");
  const auto joint = [&](const std::string& name) { return elementLabel("joint", name, joints.at(name).line); };
  const auto link = [&](const std::string& name) {
    const auto it = links.find(name);
    return elementLabel("link", name, it == links.end() ? 0 : it->second);
  };
  std::map<std::string, std::string> parent_joint;  // child link → its joint
  std::map<std::string, std::vector<std::string>> children;
  for (const auto& [name, j] : joints) {
    if (j.parent.empty() || j.child.empty()) continue;  // urdfdom names what is missing
    if (j.parent == j.child)
      throw InvalidInput(path + ": " + joint(name), "its parent and its child are the same link '" + j.child + "'");
    const auto [it, first] = parent_joint.emplace(j.child, name);
    if (!first)
      throw InvalidInput(path + ": " + link(j.child),
                         "is the child of two joints, " + joint(it->second) + " and " + joint(name) +
                             ": a URDF is a tree, each link has one parent joint (a loop cannot be closed in URDF)");
    children[j.parent].push_back(j.child);
  }
  std::vector<std::string> roots;
  for (const auto& [name, line] : links)
    if (!parent_joint.count(name)) roots.push_back(name);
  if (roots.size() > 1)
    throw InvalidInput(path + ": " + link(roots[1]),
                       "is a second root (no joint has it as child) beside link '" + roots[0] +
                           "': a URDF's links hang from one root");
  std::set<std::string> reached;
  std::vector<std::string> stack(roots.begin(), roots.end());
  while (!stack.empty()) {
    const std::string l = stack.back();
    stack.pop_back();
    if (!reached.insert(l).second) continue;
    for (const std::string& c : children[l]) stack.push_back(c);
  }
  for (const auto& [name, line] : links)
    if (!reached.count(name))
      throw InvalidInput(path + ": " + link(name), roots.empty() ? "every link is some joint's child: the joints form a cycle"
                                                                 : "is not connected to the root link '" + roots[0] +
                                                                       "' (its joints form a cycle apart from the root)");
  for (const auto& [name, j] : joints) {
    if (j.mimic.empty()) continue;
    if (j.mimic == name) throw InvalidInput(path + ": " + joint(name), "<mimic> names the joint itself");
    if (!joints.count(j.mimic))
      throw InvalidInput(path + ": " + joint(name), "<mimic> names joint '" + j.mimic + "', which the robot does not have");
    std::set<std::string> chain{name};
    for (std::string at = j.mimic; !at.empty();) {
      if (!chain.insert(at).second)
        throw InvalidInput(path + ": " + joint(name),
                           "<mimic> leads back to it through joint '" + at + "': the mimics form a cycle");
      const auto next = joints.find(at);
      at = next == joints.end() ? std::string() : next->second.mimic;
    }
  }
}

}  // namespace

ModelDescription readUrdf(const std::string& text, const std::string& path, const ModelImportOptions& options) {
  // Entities a DTD defines are not expanded by the XML readers (and a file
  // of nested ones grows without bound where they are): URDF has none.
  if (text.find("<!ENTITY") != std::string::npos)
    throw InvalidInput(path, "declares XML entities (<!ENTITY ...>): URDF files have none, and they are not read");
  const XmlLines xml(text, path);
  if (xml.rootTag() != "robot")
    throw InvalidInput(path, "a URDF file's root element is <robot>, not <" + xml.rootTag() + ">");
  // Every number where it is written, before urdfdom reads (and, for some
  // attributes, silently zeroes) it: names, links and file names aside.
  xml.requireUsableNumbers(path, {"name", "link", "joint", "filename", "type", "version"});
  requireNumberFormats(xml, path);
  requireTree(xml, path);
  ModelDescription model;
  model.source = path;
  UnsupportedFeatures unsupported;
  listUnsupported(xml, path, &unsupported);

  urdf::ModelInterfaceSharedPtr robot;
  {
    MessageCapture capture;
    robot = urdf::parseURDF(text);
    if (!robot)
      throw InvalidInput(path, "urdfdom cannot read it: " + (capture.errors.empty() ? "invalid URDF" : capture.errors));
  }
  model.name = robot->getName();
  unsupported.resolve(options, &model);

  // A link at frame T (link → world): its mass properties in the world.
  const auto linkAt = [&](const urdf::LinkConstSharedPtr& link, const Eigen::Isometry3d& T) {
    ModelLink l;
    l.name = link->name;
    l.line = xml.line("link", link->name);
    if (link->name == "ground")
      throw InvalidInput(path + ": " + elementLabel("link", l.name, l.line),
                         "'ground' is lieflow's name for the world: rename the link");
    l.orientation = Eigen::Quaterniond(T.linear());
    l.visuals = urdfLinkShapes(*link, T, path);
    if (const urdf::InertialSharedPtr& in = link->inertial) {
      const Eigen::Isometry3d Ti = T * urdfIsometry(in->origin);
      Eigen::Matrix3d I;
      I << in->ixx, in->ixy, in->ixz, in->ixy, in->iyy, in->iyz, in->ixz, in->iyz, in->izz;
      if (!(std::isfinite(in->mass) && in->mass >= 0.0) || !I.allFinite())
        throw InvalidInput(path + ": " + elementLabel("link", l.name, l.line),
                           "inertial mass and inertia must be finite, mass >= 0");
      l.mass = in->mass;
      l.com_world = Ti.translation();
      l.inertia_world = Ti.linear() * I * Ti.linear().transpose();
    } else {
      l.com_world = T.translation();
    }
    return l;
  };

  // Links in breadth-first order from the root; their frames at every joint
  // coordinate 0, the root's at the world origin. The root is the ground (a
  // fixed base, as URDF's tools take it) or, with --floating-base, a body on
  // a free joint to the world (a legged robot's trunk).
  const urdf::LinkConstSharedPtr root = robot->getRoot();
  std::map<std::string, int> index;  // link name → model link (a fixed root: −1)
  std::map<std::string, Eigen::Isometry3d> frame;
  frame[root->name] = Eigen::Isometry3d::Identity();
  index[root->name] = -1;
  if (options.floating_base) {
    index[root->name] = 0;
    model.links.push_back(linkAt(root, Eigen::Isometry3d::Identity()));
    ModelJoint free;
    free.name = root->name + "_floating_base";
    free.line = model.links.back().line;
    free.type = ModelJointType::kFree;
    free.parent = -1;
    free.child = 0;
    model.joints.push_back(free);
  } else {
    model.ground_visuals = urdfLinkShapes(*root, Eigen::Isometry3d::Identity(), path);
    model.notes.push_back("the root link '" + root->name +
                          "' is fixed to the world (a URDF's base; `floating_base` frees it)");
  }
  std::deque<urdf::LinkConstSharedPtr> queue{root};
  while (!queue.empty()) {
    const urdf::LinkConstSharedPtr link = queue.front();
    queue.pop_front();
    for (const urdf::JointSharedPtr& j : link->child_joints) {
      const urdf::LinkConstSharedPtr child = robot->getLink(j->child_link_name);
      const int jline = xml.line("joint", j->name);
      if (!child) throw InvalidInput(path + ": " + elementLabel("joint", j->name, jline), "has no child link");
      const Eigen::Isometry3d T = frame[link->name] * urdfIsometry(j->parent_to_joint_origin_transform);
      frame[child->name] = T;
      index[child->name] = static_cast<int>(model.links.size());
      model.links.push_back(linkAt(child, T));

      ModelJoint mj;
      mj.name = j->name;
      mj.line = jline;
      mj.parent = index[link->name];
      mj.child = index[child->name];
      mj.anchor_world = T.translation();
      const Eigen::Vector3d axis(j->axis.x, j->axis.y, j->axis.z);
      const bool has_axis = j->type == urdf::Joint::REVOLUTE || j->type == urdf::Joint::CONTINUOUS ||
                            j->type == urdf::Joint::PRISMATIC;
      if (has_axis && (!(axis.norm() > 0.0) || !axis.allFinite()))
        throw InvalidInput(path + ": " + elementLabel("joint", j->name, jline), "axis is zero or not finite");
      if (has_axis) mj.axis_world = T.linear() * axis.normalized();
      switch (j->type) {
        case urdf::Joint::REVOLUTE:
        case urdf::Joint::CONTINUOUS: mj.type = ModelJointType::kRevolute; break;
        case urdf::Joint::PRISMATIC: mj.type = ModelJointType::kPrismatic; break;
        case urdf::Joint::FIXED: mj.type = ModelJointType::kFixed; break;
        case urdf::Joint::FLOATING: mj.type = ModelJointType::kFree; break;
        default:
          throw InvalidInput(path + ": " + elementLabel("joint", j->name, jline),
                             "has a joint type lieflow does not know (revolute, continuous, prismatic, fixed, floating)");
      }
      if (mj.type == ModelJointType::kFree && mj.parent != -1)
        throw InvalidInput(path + ": " + elementLabel("joint", j->name, jline),
                           options.floating_base
                               ? "a floating joint frees a link from the world: with `floating_base` the root link "
                                 "floats itself, and no other link may"
                               : "a floating joint frees a link from the world: its parent must be the root link");
      if (j->dynamics) mj.damping[0] = j->dynamics->damping;
      if (j->mimic && j->type == urdf::Joint::FIXED) {
        // A fixed joint has no coordinate to couple (PAL's Talos has such
        // <mimic>s on its grippers' welded links): URDF's tools pass it by.
        model.notes.push_back("ignored mimics of fixed joints (no coordinate to couple): joint '" + j->name + "' (line " +
                              std::to_string(jline) + ") mimics '" + j->mimic->joint_name + "'");
      } else if (j->mimic) {
        ModelCoupling c;
        c.name = j->name + "-mimic";
        c.line = jline;
        c.leader = j->mimic->joint_name;
        c.follower = j->name;
        c.multiplier = j->mimic->multiplier;
        c.offset = j->mimic->offset;
        model.couplings.push_back(c);
      }
      model.joints.push_back(mj);
      queue.push_back(child);
    }
  }
  return model;
}

}  // namespace model_import

#endif

}  // namespace lieflow
