// URDF robots through urdfdom (Debian liburdfdom-dev): model_readers.hpp.
#include "joints/import/model_readers.hpp"

#include "liegroup/invalid_input.hpp"

#ifdef LIEFLOW_HAVE_URDFDOM
#include <tinyxml2.h>

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <deque>
#include <map>
#include <set>

#include "joints/import/model_to_scene.hpp"
#include "joints/import/xml_lines.hpp"
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

Eigen::Isometry3d isometry(const urdf::Pose& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return T;
}

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

/// A URDF is a tree: every link but the root is the child of exactly one
/// joint, no joint joins a link to itself, and every link hangs from the
/// root. urdfdom does not check the first two (it links a child of two joints
/// under both parents, and a link that is its own parent under itself, so a
/// walk from the root would revisit links without end), nor the last (links
/// on a cycle of joints apart from the root are never reached). Throws
/// InvalidInput naming the joints and links, with their lines.
void requireTree(const urdf::ModelInterface& robot, const XmlLines& xml, const std::string& path) {
  const auto joint = [&](const std::string& name) { return elementLabel("joint", name, xml.line("joint", name)); };
  const auto link = [&](const std::string& name) { return elementLabel("link", name, xml.line("link", name)); };
  std::map<std::string, std::string> parent_joint;  // child link → the first joint naming it
  for (const auto& [name, j] : robot.joints_) {
    if (j->parent_link_name == j->child_link_name)
      throw InvalidInput(path + ": " + joint(name),
                         "its parent and its child are the same link '" + j->child_link_name + "'");
    const auto [it, first] = parent_joint.emplace(j->child_link_name, name);
    if (!first)
      throw InvalidInput(path + ": " + link(j->child_link_name),
                         "is the child of two joints, " + joint(it->second) + " and " + joint(name) +
                             ": a URDF is a tree, each link has one parent joint (a loop cannot be closed in URDF)");
  }
  // Every link reached from the root once (each has at most one parent now).
  std::set<std::string> reached;
  std::deque<urdf::LinkConstSharedPtr> queue{robot.getRoot()};
  while (!queue.empty()) {
    const urdf::LinkConstSharedPtr l = queue.front();
    queue.pop_front();
    if (!reached.insert(l->name).second) continue;
    for (const urdf::JointSharedPtr& j : l->child_joints)
      if (const urdf::LinkConstSharedPtr c = robot.getLink(j->child_link_name)) queue.push_back(c);
  }
  for (const auto& [name, l] : robot.links_)
    if (!reached.count(name))
      throw InvalidInput(path + ": " + link(name), "is not connected to the root link '" + robot.getRoot()->name +
                                                       "' (its joints form a cycle apart from the root)");
  // <mimic>: the leader exists, is another joint, and following leaders
  // from any joint ends (a cycle of mimics holds no joint free).
  for (const auto& [name, j] : robot.joints_) {
    if (!j->mimic) continue;
    const std::string& leader = j->mimic->joint_name;
    if (leader == name) throw InvalidInput(path + ": " + joint(name), "<mimic> names the joint itself");
    if (!robot.joints_.count(leader))
      throw InvalidInput(path + ": " + joint(name), "<mimic> names joint '" + leader + "', which the robot does not have");
    std::set<std::string> chain{name};
    for (std::string at = leader;;) {
      if (!chain.insert(at).second)
        throw InvalidInput(path + ": " + joint(name),
                           "<mimic> leads back to it through joint '" + at + "': the mimics form a cycle");
      const auto next = robot.joints_.find(at);
      if (next == robot.joints_.end() || !next->second->mimic) break;
      at = next->second->mimic->joint_name;
    }
  }
}

}  // namespace

ModelDescription readUrdf(const std::string& text, const std::string& path, const ModelImportOptions& options) {
  const XmlLines xml(text, path);
  if (xml.rootTag() != "robot")
    throw InvalidInput(path, "a URDF file's root element is <robot>, not <" + xml.rootTag() + ">");
  // Every number where it is written, before urdfdom reads (and, for some
  // attributes, silently zeroes) it: names, links and file names aside.
  xml.requireUsableNumbers(path, {"name", "link", "joint", "filename", "type", "version"});
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
  requireTree(*robot, xml, path);
  unsupported.resolve(options, &model);

  // Links in breadth-first order from the root, which is the ground (a
  // fixed base); their frames at every joint coordinate 0.
  const urdf::LinkConstSharedPtr root = robot->getRoot();
  std::map<std::string, int> index;  // link name → model link (the root: −1)
  std::map<std::string, Eigen::Isometry3d> frame;
  frame[root->name] = Eigen::Isometry3d::Identity();
  index[root->name] = -1;
  std::deque<urdf::LinkConstSharedPtr> queue{root};
  while (!queue.empty()) {
    const urdf::LinkConstSharedPtr link = queue.front();
    queue.pop_front();
    for (const urdf::JointSharedPtr& j : link->child_joints) {
      const urdf::LinkConstSharedPtr child = robot->getLink(j->child_link_name);
      const int jline = xml.line("joint", j->name);
      if (!child) throw InvalidInput(path + ": " + elementLabel("joint", j->name, jline), "has no child link");
      const Eigen::Isometry3d T = frame[link->name] * isometry(j->parent_to_joint_origin_transform);
      frame[child->name] = T;
      ModelLink l;
      l.name = child->name;
      l.line = xml.line("link", child->name);
      if (child->name == "ground")
        throw InvalidInput(path + ": " + elementLabel("link", l.name, l.line),
                           "'ground' is lieflow's name for the world: rename the link");
      l.orientation = Eigen::Quaterniond(T.linear());
      if (const urdf::InertialSharedPtr& in = child->inertial) {
        const Eigen::Isometry3d Ti = T * isometry(in->origin);
        Eigen::Matrix3d I;
        I << in->ixx, in->ixy, in->ixz, in->ixy, in->iyy, in->iyz, in->ixz, in->iyz, in->izz;
        if (!(std::isfinite(in->mass) && in->mass >= 0.0) || !I.allFinite())
          throw InvalidInput(path + ": " + elementLabel("link", l.name, l.line), "inertial mass and inertia must be finite, mass >= 0");
        l.mass = in->mass;
        l.com_world = Ti.translation();
        l.inertia_world = Ti.linear() * I * Ti.linear().transpose();
      } else {
        l.com_world = T.translation();
      }
      index[child->name] = static_cast<int>(model.links.size());
      model.links.push_back(l);

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
                           "a floating joint frees a link from the world: its parent must be the root link");
      if (j->dynamics) mj.damping[0] = j->dynamics->damping;
      if (j->mimic) {
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
