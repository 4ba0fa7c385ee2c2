// MuJoCo's own URDF reader for the MuJoCo peer (mujoco_model.hpp:
// compileUrdfForMujoco).
#include "peers/mujoco/mujoco_model.hpp"

#ifdef LIEFLOW_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#include <tinyxml2.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "liegroup/invalid_input.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {
namespace mujoco_peer {

using model_import::compileModelText;

namespace {

/// A URDF <mimic>: q_follower = multiplier q_leader + offset.
struct Mimic {
  std::string follower, leader;
  double multiplier = 1.0, offset = 0.0;
};

std::string printed(tinyxml2::XMLDocument& doc) {
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  return printer.CStr();
}

/// Whether a <visual> or <collision> element's geometry is a mesh (a file
/// that MuJoCo would read: `package://` paths and meshes beside the robot's
/// description are not part of a test set's URDF, and MuJoCo 2.2 reads STL
/// only).
bool isMesh(const tinyxml2::XMLElement* e) {
  const tinyxml2::XMLElement* g = e->FirstChildElement("geometry");
  return g && g->FirstChildElement("mesh");
}

/// The model as MuJoCo saves it (MJCF) after the last load: URDF has no
/// words for a free root or a joint equality, MJCF has.
std::string savedMjcf(const mjModel* m, const std::string& path) {
  char name[] = "/tmp/lieflow-urdf-peer-XXXXXX";
  const int fd = mkstemp(name);
  if (fd < 0) throw InvalidInput(path + ": `with_mujoco`", "cannot make a temporary file for MuJoCo's MJCF");
  close(fd);
  char error[1024] = "";
  const int saved = mj_saveLastXML(name, m, error, sizeof error);
  std::ifstream in(name);
  std::stringstream text;
  text << in.rdbuf();
  std::remove(name);
  if (!saved) throw InvalidInput(path + ": `with_mujoco`", std::string("MuJoCo cannot save the model: ") + error);
  return text.str();
}

}  // namespace

MjcfModel compileUrdfForMujoco(const std::string& path, const ModelImportOptions& options,
                               std::vector<std::string>* notes) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS || !doc.RootElement())
    throw InvalidInput(path, "cannot read it as XML for MuJoCo");
  tinyxml2::XMLElement* robot = doc.RootElement();
  std::vector<Mimic> mimics;
  for (tinyxml2::XMLElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const tinyxml2::XMLElement* mimic = j->FirstChildElement("mimic");
    // A fixed joint's <mimic> has nothing to couple (the import leaves it
    // out too); MuJoCo fuses the joint's child away.
    if (!mimic || (j->Attribute("type") && std::string(j->Attribute("type")) == "fixed")) continue;
    Mimic c;
    c.follower = j->Attribute("name") ? j->Attribute("name") : "";
    c.leader = mimic->Attribute("joint") ? mimic->Attribute("joint") : "";
    mimic->QueryDoubleAttribute("multiplier", &c.multiplier);
    mimic->QueryDoubleAttribute("offset", &c.offset);
    mimics.push_back(c);
  }
  // The geometry MuJoCo would look for on disk is left out (the visuals
  // all: they never act). Welded links are fused into their parents, as
  // lieflow merges them (a massless welded link, a camera frame, would stop
  // MuJoCo's compiler as a body of its own), so every body lieflow keeps is
  // a MuJoCo body of its link's name.
  for (tinyxml2::XMLElement* link = robot->FirstChildElement("link"); link;
       link = link->NextSiblingElement("link")) {
    while (tinyxml2::XMLElement* v = link->FirstChildElement("visual")) link->DeleteChild(v);
    for (tinyxml2::XMLElement* c = link->FirstChildElement("collision"); c;) {
      tinyxml2::XMLElement* next = c->NextSiblingElement("collision");
      if (isMesh(c)) link->DeleteChild(c);
      c = next;
    }
  }
  while (tinyxml2::XMLElement* own = robot->FirstChildElement("mujoco")) robot->DeleteChild(own);
  tinyxml2::XMLElement* mujoco = doc.NewElement("mujoco");
  tinyxml2::XMLElement* compiler = doc.NewElement("compiler");
  compiler->SetAttribute("fusestatic", "true");
  compiler->SetAttribute("discardvisual", "true");
  // A link without <inertial> has no mass in URDF (urdfdom, lieflow's
  // import); MuJoCo's default would give it the mass of its collision
  // primitives (ANYmal's base: 29 kg that the file does not have).
  compiler->SetAttribute("inertiafromgeom", "false");
  mujoco->InsertEndChild(compiler);
  robot->InsertFirstChild(mujoco);
  if (options.floating_base) {
    // --floating-base: the root link (no joint's child) on a URDF floating
    // joint from a link of no mass, which MuJoCo fuses into its world: a
    // free joint, as the import puts one between the world and the root.
    std::set<std::string> children;
    for (const tinyxml2::XMLElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint"))
      if (const tinyxml2::XMLElement* c = j->FirstChildElement("child"))
        if (c->Attribute("link")) children.insert(c->Attribute("link"));
    const char* root_link = nullptr;
    for (const tinyxml2::XMLElement* l = robot->FirstChildElement("link"); l && !root_link;
         l = l->NextSiblingElement("link"))
      if (l->Attribute("name") && !children.count(l->Attribute("name"))) root_link = l->Attribute("name");
    if (!root_link) throw InvalidInput(path + ": `with_mujoco`", "has no root link to free");
    const std::string world = "lieflow_world_for_" + std::string(root_link);
    tinyxml2::XMLElement* link = doc.NewElement("link");
    link->SetAttribute("name", world.c_str());
    tinyxml2::XMLElement* joint = doc.NewElement("joint");
    joint->SetAttribute("name", ("lieflow_floating_" + std::string(root_link)).c_str());
    joint->SetAttribute("type", "floating");
    tinyxml2::XMLElement* parent = doc.NewElement("parent");
    parent->SetAttribute("link", world.c_str());
    tinyxml2::XMLElement* child = doc.NewElement("child");
    child->SetAttribute("link", root_link);
    joint->InsertEndChild(parent);
    joint->InsertEndChild(child);
    robot->InsertAfterChild(mujoco, link);
    robot->InsertAfterChild(link, joint);
  }
  MjcfModel m;
  try {
    m = compileModelText("lieflow-peer.urdf", printed(doc), path + ": `with_mujoco`");
  } catch (const InvalidInput& e) {
    // MuJoCo checks each link's inertia before it fuses welded links; an
    // unphysical one (A + B < C) it can only balance, which changes it.
    if (e.reason().find("inertia must satisfy A + B >= C") == std::string::npos) throw;
    compiler->SetAttribute("balanceinertia", "true");
    m = compileModelText("lieflow-peer.urdf", printed(doc), path + ": `with_mujoco`");
    notes->push_back("MuJoCo's compiler balanced an inertia of the file that breaks A + B >= C (" + e.reason() +
                     "), so its model differs there");
  }
  if (mimics.empty()) return m;

  tinyxml2::XMLDocument mjcf;
  const std::string saved = savedMjcf(m.get(), path);
  if (mjcf.Parse(saved.c_str()) != tinyxml2::XML_SUCCESS || !mjcf.RootElement())
    throw InvalidInput(path + ": `with_mujoco`", "MuJoCo's saved MJCF of the model does not parse");
  tinyxml2::XMLElement* root = mjcf.RootElement();
  {
    // <mimic> as MuJoCo's joint equality: q1 = c0 + c1 q2 (polycoef); MuJoCo's
    // own URDF reader leaves mimics out.
    tinyxml2::XMLElement* equality = mjcf.NewElement("equality");
    for (const Mimic& c : mimics) {
      tinyxml2::XMLElement* e = mjcf.NewElement("joint");
      e->SetAttribute("joint1", c.follower.c_str());
      e->SetAttribute("joint2", c.leader.c_str());
      e->SetAttribute("polycoef",
                      (formatNumber(c.offset, 17) + " " + formatNumber(c.multiplier, 17) + " 0 0 0").c_str());
      // As stiff as MuJoCo makes a constraint (impedance mjMAXIMP = 0.9999
      // throughout; its default 0.9-0.95 lets a mimic slip 150 times more):
      // a URDF mimic is exact, MuJoCo's equality yields by 1e-4 of its force.
      e->SetAttribute("solimp", "0.9999 0.9999 0.001");
      equality->InsertEndChild(e);
    }
    root->InsertEndChild(equality);
  }
  return compileModelText("lieflow-peer.xml", printed(mjcf), path + ": `with_mujoco`");
}

}  // namespace mujoco_peer
}  // namespace lieflow

#endif
